// The mapping of HSDF_TEST_DEVICE (test_device.h): what a typo or an unset variable does decides
// which device a whole "GPU" test run used, so each case is pinned here.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "engine/gpu/device_names.h"
#include "test_device.h"

namespace {

using engine::gpu::DevicePreference;

TEST(TestDevice, UnsetOrEmptyIsLavapipeAsOnCi) {
  ASSERT_TRUE(hsdftest::parseTestDevice(nullptr).ok());
  EXPECT_EQ(*hsdftest::parseTestDevice(nullptr), DevicePreference::Software);
  ASSERT_TRUE(hsdftest::parseTestDevice("").ok());
  EXPECT_EQ(*hsdftest::parseTestDevice(""), DevicePreference::Software);
}

TEST(TestDevice, EachNamedValue) {
  EXPECT_EQ(*hsdftest::parseTestDevice("lavapipe"), DevicePreference::Software);
  EXPECT_EQ(*hsdftest::parseTestDevice("gpu"), DevicePreference::Hardware);
  EXPECT_EQ(*hsdftest::parseTestDevice("auto"), DevicePreference::Auto);
}

TEST(TestDevice, UnknownValueIsRefusedNamingVariableAndValue) {
  // Near misses a user would type: other spellings, case, a trailing space, the engine's aliases.
  for (const char* bad : {"GPU", "vulkan", "lavapipe ", "hardware", "software", "nvidia", "1"}) {
    const auto parsed = hsdftest::parseTestDevice(bad);
    ASSERT_FALSE(parsed.ok()) << bad;
    EXPECT_EQ(parsed.error().message,
              std::string("HSDF_TEST_DEVICE: '") + bad + "' is not one of auto, gpu, lavapipe (unset means lavapipe)");
  }
}

TEST(TestDevice, EngineNamesRoundTrip) {
  // The launcher exports the engine's deviceName() as HSDF_DEVICE; each must be a value
  // HSDF_TEST_DEVICE maps back to the same preference (and the engine accepts, engine_gpu_fault_tests).
  for (DevicePreference p : {DevicePreference::Software, DevicePreference::Hardware, DevicePreference::Auto}) {
    const std::string name(engine::gpu::deviceName(p));
    const auto back = hsdftest::parseTestDevice(name.c_str());
    ASSERT_TRUE(back.ok()) << name;
    EXPECT_EQ(*back, p) << name;
  }
}

TEST(TestDevice, ReadsTheVariableWhenCalled) {
  // Read at run time, not cached: the ctests set it per test (ENVIRONMENT), one build for all.
  const char* saved = std::getenv("HSDF_TEST_DEVICE");
  const std::string restore = saved ? saved : "";
  setenv("HSDF_TEST_DEVICE", "gpu", 1);
  EXPECT_EQ(*hsdftest::testDevicePreference(), DevicePreference::Hardware);
  EXPECT_EQ(hsdftest::describeTestDevice(), "gpu (HSDF_TEST_DEVICE=gpu)");
  setenv("HSDF_TEST_DEVICE", "bogus", 1);
  EXPECT_FALSE(hsdftest::testDevicePreference().ok());
  unsetenv("HSDF_TEST_DEVICE");
  EXPECT_EQ(*hsdftest::testDevicePreference(), DevicePreference::Software);
  EXPECT_EQ(hsdftest::describeTestDevice(), "lavapipe (HSDF_TEST_DEVICE unset)");
  if (saved) setenv("HSDF_TEST_DEVICE", restore.c_str(), 1);
}

}  // namespace
