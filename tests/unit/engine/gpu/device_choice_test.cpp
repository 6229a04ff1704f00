// How the engine picks its device from DevicePreference and HSDF_DEVICE (engine/gpu/context.cpp):
// HSDF_DEVICE decides only for Auto (the programs' default `--device auto`, which the test launcher
// steers through it), an explicit preference wins over it, and an unknown value is refused. Each
// case holds on any machine: where a choice depends on whether a hardware GPU exists, both
// outcomes are checked for what they must say.
#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>

#include "engine/gpu/context.h"
#include "engine/gpu/device_names.h"
#include "engine/gpu/shader_statistics.h"
#include "test_files.h"
#include "test_device.h"

namespace engine::gpu {
namespace {

using hsdftest::ScopedEnvironment;

class ScopedHsdfDevice : public ScopedEnvironment {
 public:
  explicit ScopedHsdfDevice(const char* value) : ScopedEnvironment("HSDF_DEVICE", value) {}
};

// Tricky: an empty value says nothing (the build's default), and the usual words for off are off
// (HSDF_VALIDATION= and HSDF_VALIDATION=false turned validation on, and a machine without the
// layer then failed to start with no word of the variable).
TEST(DeviceChoice, HsdfValidationReadsOffWordsAndEmptyAsUnset) {
  bool unset = false;
  {
    ScopedEnvironment none("HSDF_VALIDATION", "");
    unset = ContextDesc::defaultValidation();
#ifdef NDEBUG
    EXPECT_FALSE(unset) << "empty is the release build's default, off";
#else
    EXPECT_TRUE(unset) << "empty is the debug build's default, on";
#endif
  }
  for (const char* off : {"0", "false", "off", "no"}) {
    ScopedEnvironment value("HSDF_VALIDATION", off);
    EXPECT_FALSE(ContextDesc::defaultValidation()) << off;
  }
  for (const char* on : {"1", "true", "on", "yes"}) {
    ScopedEnvironment value("HSDF_VALIDATION", on);
    EXPECT_TRUE(ContextDesc::defaultValidation()) << on;
  }
}

Expected<std::unique_ptr<Context>> create(DevicePreference preference) {
  ContextDesc desc;
  desc.device = preference;
  desc.validation = true;
  return Context::create(desc);
}

// The test device as an explicit preference; auto names none.
std::optional<DevicePreference> explicitTestDevice() {
  const auto device = hsdftest::testDevicePreference();
  EXPECT_TRUE(device.ok()) << device.error().message;
  if (!device || *device == DevicePreference::Auto) return std::nullopt;
  return *device;
}

TEST(DeviceChoice, UnknownHsdfDeviceIsRefusedForAuto) {
  // It used to be ignored silently: a typo ran on whatever device came first.
  ScopedHsdfDevice env("vulkan");
  const auto context = create(DevicePreference::Auto);
  ASSERT_FALSE(context.ok());
  EXPECT_NE(context.error().message.find("HSDF_DEVICE: 'vulkan' is not one of auto, gpu, lavapipe"), std::string::npos)
      << context.error().message;
}

TEST(DeviceChoice, ExplicitPreferenceWinsOverHsdfDevice) {
  const auto device = explicitTestDevice();
  if (!device) GTEST_SKIP() << "HSDF_TEST_DEVICE=auto names no explicit device to check";
  const bool software = *device == DevicePreference::Software;
  {
    ScopedHsdfDevice env("vulkan");  // not even read: an unknown value must not matter
    const auto context = create(*device);
    ASSERT_TRUE(context.ok()) << context.error().message;
    EXPECT_EQ((*context)->validationMessageCount(), 0u);
  }
  // The other kind in the environment: the code's explicit choice still decides.
  ScopedHsdfDevice env(software ? "gpu" : "lavapipe");
  const auto context = create(*device);
  ASSERT_TRUE(context.ok()) << context.error().message;
  EXPECT_EQ((*context)->capabilities().isSoftwareRasterizer, software) << (*context)->capabilities().deviceName;
  EXPECT_EQ((*context)->validationMessageCount(), 0u);
}

TEST(DeviceChoice, AutoFollowsHsdfDevice) {
  {
    // HSDF_DEVICE=gpu under Auto: a hardware device, or (no GPU here) the error that lavapipe is
    // not the kind asked for. Without HSDF_DEVICE, Auto would take lavapipe on a machine without one.
    ScopedHsdfDevice env("gpu");
    const auto context = create(DevicePreference::Auto);
    if (context.ok()) {
      EXPECT_FALSE((*context)->capabilities().isSoftwareRasterizer) << (*context)->capabilities().deviceName;
      EXPECT_EQ((*context)->validationMessageCount(), 0u);
    } else {
      EXPECT_NE(context.error().message.find("not the kind asked for (a hardware GPU)"), std::string::npos)
          << context.error().message;
    }
  }
  // What the test launcher exports for the test device picks the same kind of device under Auto.
  const auto device = explicitTestDevice();
  if (!device) GTEST_SKIP() << "HSDF_TEST_DEVICE=auto names no explicit device to check";
  ScopedHsdfDevice env(std::string(deviceName(*device)).c_str());
  const auto context = create(DevicePreference::Auto);
  ASSERT_TRUE(context.ok()) << context.error().message;
  EXPECT_EQ((*context)->capabilities().isSoftwareRasterizer, *device == DevicePreference::Software)
      << (*context)->capabilities().deviceName;
  EXPECT_EQ((*context)->validationMessageCount(), 0u);
}

// Tricky: RADV's null device (what RADV_FORCE_FAMILY makes, for compiler statistics) says it is a
// discrete GPU, so the ranking alone chose it over lavapipe and over an integrated GPU, and the
// first submission crashed. It must be passed over, and named where nothing else is left.
TEST(DeviceChoice, NeverPicksRadvsNullDevice) {
  ScopedEnvironment family("RADV_FORCE_FAMILY", "navi10");
  ScopedHsdfDevice unset("");  // Auto is the engine's own ranking
  for (const DevicePreference preference : {DevicePreference::Auto, DevicePreference::Hardware}) {
    SCOPED_TRACE(std::string(deviceName(preference)));
    const auto context = create(preference);
    if (context.ok()) {
      EXPECT_FALSE(isNullDevice((*context)->capabilities().deviceName)) << (*context)->capabilities().deviceName;
      EXPECT_EQ((*context)->validationMessageCount(), 0u);
    } else {
      EXPECT_EQ(preference, DevicePreference::Hardware) << "Auto has lavapipe left: " << context.error().message;
      EXPECT_NE(context.error().message.find("Null hardware (RADV NAVI10): a null device"), std::string::npos)
          << context.error().message;
    }
  }
}

}  // namespace
}  // namespace engine::gpu
