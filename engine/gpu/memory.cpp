#include "engine/gpu/memory.h"

#include <algorithm>
#include <string>

#include <fmt/format.h>

#include "engine/gpu/vk_check.h"

namespace engine::gpu {
namespace {

VkDeviceSize alignUp(VkDeviceSize value, VkDeviceSize alignment) {
  return (value + alignment - 1) / alignment * alignment;
}

VkMemoryPropertyFlags requiredFlags(MemoryUsage usage) {
  switch (usage) {
    case MemoryUsage::GpuOnly: return VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    case MemoryUsage::Upload: return VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    case MemoryUsage::Readback: return VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  }
  return 0;
}

VkMemoryPropertyFlags preferredFlags(MemoryUsage usage) {
  switch (usage) {
    case MemoryUsage::GpuOnly: return 0;
    case MemoryUsage::Upload: return VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;  // ReBAR when available
    case MemoryUsage::Readback: return VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
  }
  return 0;
}

}  // namespace

Allocator::Allocator(VkPhysicalDevice physicalDevice, VkDevice device, VkDeviceSize blockSize)
    : device_(device), blockSize_(blockSize) {
  vkGetPhysicalDeviceMemoryProperties(physicalDevice, &memoryProperties_);
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(physicalDevice, &properties);
  // Buffers and optimal-tiling images may share a block; aligning every sub-allocation to the
  // granularity keeps them on separate pages without tracking resource kinds.
  granularity_ = std::max<VkDeviceSize>(properties.limits.bufferImageGranularity, 256);
}

Allocator::~Allocator() {
  for (Block& block : blocks_)
    if (block.memory) vkFreeMemory(device_, block.memory, nullptr);
}

std::uint32_t Allocator::findMemoryType(std::uint32_t typeBits, MemoryUsage usage) const {
  const VkMemoryPropertyFlags required = requiredFlags(usage);
  const VkMemoryPropertyFlags preferred = required | preferredFlags(usage);
  for (VkMemoryPropertyFlags wanted : {preferred, required}) {
    for (std::uint32_t i = 0; i < memoryProperties_.memoryTypeCount; ++i) {
      const bool allowed = (typeBits & (1u << i)) != 0;
      if (allowed && (memoryProperties_.memoryTypes[i].propertyFlags & wanted) == wanted) return i;
    }
  }
  throw VulkanError(VK_ERROR_FEATURE_NOT_PRESENT, "no Vulkan memory type fits the requested usage");
}

VkDeviceMemory Allocator::allocateMemory(VkDeviceSize size, std::uint32_t memoryType, void** mapped) const {
  VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
  flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;  // every buffer may be reached by address
  VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  info.pNext = &flags;
  info.allocationSize = size;
  info.memoryTypeIndex = memoryType;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VK_CHECK(vkAllocateMemory(device_, &info, nullptr, &memory));
  *mapped = nullptr;
  if (memoryProperties_.memoryTypes[memoryType].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT)
    VK_CHECK(vkMapMemory(device_, memory, 0, VK_WHOLE_SIZE, 0, mapped));
  return memory;
}

bool Allocator::tryAllocateFromBlock(Block& block, VkDeviceSize size, VkDeviceSize alignment,
                                     VkDeviceSize& offset) {
  for (std::size_t i = 0; i < block.freeRanges.size(); ++i) {
    Range range = block.freeRanges[i];
    const VkDeviceSize start = alignUp(range.offset, alignment);
    const VkDeviceSize end = start + size;
    if (end > range.offset + range.size) continue;
    block.freeRanges.erase(block.freeRanges.begin() + static_cast<std::ptrdiff_t>(i));
    // Give back what is left on either side of the allocation.
    if (start > range.offset) releaseRange(block, {range.offset, start - range.offset});
    if (end < range.offset + range.size) releaseRange(block, {end, range.offset + range.size - end});
    offset = start;
    return true;
  }
  return false;
}

void Allocator::releaseRange(Block& block, Range range) {
  auto& ranges = block.freeRanges;
  auto it = std::lower_bound(ranges.begin(), ranges.end(), range.offset,
                             [](const Range& r, VkDeviceSize offset) { return r.offset < offset; });
  it = ranges.insert(it, range);
  // Coalesce with the next and the previous neighbour.
  if (auto next = it + 1; next != ranges.end() && it->offset + it->size == next->offset) {
    it->size += next->size;
    ranges.erase(next);
  }
  if (it != ranges.begin()) {
    auto prev = it - 1;
    if (prev->offset + prev->size == it->offset) {
      prev->size += it->size;
      ranges.erase(it);
    }
  }
}

MemoryRefusal::MemoryRefusal(const Allocator& allocator, VkDeviceSize needed)
    : used_(allocator.stats().usedBytes), budget_(allocator.budget()), needed_(needed) {}

bool MemoryRefusal::mayRetry(const Allocator& allocator) const {
  const VkDeviceSize used = allocator.stats().usedBytes;
  const VkDeviceSize budget = allocator.budget();
  if (used >= used_ && budget <= budget_) return false;  // nothing given back, no more allowed
  // No budget: lifted since, or the device's memory was short and some was given back (how much
  // the device has free is not known here).
  if (budget == Allocator::kUnlimited) return true;
  return needed_ <= budget && used <= budget - needed_;
}

void Allocator::setBudget(VkDeviceSize bytes) {
  std::lock_guard lock(mutex_);
  budget_ = bytes;
}

VkDeviceSize Allocator::budget() const {
  std::lock_guard lock(mutex_);
  return budget_;
}

Allocation Allocator::allocate(const VkMemoryRequirements& requirements, MemoryUsage usage, std::string_view what) {
  std::lock_guard lock(mutex_);
  const std::uint32_t memoryType = findMemoryType(requirements.memoryTypeBits, usage);
  const VkDeviceSize alignment = std::max(requirements.alignment, granularity_);
  const VkDeviceSize size = alignUp(requirements.size, granularity_);
  if (size > budget_ || stats_.usedBytes > budget_ - size)
    throw VulkanError(VK_ERROR_OUT_OF_DEVICE_MEMORY,
                      fmt::format("GPU memory budget: '{}' needs {} B, {} B are in use, the budget is {} B", what,
                                  size, stats_.usedBytes, budget_));
  Allocation result;
  result.memoryType = memoryType;
  result.size = size;

  if (size > blockSize_ / 2) {  // dedicated: big resources would fragment the shared blocks
    result.memory = allocateMemory(size, memoryType, &result.mapped);
    stats_.reservedBytes += size;
  } else {
    std::uint32_t blockId = 0;
    for (; blockId < blocks_.size(); ++blockId) {
      Block& block = blocks_[blockId];
      if (block.memory && block.memoryType == memoryType &&
          tryAllocateFromBlock(block, size, alignment, result.offset))
        break;
    }
    if (blockId == blocks_.size()) {
      Block block;
      block.memoryType = memoryType;
      block.size = blockSize_;
      block.memory = allocateMemory(blockSize_, memoryType, &block.mapped);
      block.freeRanges.push_back({0, blockSize_});
      blocks_.push_back(std::move(block));
      stats_.blockCount++;
      stats_.reservedBytes += blockSize_;
      tryAllocateFromBlock(blocks_.back(), size, alignment, result.offset);
    }
    Block& block = blocks_[blockId];
    result.memory = block.memory;
    result.blockId = blockId;
    if (block.mapped) result.mapped = static_cast<char*>(block.mapped) + result.offset;
  }
  stats_.usedBytes += size;
  stats_.allocationCount++;
  return result;
}

void Allocator::free(const Allocation& allocation) {
  if (!allocation.memory) return;
  std::lock_guard lock(mutex_);
  stats_.usedBytes -= allocation.size;
  stats_.allocationCount--;
  if (allocation.blockId == ~0u) {
    vkFreeMemory(device_, allocation.memory, nullptr);
    stats_.reservedBytes -= allocation.size;
    return;
  }
  releaseRange(blocks_[allocation.blockId], {allocation.offset, allocation.size});
}

AllocatorStats Allocator::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace engine::gpu
