#pragma once
// Descriptor sets of one combined image sampler each (binding 0), for devices without descriptor
// indexing (lavapipe): a texture's set is bound before the draws that sample it. Used by the mesh
// base colour textures and by any feature that binds one texture per draw. Sets come from pools of
// kSetsPerPool and are freed one by one, so textures may come and go.
#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/core/expected.h"
#include "engine/gpu/descriptor_set_layout.h"

namespace engine::gpu {

class Context;

// A write of one combined image sampler (SHADER_READ_ONLY_OPTIMAL) into `element` of binding 0.
VkWriteDescriptorSet combinedImageSamplerWrite(VkDescriptorSet set, std::uint32_t element,
                                               const VkDescriptorImageInfo& image);

class ImageSamplerSets {
 public:
  struct Set {
    VkDescriptorPool pool = VK_NULL_HANDLE;
    VkDescriptorSet set = VK_NULL_HANDLE;
  };

  // `stages` see binding 0; `name` names the layout, the pools and the sets. Throws VulkanError when
  // the driver refuses the layout (checked-call convention).
  ImageSamplerSets(const Context& context, VkShaderStageFlags stages, std::string name);
  ~ImageSamplerSets();
  ImageSamplerSets(const ImageSamplerSets&) = delete;
  ImageSamplerSets& operator=(const ImageSamplerSets&) = delete;

  VkDescriptorSetLayout layout() const { return layout_.handle(); }

  // A set that samples `view` through `sampler`; an error naming the call when no pool gives one.
  Expected<Set> add(VkImageView view, VkSampler sampler);
  // Frees `set`; no pending frame may still use it.
  void remove(const Set& set);

 private:
  static constexpr std::uint32_t kSetsPerPool = 64;
  VkDescriptorSet tryAllocate(VkDescriptorPool pool) const;
  Expected<VkDescriptorPool> createPool();

  const Context& context_;
  std::string name_;
  DescriptorSetLayout layout_;
  std::vector<VkDescriptorPool> pools_;
};

}  // namespace engine::gpu
