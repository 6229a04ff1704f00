#pragma once
// RAII buffer with a device address. Upload/Readback buffers stay mapped.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/gpu/memory.h"

namespace engine::gpu {

class Context;

class Buffer {
 public:
  Buffer() = default;
  Buffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUsage memory,
         const std::string& name);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  VkDeviceAddress address() const { return address_; }  // 0 unless created with device-address usage
  void* mapped() const { return allocation_.mapped; }
  explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }

  // Copies bytes into a mapped buffer at `offset`.
  void write(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
  template <class T>
  void write(std::span<const T> items, VkDeviceSize offset = 0) {
    write(items.data(), items.size_bytes(), offset);
  }

 private:
  void release();

  const Context* context_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  Allocation allocation_;
  VkDeviceSize size_ = 0;
  VkDeviceAddress address_ = 0;
};

// One synchronization2 global memory barrier: writes of srcStage/srcAccess made available and
// visible to dstStage/dstAccess (buffers by handle or by device address alike).
void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                   VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess);

// A device-local buffer filled through a staging buffer (one-off submit, waits).
Buffer createBufferWithData(const Context& context, const void* data, VkDeviceSize bytes,
                            VkBufferUsageFlags usage, const std::string& name);

// Copies `bytes` from a CPU pointer into an existing device-local buffer at `offset` (waits).
void uploadToBuffer(const Context& context, const Buffer& destination, const void* data, VkDeviceSize bytes,
                    VkDeviceSize offset = 0);

// One buffer's part in appendToBuffers: `bytes` written by `write` after the `used` bytes that
// hold data. `write` fills the whole span it is given, straight into the staging memory: a caller
// that assembles its data from several sources (or changes it on the way) makes no host copy of
// it first. The staging memory may be write-combined: `write` should only write to it.
struct BufferAppend {
  using Writer = std::function<void(std::span<std::byte> out)>;
  Buffer* buffer = nullptr;  // may be empty (then `used` is 0): it is made
  VkDeviceSize used = 0;
  VkDeviceSize bytes = 0;
  Writer write;  // called once with exactly `bytes` bytes when `bytes` is not 0
  VkBufferUsageFlags usage = 0;  // for a buffer made or grown (transfer usage is added)
  std::string name;
  // Bytes after `used` that a buffer made or grown has room for, when more than `bytes`: data
  // written in parts over several appends is then copied into its final buffer once, not at
  // every growth.
  VkDeviceSize reserve = 0;
};

// A writer that copies `data`, which must outlive the append (for BufferAppend::write).
BufferAppend::Writer copyOf(std::span<const std::byte> data);

// Appends to device-local buffers (created with TRANSFER_SRC and TRANSFER_DST usage), one
// submission per buffer through one staging buffer, and waits. The data already there stays where
// it is, so addresses and offsets that commands recorded earlier hold stay valid. A buffer too
// small for used + data (or `reserve`) is replaced by one with room for half as much again (exactly
// that when the room does not fit in memory, or when the buffer was empty; an empty buffer is made
// even for no data when it reserves room), into which the GPU copies its used bytes; the replaced buffers are
// returned, for the caller to release once the commands that read them have completed. Every
// earlier command on the queue completes its reads and writes before the copies, and later ones
// see the data. Throws VulkanError when an allocation fails, leaving every buffer as it was.
std::vector<Buffer> appendToBuffers(const Context& context, std::span<BufferAppend> appends);

// Regions of one device-local buffer copied into another on the GPU (`from` created with
// TRANSFER_SRC usage, `to` with TRANSFER_DST): data that stays on the GPU is not written from the
// CPU again when the buffer holding it is replaced (a buffer rebuilt with part of an older one's
// contents).
struct BufferCopy {
  const Buffer* from = nullptr;
  const Buffer* to = nullptr;
  std::vector<VkBufferCopy> regions;
};

// Records `copies` into `cmd` (a frame's commands, outside a render pass), then one barrier after
// which every later command of `cmd` (any stage) reads what they wrote. Submissions made before
// `cmd` is submitted (appendToBuffers) run before the copies: they must neither read what the
// copies write nor write what they read.
void recordBufferCopies(VkCommandBuffer cmd, std::span<const BufferCopy> copies);

// Copies a device-local buffer (created with TRANSFER_SRC usage) back to the CPU (waits). Waits
// for every earlier write to it on the queue (all stages).
std::vector<std::uint8_t> readbackBuffer(const Context& context, const Buffer& source);

}  // namespace engine::gpu
