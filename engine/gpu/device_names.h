#pragma once
// The names of the device choices, one list for every place that reads or writes one: a program's
// `--device`, the engine's HSDF_DEVICE and the tests' HSDF_TEST_DEVICE.
#include <string_view>

#include "engine/core/expected.h"
#include "engine/gpu/context.h"

namespace engine::gpu {

// The accepted names, as help text and errors list them.
inline constexpr std::string_view kDeviceNameList = "auto, gpu, lavapipe";

// "auto", "gpu" or "lavapipe": the name parseDeviceName reads back as the same preference.
std::string_view deviceName(DevicePreference preference);

// Exactly one of kDeviceNameList (case and spaces count: "GPU" or "gpu " is a typo, and a typo must
// not quietly run on another device). The error names where the text came from and the text:
// "--device: 'nvidia' is not one of auto, gpu, lavapipe".
Expected<DevicePreference> parseDeviceName(std::string_view source, std::string_view text);

}  // namespace engine::gpu
