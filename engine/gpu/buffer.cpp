#include "engine/gpu/buffer.h"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "engine/gpu/context.h"
#include "engine/gpu/vk_check.h"

namespace engine::gpu {

Buffer::Buffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUsage memory,
               const std::string& name)
    : context_(&context), size_(size) {
  if (size == 0) throw std::invalid_argument("Buffer '" + name + "': size 0");
  // Creating it would be invalid usage (VUID-VkBufferCreateInfo-size-06409); callers that size
  // buffers by the scene catch this and draw otherwise.
  if (size > context.capabilities().maxBufferSize)
    throw VulkanError(VK_ERROR_OUT_OF_DEVICE_MEMORY, fmt::format("Buffer '{}' ({} bytes): larger than the device's "
                                                                 "maxBufferSize ({} bytes)",
                                                                 name, size, context.capabilities().maxBufferSize));
  const bool wantsAddress = (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) != 0;
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  // A constructor that throws runs no destructor: every step after the buffer is made gives it
  // back here. A failed vkCreateBuffer leaves buffer_ null; fault injection reports a failure for
  // one the driver did make.
  try {
    try {
      VK_CHECK(vkCreateBuffer(context.device(), &info, nullptr, &buffer_));
    } catch (const VulkanError& error) {  // a size past the device's limits fails here: say which buffer
      throw VulkanError(error.result(), fmt::format("Buffer '{}' ({} bytes): {}", name, size, error.what()));
    }
    context.setName(buffer_, VK_OBJECT_TYPE_BUFFER, name);
    VkMemoryRequirements requirements{};
    vkGetBufferMemoryRequirements(context.device(), buffer_, &requirements);
    allocation_ = context.allocator().allocate(requirements, memory, name);
    VK_CHECK(vkBindBufferMemory(context.device(), buffer_, allocation_.memory, allocation_.offset));
  } catch (...) {
    release();
    throw;
  }

  if (wantsAddress) {
    VkBufferDeviceAddressInfo addressInfo{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
    addressInfo.buffer = buffer_;
    address_ = vkGetBufferDeviceAddress(context.device(), &addressInfo);
  }
}

Buffer::~Buffer() { release(); }

Buffer::Buffer(Buffer&& other) noexcept { *this = std::move(other); }

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    release();
    context_ = std::exchange(other.context_, nullptr);
    buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
    allocation_ = std::exchange(other.allocation_, Allocation{});
    size_ = std::exchange(other.size_, 0);
    address_ = std::exchange(other.address_, 0);
  }
  return *this;
}

void Buffer::release() {
  if (!buffer_) return;
  vkDestroyBuffer(context_->device(), buffer_, nullptr);
  context_->allocator().free(allocation_);
  buffer_ = VK_NULL_HANDLE;
}

void Buffer::write(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
  if (!allocation_.mapped) throw std::logic_error("Buffer::write on a buffer that is not host visible");
  if (offset + bytes > size_) throw std::out_of_range("Buffer::write past the end of the buffer");
  std::memcpy(static_cast<char*>(allocation_.mapped) + offset, data, bytes);
}

void uploadToBuffer(const Context& context, const Buffer& destination, const void* data, VkDeviceSize bytes,
                    VkDeviceSize offset) {
  if (bytes == 0) return;
  Buffer staging(context, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUsage::Upload, "staging");
  staging.write(data, bytes);
  context.submitAndWait([&](VkCommandBuffer cmd) {
    VkBufferCopy region{0, offset, bytes};
    vkCmdCopyBuffer(cmd, staging.handle(), destination.handle(), 1, &region);
  });
}

Buffer createBufferWithData(const Context& context, const void* data, VkDeviceSize bytes,
                            VkBufferUsageFlags usage, const std::string& name) {
  Buffer buffer(context, bytes, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::GpuOnly, name);
  uploadToBuffer(context, buffer, data, bytes);
  return buffer;
}

BufferAppend::Writer copyOf(std::span<const std::byte> data) {
  return [data](std::span<std::byte> out) { std::memcpy(out.data(), data.data(), std::min(data.size(), out.size())); };
}

namespace {

// The buffer that replaces `a.buffer` when it is too small: room for half as much again where
// memory allows it (a stream that keeps growing is copied O(log n) times, not once per append).
std::optional<Buffer> grownBuffer(const Context& context, const BufferAppend& a) {
  const VkDeviceSize needed = a.used + std::max(a.bytes, a.reserve);
  if (needed <= a.buffer->size()) return std::nullopt;
  const VkBufferUsageFlags usage = a.usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  const VkDeviceSize roomy = a.buffer->size() == 0 ? needed : std::max(needed, a.buffer->size() + a.buffer->size() / 2);
  if (roomy > needed) {
    try {
      return std::optional<Buffer>(std::in_place, context, roomy, usage, MemoryUsage::GpuOnly, a.name);
    } catch (const VulkanError& error) {
      if (error.result() != VK_ERROR_OUT_OF_DEVICE_MEMORY) throw;
    }
  }
  return std::optional<Buffer>(std::in_place, context, needed, usage, MemoryUsage::GpuOnly, a.name);
}

}  // namespace

std::vector<Buffer> appendToBuffers(const Context& context, std::span<BufferAppend> appends) {
  for (const BufferAppend& a : appends) {
    if (a.buffer == nullptr || (!*a.buffer && a.used != 0) || a.used > a.buffer->size())
      throw std::invalid_argument("appendToBuffers: '" + a.name + "' holds fewer bytes than it is said to use");
    if (a.bytes != 0 && !a.write) throw std::invalid_argument("appendToBuffers: '" + a.name + "' has bytes and no writer");
  }
  // Every allocation before any copy: one that fails leaves the buffers as they were. One staging
  // buffer, as large as the largest append, serves them in turn: the peak is one buffer's data, not all.
  std::vector<std::optional<Buffer>> grown;
  VkDeviceSize largest = 0;
  for (const BufferAppend& a : appends) {
    grown.push_back(grownBuffer(context, a));
    largest = std::max<VkDeviceSize>(largest, a.bytes);
  }
  // No data: only buffers made with room (reserve) for data that comes otherwise (recordBufferCopies).
  std::optional<Buffer> staging;
  if (largest != 0)
    staging.emplace(context, largest, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUsage::Upload, "append staging");
  for (std::size_t i = 0; i < appends.size(); ++i) {
    const BufferAppend& a = appends[i];
    const bool keeps = grown[i] && a.used > 0;  // a grown buffer gets its used bytes even with no data added
    if (a.bytes == 0 && !keeps) continue;
    if (a.bytes != 0) a.write(std::span(static_cast<std::byte*>(staging->mapped()), a.bytes));
    const Buffer& target = grown[i] ? *grown[i] : *a.buffer;
    context.submitAndWait([&](VkCommandBuffer cmd) {
      // The buffer is read by earlier submissions (frames in flight): their reads come first.
      memoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT);
      if (keeps) {
        const VkBufferCopy kept{0, 0, a.used};
        vkCmdCopyBuffer(cmd, a.buffer->handle(), target.handle(), 1, &kept);
      }
      const VkBufferCopy added{0, a.used, a.bytes};
      if (a.bytes != 0) vkCmdCopyBuffer(cmd, staging->handle(), target.handle(), 1, &added);
      memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
    });
  }
  std::vector<Buffer> replaced;
  for (std::size_t i = 0; i < appends.size(); ++i) {
    if (!grown[i]) continue;
    Buffer old = std::exchange(*appends[i].buffer, std::move(*grown[i]));
    if (old) replaced.push_back(std::move(old));  // an empty one was made, not replaced
  }
  return replaced;
}

void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                   VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess) {
  VkMemoryBarrier2 barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
  barrier.srcStageMask = srcStage;
  barrier.srcAccessMask = srcAccess;
  barrier.dstStageMask = dstStage;
  barrier.dstAccessMask = dstAccess;
  VkDependencyInfo dependency{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dependency.memoryBarrierCount = 1;
  dependency.pMemoryBarriers = &barrier;
  vkCmdPipelineBarrier2(cmd, &dependency);
}

void recordBufferCopies(VkCommandBuffer cmd, std::span<const BufferCopy> copies) {
  bool any = false;
  for (const BufferCopy& c : copies) {
    if (c.regions.empty()) continue;
    vkCmdCopyBuffer(cmd, c.from->handle(), c.to->handle(), static_cast<std::uint32_t>(c.regions.size()),
                    c.regions.data());
    any = true;
  }
  // The commands after them (vertex input, culling passes, shaders reading by address) read the data.
  if (any)
    memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                  VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
}

std::vector<std::uint8_t> readbackBuffer(const Context& context, const Buffer& source) {
  Buffer staging(context, source.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::Readback, "buffer readback");
  context.submitAndWait([&](VkCommandBuffer cmd) {
    memoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                  VK_ACCESS_2_TRANSFER_READ_BIT);
    const VkBufferCopy region{0, 0, source.size()};
    vkCmdCopyBuffer(cmd, source.handle(), staging.handle(), 1, &region);
    memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                  VK_ACCESS_2_HOST_READ_BIT);
  });
  const auto* begin = static_cast<const std::uint8_t*>(staging.mapped());
  return std::vector<std::uint8_t>(begin, begin + source.size());
}

}  // namespace engine::gpu
