#pragma once
// A GPU-only buffer of one uint per pixel of a frame (index y * width + x), optionally followed by
// a few bytes of frame-wide data (e.g. totals), made for the frame's extent on first use and made
// again when the extent changes. The renderer's work counters, the heat-map counters and the
// early-depth hit depths are such buffers: one place sizes, recreates and frees them.
#include <cstdint>
#include <string>

#include <vulkan/vulkan.h>

#include "engine/gpu/buffer.h"
#include "engine/gpu/deferred_release.h"

namespace engine::gpu {

class Context;

class PixelBuffer {
 public:
  PixelBuffer() = default;
  // `usage` is added to storage, transfer-destination (cleared with vkCmdFillBuffer) and
  // device-address usage; `trailingBytes` follow the pixels (at pixelBytes()).
  PixelBuffer(std::string name, VkBufferUsageFlags usage = 0, VkDeviceSize trailingBytes = 0);

  // Makes the buffer fit `extent` (width and height at least 1). Returns true when it was made now:
  // its contents are then undefined, the caller clears them. An old buffer is retired to `retired`
  // with `lastUse` (the frame being prepared: frames in flight and this frame's earlier commands
  // may use it), so it is freed once those frames completed, without waiting for the device. If
  // the allocation fails the helper is left empty (extent 0 x 0) and the error is thrown.
  bool ensure(const Context& context, VkExtent2D extent, DeferredRelease& retired, std::uint64_t lastUse);
  // Frees the buffer (no frame in flight may still use it).
  void reset();

  const Buffer& buffer() const { return buffer_; }
  VkBuffer handle() const { return buffer_.handle(); }
  VkDeviceAddress address() const { return buffer_.address(); }
  VkExtent2D extent() const { return extent_; }
  // Bytes of the per-pixel part, the offset of the trailing bytes.
  VkDeviceSize pixelBytes() const { return pixelBytes(extent_); }
  static VkDeviceSize pixelBytes(VkExtent2D extent) {
    return VkDeviceSize(extent.width) * extent.height * sizeof(std::uint32_t);
  }
  explicit operator bool() const { return static_cast<bool>(buffer_); }

 private:
  std::string name_;
  VkBufferUsageFlags usage_ = 0;
  VkDeviceSize trailingBytes_ = 0;
  Buffer buffer_;
  VkExtent2D extent_{0, 0};
};

}  // namespace engine::gpu
