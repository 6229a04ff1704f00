#pragma once
// A small device-memory allocator: memory comes from large blocks (64 MiB by default) per memory
// type and is sub-allocated with a first-fit free list, so creating a buffer or image does not cost
// one vkAllocateMemory. Requests larger than a block get a dedicated allocation. Host-visible
// blocks stay persistently mapped.
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <string_view>
#include <vector>

#include <vulkan/vulkan.h>

namespace engine::gpu {

enum class MemoryUsage {
  GpuOnly,   // device local
  Upload,    // host visible + coherent, written by the CPU every frame or for staging
  Readback,  // host visible (cached if possible), read by the CPU
};

struct Allocation {
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize offset = 0;
  VkDeviceSize size = 0;
  void* mapped = nullptr;          // non-null for host-visible memory
  std::uint32_t blockId = ~0u;     // ~0u: dedicated allocation
  std::uint32_t memoryType = 0;
  explicit operator bool() const { return memory != VK_NULL_HANDLE; }
};

struct AllocatorStats {
  std::uint64_t blockCount = 0;
  std::uint64_t reservedBytes = 0;   // sum of block sizes + dedicated allocations
  std::uint64_t usedBytes = 0;
  std::uint64_t allocationCount = 0;
};

class Allocator {
 public:
  Allocator(VkPhysicalDevice physicalDevice, VkDevice device, VkDeviceSize blockSize = VkDeviceSize(64) << 20);
  ~Allocator();
  Allocator(const Allocator&) = delete;
  Allocator& operator=(const Allocator&) = delete;

  // Throws VulkanError when the device is out of memory, the request would pass the budget
  // (VK_ERROR_OUT_OF_DEVICE_MEMORY, the message names `what`, its size and the budget) or no
  // memory type fits. `what` names the resource (the buffer's or image's debug name).
  Allocation allocate(const VkMemoryRequirements& requirements, MemoryUsage usage,
                      std::string_view what = "unnamed allocation");
  void free(const Allocation& allocation);
  AllocatorStats stats() const;

  // A cap on the bytes handed out (AllocatorStats::usedBytes), checked before any Vulkan memory is
  // allocated: a limit for an editor that shares the GPU, and the fault-injection hook tests lower
  // until allocations fail. Lowering it below what is in use frees nothing; later requests fail.
  static constexpr VkDeviceSize kUnlimited = std::numeric_limits<VkDeviceSize>::max();
  void setBudget(VkDeviceSize bytes);
  VkDeviceSize budget() const;

 private:
  struct Range {
    VkDeviceSize offset;
    VkDeviceSize size;
  };
  struct Block {
    VkDeviceMemory memory = VK_NULL_HANDLE;
    std::uint32_t memoryType = 0;
    VkDeviceSize size = 0;
    void* mapped = nullptr;
    std::vector<Range> freeRanges;  // sorted by offset, coalesced
  };

  std::uint32_t findMemoryType(std::uint32_t typeBits, MemoryUsage usage) const;
  VkDeviceMemory allocateMemory(VkDeviceSize size, std::uint32_t memoryType, void** mapped) const;
  bool tryAllocateFromBlock(Block& block, VkDeviceSize size, VkDeviceSize alignment, VkDeviceSize& offset);
  static void releaseRange(Block& block, Range range);

  VkDevice device_;
  VkPhysicalDeviceMemoryProperties memoryProperties_{};
  VkDeviceSize blockSize_;
  VkDeviceSize granularity_;
  VkDeviceSize budget_ = kUnlimited;
  mutable std::mutex mutex_;
  std::vector<Block> blocks_;
  AllocatorStats stats_;
};

// An upload refused for GPU memory (the budget or the device), and whether trying it again could
// now succeed: memory was given back since (the bytes in use fell) or the budget was raised, and,
// under a budget, `needed` (what the upload allocates at least) fits below it. Retrying only then
// keeps a refused upload from being tried, and reported, every frame, while an object refused in a
// full scene is drawn once others are destroyed.
class MemoryRefusal {
 public:
  MemoryRefusal(const Allocator& allocator, VkDeviceSize needed);
  bool mayRetry(const Allocator& allocator) const;

 private:
  VkDeviceSize used_ = 0;
  VkDeviceSize budget_ = 0;
  VkDeviceSize needed_ = 0;
};

}  // namespace engine::gpu
