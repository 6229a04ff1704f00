// The table of required device features (engine/gpu/device_features.h) against fake feature sets:
// no device is needed to see which one a device would be refused for.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "engine/gpu/device_features.h"

namespace engine::gpu {
namespace {

// The features the engine's code and shaders use unconditionally, spelled here independently of
// the table (each read from its own struct): gl_DrawID (shaderDrawParameters), indirect draws by
// firstInstance (drawIndirectFirstInstance), atomics and stores in fragment shaders
// (fragmentStoresAndAtomics), besides Vulkan 1.3's and the shared structs' own.
struct Spelled {
  const char* name;
  VkBool32 (*read)(const FeatureChain& chain);
};
const Spelled kExpected[] = {
    {"dynamicRendering", [](const FeatureChain& c) { return c.v13.dynamicRendering; }},
    {"synchronization2", [](const FeatureChain& c) { return c.v13.synchronization2; }},
    {"bufferDeviceAddress", [](const FeatureChain& c) { return c.v12.bufferDeviceAddress; }},
    {"scalarBlockLayout", [](const FeatureChain& c) { return c.v12.scalarBlockLayout; }},
    {"shaderInt64", [](const FeatureChain& c) { return c.core.features.shaderInt64; }},
    {"drawIndirectFirstInstance", [](const FeatureChain& c) { return c.core.features.drawIndirectFirstInstance; }},
    {"fragmentStoresAndAtomics", [](const FeatureChain& c) { return c.core.features.fragmentStoresAndAtomics; }},
    {"shaderDrawParameters", [](const FeatureChain& c) { return c.v11.shaderDrawParameters; }},
};

// Tricky: the check, the enabled list and the message were three copies that disagreed (a device
// without drawIndirectFirstInstance was accepted, the feature left off, and the brick draws were
// invalid). Every feature must be in the table under its own struct member (a row pointing at the
// wrong member would enable one feature and check another), the enabled list must set exactly
// those members, and a device missing any one of them must be refused naming that one alone.
TEST(RequiredFeatures, EachMissingFeatureIsNamedAndEnabled) {
  std::set<std::string> names;
  for (const RequiredFeature& feature : requiredFeatures()) names.insert(feature.name);
  std::set<std::string> expectedNames;
  for (const Spelled& e : kExpected) expectedNames.insert(e.name);
  EXPECT_EQ(names, expectedNames);

  FeatureChain enabled;
  enableRequiredFeatures(enabled);
  for (const Spelled& e : kExpected) EXPECT_TRUE(e.read(enabled)) << e.name << " is not enabled";
  EXPECT_EQ(missingRequiredFeatures(enabled), "") << "a device with every required feature is refused";
  EXPECT_FALSE(enabled.core.features.multiDrawIndirect) << "an optional feature was enabled as required";

  const std::string requirements = describeRequirements();
  for (const RequiredFeature& feature : requiredFeatures()) {
    SCOPED_TRACE(feature.name);
    EXPECT_NE(requirements.find(feature.name), std::string::npos) << requirements;
    FeatureChain supported;
    enableRequiredFeatures(supported);
    feature.member(supported) = VK_FALSE;
    const std::string missing = missingRequiredFeatures(supported);
    EXPECT_EQ(missing.rfind(std::string("no ") + feature.name + " (", 0), 0u) << missing;
    EXPECT_EQ(missing.find(','), std::string::npos) << "only the missing one is named: " << missing;
    for (const Spelled& e : kExpected) {
      if (e.name == std::string(feature.name)) {
        EXPECT_FALSE(e.read(supported)) << "the row points at another member";
      }
    }
  }

  FeatureChain none;
  EXPECT_EQ(missingRequiredFeatures(none).find("no dynamicRendering ("), 0u);
}

}  // namespace
}  // namespace engine::gpu
