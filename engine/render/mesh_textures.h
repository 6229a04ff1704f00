#pragma once
// The base colour textures of meshes (glTF baseColorTexture): sRGB RGBA8 images with their mip
// chains, each with its own sampler and its own descriptor set (mesh.frag's set 0, binding 0). A
// set per texture, not a bindless table: devices without descriptor indexing (lavapipe) draw them
// too, and the mesh feature binds a texture's set once per batch of the meshes that use it.
// Texture 0 is one white texel: a mesh without a texture samples it, and its colour times 1.0 is
// the colour it had before textures were drawn.
#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/gpu/device_handle.h"
#include "engine/gpu/image.h"
#include "engine/gpu/image_sampler_sets.h"
#include "engine/render/components.h"
#include "engine/scene/scene_data.h"

namespace engine::gpu {
class Context;
}

namespace engine::render {

class MeshTextures {
 public:
  explicit MeshTextures(const gpu::Context& context);
  ~MeshTextures() = default;
  MeshTextures(const MeshTextures&) = delete;
  MeshTextures& operator=(const MeshTextures&) = delete;

  // Uploads `texture` with its mip chain (waits for the GPU; textures come at load). Throws
  // VulkanError when the device refuses (checked-call convention).
  TextureHandle add(const scene::TextureData& texture);
  std::uint32_t count() const { return static_cast<std::uint32_t>(entries_.size()); }

  VkDescriptorSetLayout layout() const { return sets_.layout(); }
  // Binds `texture`'s set as set 0 of `layout` (the white texel for an unknown handle).
  void bind(VkCommandBuffer cmd, VkPipelineLayout layout, TextureHandle texture) const;

 private:
  struct Entry {
    gpu::Image image;
    gpu::SamplerHandle sampler;
    VkDescriptorSet set = VK_NULL_HANDLE;  // lives as long as the texture: freed with the sets' pools
  };

  const gpu::Context& context_;
  gpu::ImageSamplerSets sets_;
  std::vector<Entry> entries_;
};

}  // namespace engine::render
