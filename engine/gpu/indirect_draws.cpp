#include "engine/gpu/indirect_draws.h"

#include "engine/gpu/context.h"

namespace engine::gpu {

IndirectDraws::IndirectDraws(const Context& context) : multiDraw_(context.capabilities().multiDrawIndirect) {
  if (!context.capabilities().drawIndirectCount) return;
  drawAll_ = Buffer(context, sizeof(std::uint32_t), VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT, MemoryUsage::Upload,
                    "draw-all indirect count");
  const std::uint32_t all = ~0u;
  drawAll_.write(&all, sizeof(all));
}

void IndirectDraws::draw(VkCommandBuffer cmd, VkBuffer commands, std::uint32_t first, std::uint32_t count,
                         VkBuffer countBuffer, VkDeviceSize countOffset, const BeforeSingle& beforeSingle) const {
  record(cmd, false, commands, first, count, countBuffer, countOffset, beforeSingle);
}

void IndirectDraws::drawIndexed(VkCommandBuffer cmd, VkBuffer commands, std::uint32_t first, std::uint32_t count,
                                VkBuffer countBuffer, VkDeviceSize countOffset, const BeforeSingle& beforeSingle) const {
  record(cmd, true, commands, first, count, countBuffer, countOffset, beforeSingle);
}

void IndirectDraws::record(VkCommandBuffer cmd, bool indexed, VkBuffer commands, std::uint32_t first,
                           std::uint32_t count, VkBuffer countBuffer, VkDeviceSize countOffset,
                           const BeforeSingle& beforeSingle) const {
  if (count == 0) return;
  if (countBuffer == VK_NULL_HANDLE && drawAll_) {
    countBuffer = drawAll_.handle();
    countOffset = 0;
  }
  const auto stride = static_cast<std::uint32_t>(indexed ? sizeof(VkDrawIndexedIndirectCommand)
                                                         : sizeof(VkDrawIndirectCommand));
  const auto one = [&](std::uint32_t at, std::uint32_t n) {
    const VkDeviceSize offset = VkDeviceSize(at) * stride;
    if (countBuffer != VK_NULL_HANDLE && indexed)
      vkCmdDrawIndexedIndirectCount(cmd, commands, offset, countBuffer, countOffset, n, stride);
    else if (countBuffer != VK_NULL_HANDLE)
      vkCmdDrawIndirectCount(cmd, commands, offset, countBuffer, countOffset, n, stride);
    else if (indexed)
      vkCmdDrawIndexedIndirect(cmd, commands, offset, n, stride);
    else
      vkCmdDrawIndirect(cmd, commands, offset, n, stride);
  };
  if (multiDraw_) {
    one(first, count);
    return;
  }
  for (std::uint32_t i = first; i < first + count; ++i) {
    if (beforeSingle) beforeSingle(i);
    one(i, 1);
  }
}

}  // namespace engine::gpu
