#include "engine/render/mesh_textures.h"

#include <array>
#include <string>

#include "engine/gpu/context.h"
#include "engine/gpu/vk_check.h"
#include "shared/host_device.h"

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

// The image of each binding of a material's set, in the order of the MESH_TEXTURE_* bindings.
std::array<MeshImageHandle, MESH_TEXTURE_COUNT> bindingOrder(const MaterialImages& images) {
  std::array<MeshImageHandle, MESH_TEXTURE_COUNT> order{};
  for (const MaterialTextureKind& kind : kMaterialTextureKinds) order[kind.binding] = images.*kind.image;
  return order;
}

}  // namespace

MeshTextures::MeshTextures(const gpu::Context& context)
    : context_(context), setAllocator_(context, VK_SHADER_STAGE_FRAGMENT_BIT, MESH_TEXTURE_COUNT, "mesh material textures") {
  addImage(whiteTexel(), TexelEncoding::Srgb);  // 1.0 in either encoding
  addMaterial({});
}

MeshImageHandle MeshTextures::addImage(const scene::TextureData& texture, TexelEncoding encoding) {
  const std::string name = "mesh texture '" + texture.name + "'";
  Entry entry;
  gpu::ImageDesc desc;
  desc.format = encoding == TexelEncoding::Srgb ? VK_FORMAT_R8G8B8A8_SRGB : VK_FORMAT_R8G8B8A8_UNORM;
  desc.extent = {texture.width, texture.height, 1};
  desc.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  desc.mipLevels = texture.mipmaps ? gpu::fullMipChain(texture.width, texture.height) : 1;
  desc.name = name;
  entry.image = gpu::Image(context_, desc);
  gpu::uploadImage(context_, entry.image, texture.rgba.data(), texture.rgba.size());
  entry.sampler = createSampler(context_, texture, name);
  images_.push_back(std::move(entry));
  return MeshImageHandle{static_cast<std::uint32_t>(images_.size() - 1)};
}

TextureHandle MeshTextures::addMaterial(const MaterialImages& images) {
  std::array<VkDescriptorImageInfo, MESH_TEXTURE_COUNT> infos{};
  const auto order = bindingOrder(images);
  for (std::size_t b = 0; b < infos.size(); ++b) {
    const Entry& entry = images_[order[b].index < images_.size() ? order[b].index : 0];
    infos[b] = {entry.sampler.get(), entry.image.view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  }
  const auto set = setAllocator_.add(infos);
  // The message names the refused call and its result; the code is Vulkan's own for a set not given.
  if (!set) throw gpu::VulkanError(VK_ERROR_OUT_OF_POOL_MEMORY, set.error().message);
  sets_.push_back(set->set);
  return TextureHandle{static_cast<std::uint32_t>(sets_.size() - 1)};
}

void MeshTextures::bind(VkCommandBuffer cmd, VkPipelineLayout layout, TextureHandle textures) const {
  const VkDescriptorSet set = sets_[textures.index < sets_.size() ? textures.index : 0];
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0, 1, &set, 0, nullptr);
}

}  // namespace engine::render
