#include "render/cell_history.h"

#include <algorithm>

#include "engine/gpu/context.h"
#include "engine/gpu/vk_check.h"

namespace hsdf {

std::vector<std::uint32_t> CellHistory::place(const engine::gpu::Context& context, VkCommandBuffer cmd,
                                              const std::vector<Object>& objects, std::uint32_t region,
                                              std::uint32_t regions, std::uint64_t frameNumber,
                                              engine::gpu::DeferredRelease& retired) {
  std::vector<std::uint32_t> bases;
  if (regions != regions_.size() || !placeAll(regions_[region], objects, bases)) {
    grow(context, cmd, objects, regions, frameNumber, retired);
    bases.clear();
    placeAll(regions_[region], objects, bases);
  }
  for (std::uint32_t& base : bases) base += region * capacity_;
  return bases;
}

// Keeps the bases of objects that draw the same asset as before, appends the others; false when
// they do not fit.
bool CellHistory::placeAll(Region& region, const std::vector<Object>& objects, std::vector<std::uint32_t>& bases) {
  for (const Object& object : objects) {
    auto found = region.slots.find(object.entity);
    if (found != region.slots.end() && found->second.asset == object.asset && found->second.cells == object.cells) {
      bases.push_back(found->second.base);
      continue;
    }
    if (std::uint64_t(region.used) + object.cells > capacity_) return false;
    region.slots[object.entity] = {object.asset, region.used, object.cells};
    bases.push_back(region.used);
    region.used += object.cells;
  }
  return true;
}

void CellHistory::release(std::uint64_t frameNumber, engine::gpu::DeferredRelease& retired) {
  regions_.clear();
  capacity_ = 0;
  if (buffer_) retired.retire(std::move(buffer_), frameNumber);
  buffer_ = engine::gpu::Buffer{};
}

// A zeroed buffer with room for twice this frame's cells (objects that come and go need not
// reallocate it each time), the old one retired; the places are forgotten.
void CellHistory::grow(const engine::gpu::Context& context, VkCommandBuffer cmd, const std::vector<Object>& objects,
                       std::uint32_t regions, std::uint64_t frameNumber, engine::gpu::DeferredRelease& retired) {
  std::uint64_t cells = 0;
  for (const Object& object : objects) cells += object.cells;
  // Twice the cells, but within a 32-bit index; at least the cells themselves.
  const std::uint64_t capacity = std::max<std::uint64_t>(std::min<std::uint64_t>(2 * cells, 0xffffffffu), 64);
  if (cells > capacity)
    throw engine::gpu::VulkanError(VK_ERROR_OUT_OF_DEVICE_MEMORY,
                                   "hermite cell visibility history: more cells than a 32-bit index reaches");
  // The new buffer first: if it cannot be had, the history stays as it was (the caller draws
  // without occlusion culling).
  engine::gpu::Buffer buffer(context, VkDeviceSize(capacity) * regions * sizeof(std::uint32_t),
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT |
                                 VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                             engine::gpu::MemoryUsage::GpuOnly, "hermite cell visibility history");
  regions_.assign(regions, Region{});
  capacity_ = std::uint32_t(capacity);
  if (buffer_) retired.retire(std::move(buffer_), frameNumber);
  buffer_ = std::move(buffer);
  vkCmdFillBuffer(cmd, buffer_.handle(), 0, VK_WHOLE_SIZE, 0);
  engine::gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                             VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                             VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

}  // namespace hsdf
