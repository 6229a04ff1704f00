#pragma once
// A host-visible buffer per frame in flight, rewritten by the CPU every frame and grown on demand.
// Growing happens while the frame's previous submission is known to be complete (after its fence),
// so the old buffer can be destroyed at once.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/gpu/buffer.h"

namespace engine::render {

class PerFrameBuffer {
 public:
  PerFrameBuffer() = default;
  PerFrameBuffer(const gpu::Context& context, std::uint32_t framesInFlight, VkBufferUsageFlags usage,
                 std::string name);

  // Copies `bytes` into the buffer of frame slot `frame`, growing it if needed.
  void upload(std::uint32_t frame, const void* data, VkDeviceSize bytes);
  template <class T>
  void upload(std::uint32_t frame, const std::vector<T>& items) {
    upload(frame, items.data(), items.size() * sizeof(T));
  }
  const gpu::Buffer& buffer(std::uint32_t frame) const { return buffers_[frame]; }
  VkDeviceAddress address(std::uint32_t frame) const { return buffers_[frame].address(); }

 private:
  const gpu::Context* context_ = nullptr;
  VkBufferUsageFlags usage_ = 0;
  std::string name_;
  std::vector<gpu::Buffer> buffers_;
};

}  // namespace engine::render
