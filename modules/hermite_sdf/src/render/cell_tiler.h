#pragma once
// Tiled cells (HermiteCellFeature::Settings::tiles): cell_tiles.comp bins the cells that
// the cell culling pass kept into screen tiles, and the prepass draws one quad per non-empty tile
// (cell_tiles.vert) whose fragments search the tile's cells (cell_tiles_depth.glsl). On lavapipe,
// which shades and counts whole 4x4 blocks, a box of a few pixels costs 16-64 fragment invocations;
// a tile costs its 64 pixels once, whatever the number of cells behind them.
//
// Per frame slot: the tiles (CellTile per tile, the non-empty tile list, the pixel masks), the entry list and
// the totals (the tile draw's indirect command, host-visible: the entries the scan needed are read
// back to size the next frame's list). record() in prepare(), after the cell culling pass.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/core/expected.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/deferred_release.h"
#include "engine/gpu/gpu_timer.h"
#include "engine/gpu/pipeline.h"
#include "engine/render/per_frame_buffer.h"
#include "hermite/hermite_host_device.h"

namespace hsdf {

// Whether the tiles are drawn as points (one vertex; large points up to CELL_TILE_SIZE_MAX pixels,
// so that every tile size can be drawn by the same pipelines), else as two triangles
// (cell_tiles_vert.glsl).
bool tilesAsPoints(const engine::gpu::Context& context);

// The tiles per row and column of a frame (its edge tiles cut by the frame count whole).
inline VkExtent2D tileGrid(VkExtent2D extent, std::uint32_t tileSize) {
  return {(extent.width + tileSize - 1) / tileSize, (extent.height + tileSize - 1) / tileSize};
}

class CellTiler {
 public:
  static engine::Expected<CellTiler> create(const engine::gpu::Context& context, std::uint32_t frameSlots);

  // One record precision's culled ranges, as the cell culling pass wrote them.
  struct Ranges {
    VkDeviceAddress ranges = 0;       // CellCullRange[count]
    VkDeviceAddress keptIndices = 0;  // their kept cells' record indices
    VkDeviceAddress keptRanges = 0;   // their kept cells' range indices
    VkDeviceAddress keptCount = 0;    // uint: the culling pass's append cursor
    std::uint32_t count = 0;
    std::uint32_t slots = 0;          // the kept streams' capacity
  };
  struct Frame {
    std::uint32_t slot = 0;
    VkExtent2D extent{};
    std::uint32_t tileSize = CELL_TILE_SIZE;  // the tiles' side in pixels (Settings::tileSize)
    VkDeviceAddress draws = 0;         // the draw table (HermiteDrawTableHeader)
    VkDeviceAddress objects = 0;       // BrickCullObject[] of the cell culling pass
    VkDeviceAddress frameGlobals = 0;  // FrameGlobals
    Ranges precisions[2];
    // The entries this frame may need (an estimate from the cells and their size on screen); the
    // list grows to it, and to what an earlier frame of this slot needed, up to entryLimit.
    std::uint64_t entryEstimate = 0;
    std::uint32_t entryLimit = 4096;  // HermiteCellFeature::Settings::maxTileEntries
  };
  // Records COUNT, SCAN, SCATTER, SORT and MASKS with their barriers; after it the tiles, entries and the tile
  // draw's command are visible to the draw. Each phase is a scope of `timer` where it is not null
  // ("cells tiling count", ... "cells tiling masks").
  void record(VkCommandBuffer cmd, const Frame& frame, engine::gpu::GpuTimer* timer);
  // Makes the slot's buffers ready for such a frame (record makes them otherwise) before its
  // commands are written: false, with the reason, when GPU memory or the budget refuses them (the
  // slot keeps its old buffers, and the frame draws its cells as boxes instead).
  bool reserve(std::uint32_t slot, VkExtent2D extent, std::uint32_t tileSize, std::uint64_t entryEstimate,
               std::uint32_t entryLimit, std::string& refusal);

  // Releases the slot's tiles and lists after `frames` of its frames in a row that drew no tiles
  // (`tiling` false) or whose lists held more than 2^16 entries and four times what they wanted
  // (wantedEntries); the next tiled frame makes them at its size. Before reserve, every frame.
  // What goes is retired to `retired` with `lastUse`, the last frame that may have used the slot.
  void releaseUnneeded(std::uint32_t slot, bool tiling, std::uint64_t entryEstimate, std::uint32_t frames,
                       engine::gpu::DeferredRelease& retired, std::uint64_t lastUse);
  // Retires the slot's tiles and lists, last used by frame `lastUse`.
  void release(std::uint32_t slot, engine::gpu::DeferredRelease& retired, std::uint64_t lastUse);
  // The bytes every slot's tiles and lists hold.
  std::uint64_t bytesHeld() const;

  VkDeviceAddress tiles(std::uint32_t slot) const { return slots_[slot].tiles.address(); }
  VkDeviceAddress entries(std::uint32_t slot) const { return slots_[slot].sortedEntries.address(); }
  const engine::gpu::Buffer& drawCommand(std::uint32_t slot) const { return totals_.buffer(slot); }
  // The count of the boxes' fallback draws (vkCmdDrawIndirectCount): in drawCommand(slot) at this
  // offset, ~0u where this frame's lists overflowed, else 0.
  static constexpr VkDeviceSize kBoxDrawCountOffset = offsetof(shader::CellTileTotals, boxDrawCount);
  // What the slot's last completed scan wrote (the draw, the entries it needed).
  shader::CellTileTotals lastTotals(std::uint32_t slot) const;
  // The entries the slot's lists held when that scan was recorded.
  std::uint32_t lastCapacity(std::uint32_t slot) const { return slots_[slot].recordedCapacity; }

 private:
  struct Slot {
    engine::gpu::Buffer tiles;
    engine::gpu::Buffer entries;        // the scatter's lists
    engine::gpu::Buffer sortedEntries;  // the same, sorted (the draw's)
    std::uint32_t capacity = 0;
    bool recorded = false;
    std::uint64_t recordedEstimate = 0;  // the entry estimate of the slot's last recorded frame
    std::uint32_t recordedCapacity = 0;  // the lists' capacity then
    bool boundSized = false;             // its lists were made by the estimate, before any measure
    engine::gpu::IdleFrames idle;  // releaseUnneeded's frames in a row
  };
  // Whether the slot has tiled a frame whose need (CellTileTotals::entriesNeeded) can be read.
  static bool measured(const Slot& slot) { return slot.recorded && slot.recordedEstimate != 0; }
  void ensureBuffers(Slot& slot, std::uint32_t tileCount, std::uint32_t tileSize, std::uint64_t wanted,
                     std::uint32_t limit);
  std::uint64_t wantedEntries(std::uint32_t slot, std::uint64_t entryEstimate) const;
  void dispatchBins(VkCommandBuffer cmd, shader::CellTilePushConstants push, const Frame& frame, std::uint32_t phase);
  std::uint32_t startFrame(Slot& slot, const Frame& frame, VkExtent2D grid);
  shader::CellTilePushConstants pushConstants(const Slot& slot, const Frame& frame, VkExtent2D grid) const;

  const engine::gpu::Context* context_ = nullptr;
  engine::gpu::Pipeline pipeline_;
  std::vector<Slot> slots_;
  engine::render::PerFrameBuffer totals_;
};

}  // namespace hsdf
