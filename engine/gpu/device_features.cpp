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

bool hasDescriptorIndexing(FeatureChain& supported) {
  return supported.v12.descriptorIndexing && supported.v12.runtimeDescriptorArray &&
         supported.v12.shaderSampledImageArrayNonUniformIndexing && supported.v12.descriptorBindingPartiallyBound &&
         supported.v12.descriptorBindingSampledImageUpdateAfterBind;
}

void enableOptionalFeatures(FeatureChain& enabled, FeatureChain& supported) {
  enabled.core.features.multiDrawIndirect = supported.core.features.multiDrawIndirect;
  enabled.core.features.fillModeNonSolid = supported.core.features.fillModeNonSolid;
  enabled.core.features.largePoints = supported.core.features.largePoints;
  enabled.core.features.pipelineStatisticsQuery = supported.core.features.pipelineStatisticsQuery;
  enabled.core.features.depthClamp = supported.core.features.depthClamp;
  enabled.core.features.samplerAnisotropy = supported.core.features.samplerAnisotropy;
  enabled.v11.storageBuffer16BitAccess = supported.v11.storageBuffer16BitAccess;
  enabled.v12.shaderFloat16 = supported.v12.shaderFloat16;
  enabled.v12.drawIndirectCount = supported.v12.drawIndirectCount;
  enabled.v12.hostQueryReset = supported.v12.hostQueryReset;
  if (hasDescriptorIndexing(supported)) {
    enabled.v12.descriptorIndexing = VK_TRUE;
    enabled.v12.runtimeDescriptorArray = VK_TRUE;
    enabled.v12.shaderSampledImageArrayNonUniformIndexing = VK_TRUE;
    enabled.v12.descriptorBindingPartiallyBound = VK_TRUE;
    enabled.v12.descriptorBindingSampledImageUpdateAfterBind = VK_TRUE;
  }
  enabled.v13.maintenance4 = supported.v13.maintenance4;
}

std::string describeRequirements() {
  std::string text = "Vulkan 1.3 with";
  for (const RequiredFeature& feature : kRequired) text += (&feature == kRequired ? " " : ", ") + std::string(feature.name);
  return text;
}

}  // namespace engine::gpu
