#include "engine/gpu/image_sampler_sets.h"

#include <utility>
#include <vector>

#include <fmt/format.h>

#include "engine/gpu/context.h"
#include "engine/gpu/vk_check.h"

namespace engine::gpu {

VkWriteDescriptorSet combinedImageSamplerWrite(VkDescriptorSet set, std::uint32_t binding, std::uint32_t element,
                                               const VkDescriptorImageInfo& image) {
  VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  write.dstSet = set;
  write.dstBinding = binding;
  write.dstArrayElement = element;
  write.descriptorCount = 1;
  write.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  write.pImageInfo = &image;
  return write;
}

namespace {

// Bindings 0 .. count - 1, one combined image sampler each.
std::vector<VkDescriptorSetLayoutBinding> imageSamplerBindings(std::uint32_t count, VkShaderStageFlags stages) {
  std::vector<VkDescriptorSetLayoutBinding> bindings;
  for (std::uint32_t b = 0; b < count; ++b)
    bindings.push_back({b, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, stages, nullptr});
  return bindings;
}

}  // namespace

ImageSamplerSets::ImageSamplerSets(const Context& context, VkShaderStageFlags stages, std::uint32_t bindings,
                                   std::string name)
    : context_(context),
      name_(std::move(name)),
      bindings_(bindings),
      layout_(context, {name_ + " layout", imageSamplerBindings(bindings, stages), {}}) {}

ImageSamplerSets::~ImageSamplerSets() {
  for (VkDescriptorPool pool : pools_) vkDestroyDescriptorPool(context_.device(), pool, nullptr);
}

Expected<ImageSamplerSets::Set> ImageSamplerSets::add(std::span<const VkDescriptorImageInfo> images) {
  if (images.size() != bindings_)
    return makeError(fmt::format("{} images given for the {} bindings of a {} set", images.size(), bindings_, name_));
  Set out;
  for (VkDescriptorPool pool : pools_) {
    if ((out.set = tryAllocate(pool)) != VK_NULL_HANDLE) {
      out.pool = pool;
      break;
    }
  }
  if (out.set == VK_NULL_HANDLE) {
    ENGINE_TRY_ASSIGN(out.pool, createPool());
    out.set = tryAllocate(out.pool);
    if (out.set == VK_NULL_HANDLE) return makeError("cannot allocate a " + name_ + " descriptor set from a new pool");
  }
  std::vector<VkWriteDescriptorSet> writes;
  for (std::uint32_t b = 0; b < bindings_; ++b) writes.push_back(combinedImageSamplerWrite(out.set, b, 0, images[b]));
  vkUpdateDescriptorSets(context_.device(), bindings_, writes.data(), 0, nullptr);
  return out;
}

void ImageSamplerSets::remove(const Set& set) {
  VK_CHECK(vkFreeDescriptorSets(context_.device(), set.pool, 1, &set.set));
}

// A full (or fragmented) pool answers with an error code: then the next pool is tried.
VkDescriptorSet ImageSamplerSets::tryAllocate(VkDescriptorPool pool) const {
  VkDescriptorSetAllocateInfo allocInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  allocInfo.descriptorPool = pool;
  allocInfo.descriptorSetCount = 1;
  const VkDescriptorSetLayout setLayout = layout_.handle();
  allocInfo.pSetLayouts = &setLayout;
  VkDescriptorSet set = VK_NULL_HANDLE;
  if (vkAllocateDescriptorSets(context_.device(), &allocInfo, &set) != VK_SUCCESS) return VK_NULL_HANDLE;
  context_.setName(set, VK_OBJECT_TYPE_DESCRIPTOR_SET, name_);
  return set;
}

Expected<VkDescriptorPool> ImageSamplerSets::createPool() {
  const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, kSetsPerPool * bindings_};
  VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  poolInfo.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  poolInfo.maxSets = kSetsPerPool;
  poolInfo.poolSizeCount = 1;
  poolInfo.pPoolSizes = &size;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VK_TRY(vkCreateDescriptorPool(context_.device(), &poolInfo, nullptr, &pool));
  context_.setName(pool, VK_OBJECT_TYPE_DESCRIPTOR_POOL, name_ + " pool " + std::to_string(pools_.size()));
  pools_.push_back(pool);
  return pool;
}

}  // namespace engine::gpu
