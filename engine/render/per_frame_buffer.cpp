#include "engine/render/per_frame_buffer.h"

#include <algorithm>

namespace engine::render {

PerFrameBuffer::PerFrameBuffer(const gpu::Context& context, std::uint32_t framesInFlight,
                               VkBufferUsageFlags usage, std::string name)
    : context_(&context),
      usage_(usage | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT),
      name_(std::move(name)),
      buffers_(framesInFlight) {}

void PerFrameBuffer::upload(std::uint32_t frame, const void* data, VkDeviceSize bytes) {
  gpu::Buffer& buffer = buffers_[frame];
  if (!buffer || buffer.size() < bytes) {
    const VkDeviceSize capacity = std::max<VkDeviceSize>({bytes + bytes / 2, 4096, buffer ? buffer.size() * 2 : 0});
    buffer = gpu::Buffer(*context_, capacity, usage_, gpu::MemoryUsage::Upload,
                         name_ + " [frame " + std::to_string(frame) + "]");
  }
  if (bytes > 0) buffer.write(data, bytes);
}

}  // namespace engine::render
