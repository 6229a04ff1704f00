#pragma once
// RAII 2D/3D image with one view, plus the layout transitions and copies the engine needs.
#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/gpu/device_handle.h"
#include "engine/gpu/memory.h"

namespace engine::gpu {

class Context;

struct ImageDesc {
  VkImageType type = VK_IMAGE_TYPE_2D;
  VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
  VkExtent3D extent{1, 1, 1};
  VkImageUsageFlags usage = VK_IMAGE_USAGE_SAMPLED_BIT;
  std::string name = "image";
  std::uint32_t mipLevels = 1;  // the view sees them all
};

// The levels of a full mip chain down to 1x1 for a 2D image of this size.
std::uint32_t fullMipChain(std::uint32_t width, std::uint32_t height);

// A sampler of one level, clamped to the edge on every axis, with `filter` both ways: images read
// at texel centres or filtered between them, never wrapped around or mipmapped. Named `name`.
SamplerHandle createClampedSampler(const Context& context, VkFilter filter, const std::string& name);

class Image {
 public:
  Image() = default;
  Image(const Context& context, const ImageDesc& desc);
  ~Image();
  Image(Image&& other) noexcept;
  Image& operator=(Image&& other) noexcept;
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;

  VkImage handle() const { return image_; }
  VkImageView view() const { return view_; }
  VkFormat format() const { return format_; }
  VkExtent3D extent() const { return extent_; }
  VkImageAspectFlags aspect() const { return aspect_; }
  std::uint32_t mipLevels() const { return mipLevels_; }
  explicit operator bool() const { return image_ != VK_NULL_HANDLE; }

 private:
  void release();

  const Context* context_ = nullptr;
  VkImage image_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  Allocation allocation_;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkExtent3D extent_{};
  VkImageAspectFlags aspect_ = VK_IMAGE_ASPECT_COLOR_BIT;
  std::uint32_t mipLevels_ = 1;
};

bool isDepthFormat(VkFormat format);
std::uint32_t bytesPerPixel(VkFormat format);  // for the formats the engine reads back / uploads

// One synchronization2 image barrier (whole image, all mips/layers).
void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout oldLayout,
                  VkImageLayout newLayout, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                  VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess);

// Fills level 0 of an image (2D or 3D) from tightly packed texels and leaves every level in
// SHADER_READ_ONLY_OPTIMAL (waits). An image of several mip levels gets each further level from the
// one before by a linear blit (for an sRGB format the blit averages in linear colour); it needs
// TRANSFER_SRC usage and a format the device blits with linear filtering. Every image needs
// TRANSFER_DST usage.
void uploadImage(const Context& context, const Image& image, const void* texels, std::size_t bytes);

// Copies an image in `currentLayout` back to the CPU as tightly packed texels (waits); the image is
// returned to `currentLayout`.
std::vector<std::uint8_t> readbackImage(const Context& context, const Image& image, VkImageLayout currentLayout);

}  // namespace engine::gpu
