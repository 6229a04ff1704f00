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
    : context_(context),
      layout_(context, {"mesh base colour texture layout",
                        {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}},
                        {}}) {
  add(whiteTexel());
}

MeshTextures::~MeshTextures() { destroyPools(); }

void MeshTextures::destroyPools() noexcept {
  for (Entry& entry : entries_) vkDestroyDescriptorPool(context_.device(), entry.pool, nullptr);
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
  gpu::uploadImageWithMipmaps(context_, entry.image, texture.rgba.data(), texture.rgba.size());
  entry.sampler = createSampler(context_, texture, name);

  const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1};
  VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  poolInfo.maxSets = 1;
  poolInfo.poolSizeCount = 1;
  poolInfo.pPoolSizes = &size;
  VK_CHECK(vkCreateDescriptorPool(context_.device(), &poolInfo, nullptr, &entry.pool));
  entries_.push_back(std::move(entry));  // owned from here: the destructor frees its pool
  Entry& owned = entries_.back();
  VkDescriptorSetAllocateInfo allocInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  allocInfo.descriptorPool = owned.pool;
  allocInfo.descriptorSetCount = 1;
  const VkDescriptorSetLayout setLayout = layout_.handle();
  allocInfo.pSetLayouts = &setLayout;
  VK_CHECK(vkAllocateDescriptorSets(context_.device(), &allocInfo, &owned.set));
  context_.setName(owned.set, VK_OBJECT_TYPE_DESCRIPTOR_SET, name);
  const VkDescriptorImageInfo image{owned.sampler.get(), owned.image.view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  write.dstSet = owned.set;
  write.dstBinding = 0;
  write.descriptorCount = 1;
  write.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  write.pImageInfo = &image;
  vkUpdateDescriptorSets(context_.device(), 1, &write, 0, nullptr);
  return TextureHandle{static_cast<std::uint32_t>(entries_.size() - 1)};
}

void MeshTextures::bind(VkCommandBuffer cmd, VkPipelineLayout layout, TextureHandle texture) const {
  const Entry& entry = entries_[texture.index < entries_.size() ? texture.index : 0];
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0, 1, &entry.set, 0, nullptr);
}

}  // namespace engine::render
