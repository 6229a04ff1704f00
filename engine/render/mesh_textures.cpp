#include "engine/render/mesh_textures.h"

#include <string>

#include "engine/gpu/context.h"
#include "engine/gpu/vk_check.h"

namespace engine::render {
namespace {

VkFilter filterOf(scene::TextureFilter filter) {
  return filter == scene::TextureFilter::Nearest ? VK_FILTER_NEAREST : VK_FILTER_LINEAR;
}

VkSamplerAddressMode addressOf(scene::TextureWrap wrap) {
  switch (wrap) {
    case scene::TextureWrap::ClampToEdge: return VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    case scene::TextureWrap::MirroredRepeat: return VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT;
    case scene::TextureWrap::Repeat: break;
  }
  return VK_SAMPLER_ADDRESS_MODE_REPEAT;
}

// The glTF sampler: without mipmaps (minFilter NEAREST / LINEAR) only level 0 is read.
gpu::SamplerHandle createSampler(const gpu::Context& context, const scene::TextureData& texture, const std::string& name) {
  VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  info.magFilter = filterOf(texture.magFilter);
  info.minFilter = filterOf(texture.minFilter);
  info.mipmapMode = texture.mipmapFilter == scene::TextureFilter::Nearest ? VK_SAMPLER_MIPMAP_MODE_NEAREST
                                                                           : VK_SAMPLER_MIPMAP_MODE_LINEAR;
  info.addressModeU = addressOf(texture.wrapS);
  info.addressModeV = addressOf(texture.wrapT);
  info.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
  info.maxLod = texture.mipmaps ? VK_LOD_CLAMP_NONE : 0.0f;
  gpu::SamplerHandle sampler;
  VK_CHECK(vkCreateSampler(context.device(), &info, nullptr, sampler.receive(context.device())));
  context.setName(sampler.get(), VK_OBJECT_TYPE_SAMPLER, name);
  return sampler;
}

scene::TextureData whiteTexel() {
  scene::TextureData white;
  white.name = "white";
  white.width = white.height = 1;
  white.rgba = {255, 255, 255, 255};
  return white;
}

}  // namespace

MeshTextures::MeshTextures(const gpu::Context& context)
    : context_(context), sets_(context, VK_SHADER_STAGE_FRAGMENT_BIT, "mesh base colour texture") {
  add(whiteTexel());
}

TextureHandle MeshTextures::add(const scene::TextureData& texture) {
  const std::string name = "mesh texture '" + texture.name + "'";
  Entry entry;
  gpu::ImageDesc desc;
  desc.format = VK_FORMAT_R8G8B8A8_SRGB;
  desc.extent = {texture.width, texture.height, 1};
  desc.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  desc.mipLevels = texture.mipmaps ? gpu::fullMipChain(texture.width, texture.height) : 1;
  desc.name = name;
  entry.image = gpu::Image(context_, desc);
  gpu::uploadImage(context_, entry.image, texture.rgba.data(), texture.rgba.size());
  entry.sampler = createSampler(context_, texture, name);
  const auto set = sets_.add(entry.image.view(), entry.sampler.get());
  // The message names the refused call and its result; the code is Vulkan's own for a set not given.
  if (!set) throw gpu::VulkanError(VK_ERROR_OUT_OF_POOL_MEMORY, set.error().message);
  entry.set = set->set;
  entries_.push_back(std::move(entry));
  return TextureHandle{static_cast<std::uint32_t>(entries_.size() - 1)};
}

void MeshTextures::bind(VkCommandBuffer cmd, VkPipelineLayout layout, TextureHandle texture) const {
  const Entry& entry = entries_[texture.index < entries_.size() ? texture.index : 0];
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0, 1, &entry.set, 0, nullptr);
}

}  // namespace engine::render
