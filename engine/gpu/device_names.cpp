#include "engine/gpu/device_names.h"

#include <array>
#include <string>

namespace engine::gpu {

namespace {
constexpr std::array kPreferences = {DevicePreference::Auto, DevicePreference::Hardware, DevicePreference::Software};
}  // namespace

std::string_view deviceName(DevicePreference preference) {
  switch (preference) {
    case DevicePreference::Hardware: return "gpu";
    case DevicePreference::Software: return "lavapipe";
    case DevicePreference::Auto: break;
  }
  return "auto";
}

Expected<DevicePreference> parseDeviceName(std::string_view source, std::string_view text) {
  for (const DevicePreference preference : kPreferences)
    if (text == deviceName(preference)) return preference;
  return makeError(std::string(source) + ": '" + std::string(text) + "' is not one of " + std::string(kDeviceNameList));
}

}  // namespace engine::gpu
