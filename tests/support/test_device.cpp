#include "test_device.h"

#include <cstdlib>

#include "engine/gpu/device_names.h"

namespace hsdftest {

using engine::gpu::DevicePreference;

engine::Expected<DevicePreference> parseTestDevice(const char* value) {
  if (!value || !*value) return DevicePreference::Software;
  auto parsed = engine::gpu::parseDeviceName(kTestDeviceVariable, value);
  if (!parsed) return engine::makeError(parsed.error().message + " (unset means lavapipe)");
  return parsed;
}

engine::Expected<DevicePreference> testDevicePreference() { return parseTestDevice(std::getenv(kTestDeviceVariable)); }

std::string describeTestDevice() {
  const char* value = std::getenv(kTestDeviceVariable);
  const auto preference = parseTestDevice(value);
  const std::string how = value && *value ? std::string(kTestDeviceVariable) + "=" + value
                                          : std::string(kTestDeviceVariable) + " unset";
  if (!preference) return "no device (" + how + " is refused)";
  return std::string(engine::gpu::deviceName(*preference)) + " (" + how + ")";
}

}  // namespace hsdftest
