#pragma once
// Which Vulkan device the tests run on: HSDF_TEST_DEVICE=gpu|lavapipe|auto, unset or empty meaning
// lavapipe (what CI has). The one mapping every GPU test uses: the in-process test contexts
// (gtest fixtures, the soak) call testDevicePreference(), and the ctests that run programs
// (scene_runner, perf_capture, the Xvfb scripts, the cmake -P scripts, the consumer project) go
// through hsdf_test_device_run, which maps the same variable onto the programs' HSDF_DEVICE with
// this code. An unknown value is an error naming the variable and the value, never a silent
// fallback: a typo must not quietly run the "GPU" suite on lavapipe. `auto` is the engine's own
// choice (DevicePreference::Auto: discrete GPU first, lavapipe last; the launcher exports
// HSDF_DEVICE=auto, and an in-process context honours an HSDF_DEVICE the caller set).
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "engine/core/expected.h"
#include "engine/gpu/context.h"

namespace hsdftest {

inline constexpr const char* kTestDeviceVariable = "HSDF_TEST_DEVICE";

// Maps one value of HSDF_TEST_DEVICE with the engine's device names (engine/gpu/device_names.h,
// whose deviceName() the launcher exports as HSDF_DEVICE); nullptr or "" (unset) is lavapipe.
engine::Expected<engine::gpu::DevicePreference> parseTestDevice(const char* value);

// parseTestDevice(getenv("HSDF_TEST_DEVICE")).
engine::Expected<engine::gpu::DevicePreference> testDevicePreference();

// "lavapipe (HSDF_TEST_DEVICE unset)", "gpu (HSDF_TEST_DEVICE=gpu)": for messages that say where a
// failing test ran and how that was chosen.
std::string describeTestDevice();

// Destroys `context` and returns the validation messages it reported over its whole life, those
// reported while it is destroyed included: the layer names every object never destroyed at
// vkDestroyDevice, after the last moment the context itself can be asked.
inline std::uint64_t messagesThroughDestruction(std::unique_ptr<engine::gpu::Context>& context) {
  const std::uint64_t others =
      engine::gpu::Context::processValidationMessageCount() - context->validationMessageCount();
  context.reset();
  return engine::gpu::Context::processValidationMessageCount() - others;
}

}  // namespace hsdftest
