#include "engine/gpu/pixel_buffer.h"

#include <stdexcept>
#include <utility>


namespace engine::gpu {

PixelBuffer::PixelBuffer(std::string name, VkBufferUsageFlags usage, VkDeviceSize trailingBytes)
    : name_(std::move(name)),
      usage_(usage | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
             VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT),
      trailingBytes_(trailingBytes) {}

bool PixelBuffer::ensure(const Context& context, VkExtent2D extent, DeferredRelease& retired, std::uint64_t lastUse) {
  if (extent.width == 0 || extent.height == 0) {
    throw std::invalid_argument("PixelBuffer '" + name_ + "': extent " + std::to_string(extent.width) + "x" +
                                std::to_string(extent.height));
  }
  if (buffer_ && extent_.width == extent.width && extent_.height == extent.height) return false;
  if (buffer_) retired.retire(std::move(buffer_), lastUse);
  reset();
  buffer_ = Buffer(context, pixelBytes(extent) + trailingBytes_, usage_, MemoryUsage::GpuOnly, name_);
  extent_ = extent;
  return true;
}

void PixelBuffer::reset() {
  buffer_ = Buffer();
  extent_ = {0, 0};
}

}  // namespace engine::gpu
