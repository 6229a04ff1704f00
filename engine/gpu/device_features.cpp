#include "engine/gpu/device_features.h"

namespace engine::gpu {
namespace {

// A member of the chain, as a plain function pointer for the constant table.
#define HSDF_FEATURE(path) [](FeatureChain& chain) -> VkBool32& { return chain.path; }

constexpr RequiredFeature kRequired[] = {
    {"dynamicRendering", "every pass renders without render pass objects", HSDF_FEATURE(v13.dynamicRendering)},
    {"synchronization2", "every barrier and submission", HSDF_FEATURE(v13.synchronization2)},
    {"bufferDeviceAddress", "shaders reach their buffers by address", HSDF_FEATURE(v12.bufferDeviceAddress)},
    {"scalarBlockLayout", "the structs shared with shaders use the scalar layout",
     HSDF_FEATURE(v12.scalarBlockLayout)},
    {"shaderInt64", "buffer addresses in push constants", HSDF_FEATURE(core.features.shaderInt64)},
    {"drawIndirectFirstInstance", "indirect draws pick their instances by firstInstance",
     HSDF_FEATURE(core.features.drawIndirectFirstInstance)},
    {"fragmentStoresAndAtomics", "fragment shaders count work and keep nearest depths by atomics",
     HSDF_FEATURE(core.features.fragmentStoresAndAtomics)},
    {"shaderDrawParameters", "vertex shaders read gl_DrawID", HSDF_FEATURE(v11.shaderDrawParameters)},
};

#undef HSDF_FEATURE

}  // namespace

std::span<const RequiredFeature> requiredFeatures() { return kRequired; }

std::string missingRequiredFeatures(FeatureChain& supported) {
  std::string missing;
  for (const RequiredFeature& feature : kRequired)
    if (!feature.member(supported))
      missing += (missing.empty() ? "no " : ", ") + std::string(feature.name) + " (" + feature.usedBy + ")";
  return missing;
}

void enableRequiredFeatures(FeatureChain& enabled) {
  for (const RequiredFeature& feature : kRequired) feature.member(enabled) = VK_TRUE;
}

std::string describeRequirements() {
  std::string text = "Vulkan 1.3 with";
  for (const RequiredFeature& feature : kRequired) text += (&feature == kRequired ? " " : ", ") + std::string(feature.name);
  return text;
}

}  // namespace engine::gpu
