#include "test_device.h"

#include <cstdlib>

namespace hsdftest {

using engine::gpu::DevicePreference;

engine::Expected<DevicePreference> parseTestDevice(const char* value) {
  const std::string_view v = value ? value : "";
  if (v.empty() || v == "lavapipe") return DevicePreference::Software;
  if (v == "gpu") return DevicePreference::Hardware;
  if (v == "auto") return DevicePreference::Auto;
  return engine::makeError(std::string(kTestDeviceVariable) + "='" + std::string(v) +
                           "' is not one of gpu, lavapipe, auto (unset means lavapipe)");
}

engine::Expected<DevicePreference> testDevicePreference() { return parseTestDevice(std::getenv(kTestDeviceVariable)); }

std::string_view engineDeviceName(DevicePreference preference) {
  switch (preference) {
    case DevicePreference::Hardware: return "gpu";
    case DevicePreference::Software: return "lavapipe";
    case DevicePreference::Auto: break;
  }
  return "auto";
}

std::string describeTestDevice() {
  const char* value = std::getenv(kTestDeviceVariable);
  const auto preference = parseTestDevice(value);
  const std::string how = value && *value ? std::string(kTestDeviceVariable) + "=" + value
                                          : std::string(kTestDeviceVariable) + " unset";
  if (!preference) return "no device (" + how + " is refused)";
  return std::string(engineDeviceName(*preference)) + " (" + how + ")";
}

}  // namespace hsdftest
