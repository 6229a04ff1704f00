#include "engine/gpu/image.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "engine/gpu/buffer.h"
#include "engine/gpu/context.h"
#include "engine/gpu/vk_check.h"

namespace engine::gpu {

SamplerHandle createClampedSampler(const Context& context, VkFilter filter, const std::string& name) {
  VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  info.magFilter = filter;
  info.minFilter = filter;
  info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  info.addressModeU = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  info.addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  info.maxLod = 0.0f;
  SamplerHandle sampler;
  VK_CHECK(vkCreateSampler(context.device(), &info, nullptr, sampler.receive(context.device())));
  context.setName(sampler.get(), VK_OBJECT_TYPE_SAMPLER, name);
  return sampler;
}

std::uint32_t fullMipChain(std::uint32_t width, std::uint32_t height) {
  std::uint32_t levels = 1;
  for (std::uint32_t side = std::max(width, height); side > 1; side /= 2) ++levels;
  return levels;
}

bool isDepthFormat(VkFormat format) {
  return format == VK_FORMAT_D32_SFLOAT || format == VK_FORMAT_D24_UNORM_S8_UINT ||
         format == VK_FORMAT_D16_UNORM || format == VK_FORMAT_D32_SFLOAT_S8_UINT;
}

std::uint32_t bytesPerPixel(VkFormat format) {
  switch (format) {
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_SRGB:
    case VK_FORMAT_B8G8R8A8_UNORM:
    case VK_FORMAT_B8G8R8A8_SRGB:
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_D32_SFLOAT:
    case VK_FORMAT_R32_UINT: return 4;
    case VK_FORMAT_R16_SFLOAT: return 2;
    case VK_FORMAT_R16G16B16A16_SFLOAT:
    case VK_FORMAT_R32G32_UINT: return 8;
    case VK_FORMAT_R32G32B32A32_SFLOAT: return 16;
    default: throw std::invalid_argument("bytesPerPixel: unsupported format " + std::to_string(int(format)));
  }
}

Image::Image(const Context& context, const ImageDesc& desc)
    : context_(&context), format_(desc.format), extent_(desc.extent), mipLevels_(desc.mipLevels) {
  aspect_ = isDepthFormat(desc.format) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = desc.type;
  info.format = desc.format;
  info.extent = desc.extent;
  info.mipLevels = desc.mipLevels;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = desc.usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  // A constructor that throws runs no destructor: every step after the image is made gives it
  // back here (its memory and view too). A failed vkCreateImage leaves image_ null; fault
  // injection reports a failure for one the driver did make.
  try {
    VK_CHECK(vkCreateImage(context.device(), &info, nullptr, &image_));
    context.setName(image_, VK_OBJECT_TYPE_IMAGE, desc.name);
    VkMemoryRequirements requirements{};
    vkGetImageMemoryRequirements(context.device(), image_, &requirements);
    allocation_ = context.allocator().allocate(requirements, MemoryUsage::GpuOnly, desc.name);
    VK_CHECK(vkBindImageMemory(context.device(), image_, allocation_.memory, allocation_.offset));

    VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    viewInfo.image = image_;
    viewInfo.viewType = desc.type == VK_IMAGE_TYPE_3D ? VK_IMAGE_VIEW_TYPE_3D : VK_IMAGE_VIEW_TYPE_2D;
    viewInfo.format = desc.format;
    viewInfo.subresourceRange = {aspect_, 0, desc.mipLevels, 0, 1};
    VK_CHECK(vkCreateImageView(context.device(), &viewInfo, nullptr, &view_));
    context.setName(view_, VK_OBJECT_TYPE_IMAGE_VIEW, desc.name + " view");
  } catch (...) {
    release();
    throw;
  }
}

Image::~Image() { release(); }

Image::Image(Image&& other) noexcept { *this = std::move(other); }

Image& Image::operator=(Image&& other) noexcept {
  if (this != &other) {
    release();
    context_ = std::exchange(other.context_, nullptr);
    image_ = std::exchange(other.image_, VK_NULL_HANDLE);
    view_ = std::exchange(other.view_, VK_NULL_HANDLE);
    allocation_ = std::exchange(other.allocation_, Allocation{});
    format_ = other.format_;
    extent_ = other.extent_;
    aspect_ = other.aspect_;
    mipLevels_ = other.mipLevels_;
  }
  return *this;
}

void Image::release() {
  if (!image_) return;
  vkDestroyImageView(context_->device(), view_, nullptr);
  vkDestroyImage(context_->device(), image_, nullptr);
  context_->allocator().free(allocation_);
  image_ = VK_NULL_HANDLE;
  view_ = VK_NULL_HANDLE;
}

namespace {

// One synchronization2 barrier on `range` of an image.
void rangeBarrier(VkCommandBuffer cmd, VkImage image, const VkImageSubresourceRange& range, VkImageLayout oldLayout,
                  VkImageLayout newLayout, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                  VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess) {
  VkImageMemoryBarrier2 barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
  barrier.srcStageMask = srcStage;
  barrier.srcAccessMask = srcAccess;
  barrier.dstStageMask = dstStage;
  barrier.dstAccessMask = dstAccess;
  barrier.oldLayout = oldLayout;
  barrier.newLayout = newLayout;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image;
  barrier.subresourceRange = range;
  VkDependencyInfo dependency{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dependency.imageMemoryBarrierCount = 1;
  dependency.pImageMemoryBarriers = &barrier;
  vkCmdPipelineBarrier2(cmd, &dependency);
}

}  // namespace

void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout oldLayout,
                  VkImageLayout newLayout, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                  VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess) {
  rangeBarrier(cmd, image, {aspect, 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS}, oldLayout, newLayout,
               srcStage, srcAccess, dstStage, dstAccess);
}

namespace {

std::size_t imageBytes(const Image& image) {
  const VkExtent3D e = image.extent();
  return std::size_t(e.width) * e.height * e.depth * bytesPerPixel(image.format());
}

VkBufferImageCopy wholeImageCopy(const Image& image) {
  VkBufferImageCopy region{};
  region.imageSubresource = {image.aspect(), 0, 0, 1};
  region.imageExtent = image.extent();
  return region;
}

}  // namespace

namespace {

// A barrier on one mip level of a colour image.
void levelBarrier(VkCommandBuffer cmd, const Image& image, std::uint32_t level, VkImageLayout oldLayout,
                  VkImageLayout newLayout, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                  VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess) {
  rangeBarrier(cmd, image.handle(), {image.aspect(), level, 1, 0, 1}, oldLayout, newLayout, srcStage, srcAccess,
               dstStage, dstAccess);
}

std::int32_t levelSide(std::uint32_t side, std::uint32_t level) { return std::int32_t(std::max(1u, side >> level)); }

// Level `level` blitted from level - 1 (TRANSFER_SRC) into `level` (TRANSFER_DST).
void blitLevel(VkCommandBuffer cmd, const Image& image, std::uint32_t level) {
  const VkExtent3D e = image.extent();
  VkImageBlit blit{};
  blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, level - 1, 0, 1};
  blit.srcOffsets[1] = {levelSide(e.width, level - 1), levelSide(e.height, level - 1), levelSide(e.depth, level - 1)};
  blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, level, 0, 1};
  blit.dstOffsets[1] = {levelSide(e.width, level), levelSide(e.height, level), levelSide(e.depth, level)};
  vkCmdBlitImage(cmd, image.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, image.handle(),
                 VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_LINEAR);
}

}  // namespace

void uploadImage(const Context& context, const Image& image, const void* texels, std::size_t bytes) {
  if (bytes != imageBytes(image)) throw std::invalid_argument("uploadImage: size does not match the image");
  Buffer staging(context, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUsage::Upload, "image staging");
  staging.write(texels, bytes);
  const std::uint32_t levels = image.mipLevels();
  context.submitAndWait([&](VkCommandBuffer cmd) {
    imageBarrier(cmd, image.handle(), image.aspect(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                 VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                 VK_ACCESS_2_TRANSFER_WRITE_BIT);
    const VkBufferImageCopy region = wholeImageCopy(image);
    vkCmdCopyBufferToImage(cmd, staging.handle(), image.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    // Each level is written, then read by the next level's blit, then read by shaders.
    for (std::uint32_t level = 1; level < levels; ++level) {
      levelBarrier(cmd, image, level - 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                   VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                   VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
      blitLevel(cmd, image, level);
      levelBarrier(cmd, image, level - 1, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                   VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                   VK_ACCESS_2_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_2_ALL_GRAPHICS_BIT,
                   VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    }
    levelBarrier(cmd, image, levels - 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                 VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                 VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_GRAPHICS_BIT,
                 VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
  });
}

std::vector<std::uint8_t> readbackImage(const Context& context, const Image& image, VkImageLayout currentLayout) {
  const std::size_t bytes = imageBytes(image);
  Buffer staging(context, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::Readback, "readback");
  context.submitAndWait([&](VkCommandBuffer cmd) {
    imageBarrier(cmd, image.handle(), image.aspect(), currentLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                 VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    const VkBufferImageCopy region = wholeImageCopy(image);
    vkCmdCopyImageToBuffer(cmd, image.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.handle(), 1,
                           &region);
    imageBarrier(cmd, image.handle(), image.aspect(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, currentLayout,
                 VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                 VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
    VkBufferMemoryBarrier2 hostBarrier{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
    hostBarrier.srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
    hostBarrier.srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
    hostBarrier.dstStageMask = VK_PIPELINE_STAGE_2_HOST_BIT;
    hostBarrier.dstAccessMask = VK_ACCESS_2_HOST_READ_BIT;
    hostBarrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    hostBarrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    hostBarrier.buffer = staging.handle();
    hostBarrier.size = VK_WHOLE_SIZE;
    VkDependencyInfo dependency{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dependency.bufferMemoryBarrierCount = 1;
    dependency.pBufferMemoryBarriers = &hostBarrier;
    vkCmdPipelineBarrier2(cmd, &dependency);
  });
  const auto* begin = static_cast<const std::uint8_t*>(staging.mapped());
  return std::vector<std::uint8_t>(begin, begin + bytes);
}

}  // namespace engine::gpu
