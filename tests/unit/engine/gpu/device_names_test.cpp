// The one list of device names (engine/gpu/device_names.h) that --device, HSDF_DEVICE and
// HSDF_TEST_DEVICE all read: what a typo does decides which device a whole run uses.
#include <gtest/gtest.h>

#include <string>

#include "engine/gpu/device_names.h"

namespace engine::gpu {
namespace {

// Tricky: the names a launcher writes (deviceName) must be exactly the names a program reads back
// (the test launcher exports deviceName() as HSDF_DEVICE for every program it starts).
TEST(DeviceNames, EachNameReadsBackAsItsPreference) {
  for (DevicePreference p : {DevicePreference::Auto, DevicePreference::Hardware, DevicePreference::Software}) {
    const auto back = parseDeviceName("--device", deviceName(p));
    ASSERT_TRUE(back.ok()) << deviceName(p) << ": " << back.error().message;
    EXPECT_EQ(*back, p) << deviceName(p);
  }
  EXPECT_EQ(deviceName(DevicePreference::Software), "lavapipe");
  EXPECT_EQ(deviceName(DevicePreference::Hardware), "gpu");
}

// Tricky: near misses a user types (case, a stray space, the old aliases "cpu" and "software" that
// HSDF_DEVICE alone used to take, an empty value) are refused, naming the source and the text, so
// that a typo never quietly runs on another device.
TEST(DeviceNames, NearMissesAreRefusedNamingSourceAndText) {
  for (const char* bad : {"GPU", "Lavapipe", "gpu ", " auto", "cpu", "software", "hardware", "vulkan", "", "1"}) {
    const auto parsed = parseDeviceName("HSDF_DEVICE", bad);
    ASSERT_FALSE(parsed.ok()) << "'" << bad << "' was accepted";
    EXPECT_EQ(parsed.error().message, std::string("HSDF_DEVICE: '") + bad + "' is not one of auto, gpu, lavapipe");
  }
}

}  // namespace
}  // namespace engine::gpu
