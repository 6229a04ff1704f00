#pragma once
// The Vulkan device features the engine uses unconditionally, in one table: the device check, the
// list enabled at device creation and the refusal's message are all made from it, so they cannot
// disagree. Optional features (engine::gpu::DeviceCapabilities) are not in it.
#include <span>
#include <string>

#include <vulkan/vulkan.h>

namespace engine::gpu {

// The chain of feature structs the engine queries and enables (core, 1.1, 1.2, 1.3).
struct FeatureChain {
  VkPhysicalDeviceFeatures2 core{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  VkPhysicalDeviceVulkan11Features v11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES};
  VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceVulkan13Features v13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  FeatureChain() {
    core.pNext = &v11;
    v11.pNext = &v12;
    v12.pNext = &v13;
  }
  // The structs point at each other: a copy would point into the original.
  FeatureChain(const FeatureChain&) = delete;
  FeatureChain& operator=(const FeatureChain&) = delete;
};

struct RequiredFeature {
  const char* name;     // the member's name in its Vulkan struct, as the refusal says it
  const char* usedBy;   // why the engine cannot run without it
  // The member in a chain: read in the queried one, set in the one given to vkCreateDevice.
  VkBool32& (*member)(FeatureChain& chain);
};

std::span<const RequiredFeature> requiredFeatures();

// The required features `supported` lacks, each with what needs it ("no shaderInt64 (...),
// fragmentStoresAndAtomics (...)"), or empty when it has them all.
std::string missingRequiredFeatures(FeatureChain& supported);

// Sets every required feature in `enabled`.
void enableRequiredFeatures(FeatureChain& enabled);

// Whether `supported` has everything the descriptor-indexed ("bindless") sphere tracer needs.
bool hasDescriptorIndexing(FeatureChain& supported);

// Sets in `enabled` the optional features the engine uses where `supported` has them (multi-draw,
// fp16, 16-bit storage, descriptor indexing, ...): every device the engine creates, the one it
// renders on and a device that only compiles its pipelines, gets the same list.
void enableOptionalFeatures(FeatureChain& enabled, FeatureChain& supported);

// "Vulkan 1.3 with dynamicRendering, synchronization2, ...": what the engine needs, for messages.
std::string describeRequirements();

}  // namespace engine::gpu
