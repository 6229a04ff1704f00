#pragma once
// Descriptor sets of `bindings` combined image samplers each (bindings 0 .. bindings - 1, one image
// each), for devices without descriptor indexing (lavapipe): a set is bound before the draws that
// sample it. Used by the mesh material textures (a set per material, a binding per texture kind)
// and by any feature that binds its textures per draw. Sets come from pools of kSetsPerPool and are
// freed one by one, so textures may come and go.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/core/expected.h"
#include "engine/gpu/descriptor_set_layout.h"

namespace engine::gpu {

class Context;

// A write of one combined image sampler (SHADER_READ_ONLY_OPTIMAL) into `element` of `binding`.
VkWriteDescriptorSet combinedImageSamplerWrite(VkDescriptorSet set, std::uint32_t binding, std::uint32_t element,
                                               const VkDescriptorImageInfo& image);

class ImageSamplerSets {
 public:
  struct Set {
    VkDescriptorPool pool = VK_NULL_HANDLE;
    VkDescriptorSet set = VK_NULL_HANDLE;
  };

  // `stages` see the `bindings` bindings; `name` names the layout, the pools and the sets. Throws
  // VulkanError when the driver refuses the layout (checked-call convention).
  ImageSamplerSets(const Context& context, VkShaderStageFlags stages, std::uint32_t bindings, std::string name);
  ~ImageSamplerSets();
  ImageSamplerSets(const ImageSamplerSets&) = delete;
  ImageSamplerSets& operator=(const ImageSamplerSets&) = delete;

  VkDescriptorSetLayout layout() const { return layout_.handle(); }

  // A set whose binding i samples images[i] (one per binding, SHADER_READ_ONLY_OPTIMAL); an error
  // naming the call when no pool gives one.
  Expected<Set> add(std::span<const VkDescriptorImageInfo> images);
  // Frees `set`; no pending frame may still use it.
  void remove(const Set& set);

 private:
  static constexpr std::uint32_t kSetsPerPool = 64;
  VkDescriptorSet tryAllocate(VkDescriptorPool pool) const;
  Expected<VkDescriptorPool> createPool();

  const Context& context_;
  std::string name_;
  std::uint32_t bindings_;
  DescriptorSetLayout layout_;
  std::vector<VkDescriptorPool> pools_;
};

}  // namespace engine::gpu
