#pragma once
// Indirect draws for every feature: one place for the two device differences they meet.
//  - Without multiDrawIndirect a multi-draw is recorded as single draws; gl_DrawID is then 0 in
//    each, so the caller may push what tells them apart before each one (`beforeSingle`).
//  - Where the device has drawIndirectCount, every indirect draw goes through the count form, a
//    draw with no GPU-written count through a one-word count buffer of ~0u (draw them all).
//    Lavapipe (Mesa 22.3, Debian 12) keeps the count buffer of a vkCmdDrawIndirectCount for every
//    later vkCmdDrawIndirect / vkCmdDrawIndexedIndirect of the command buffer: after the tiled
//    cells' fallback draws (count 0) the meshes drawn later vanished (the scene runner's ground;
//    TiledCellsTest.MeshesDrawnAfterTheTilesStayDrawn). A plain indirect draw is therefore never
//    recorded on such a device, by any feature that draws through this.
#include <cstdint>
#include <functional>

#include <vulkan/vulkan.h>

#include "engine/gpu/buffer.h"

namespace engine::gpu {

class Context;

class IndirectDraws {
 public:
  IndirectDraws() = default;
  explicit IndirectDraws(const Context& context);

  // Called with a command's index before it is drawn on its own (devices without multiDrawIndirect).
  using BeforeSingle = std::function<void(std::uint32_t command)>;

  // `count` VkDrawIndirectCommands of `commands` from command `first`; where `countBuffer` is given
  // (its word at `countOffset`, written on the GPU), at most as many as that word says. Drawn one
  // by one (no multiDrawIndirect), each command is drawn where the word is not 0: a word that
  // means all or none is what both paths agree on.
  void draw(VkCommandBuffer cmd, VkBuffer commands, std::uint32_t first, std::uint32_t count,
            VkBuffer countBuffer = VK_NULL_HANDLE, VkDeviceSize countOffset = 0,
            const BeforeSingle& beforeSingle = {}) const;
  // The same with VkDrawIndexedIndirectCommands.
  void drawIndexed(VkCommandBuffer cmd, VkBuffer commands, std::uint32_t first, std::uint32_t count,
                   VkBuffer countBuffer = VK_NULL_HANDLE, VkDeviceSize countOffset = 0,
                   const BeforeSingle& beforeSingle = {}) const;

  bool multiDraw() const { return multiDraw_; }

 private:
  void record(VkCommandBuffer cmd, bool indexed, VkBuffer commands, std::uint32_t first, std::uint32_t count,
              VkBuffer countBuffer, VkDeviceSize countOffset, const BeforeSingle& beforeSingle) const;

  bool multiDraw_ = false;
  Buffer drawAll_;  // one word, ~0u; only where the device has drawIndirectCount
};

}  // namespace engine::gpu
