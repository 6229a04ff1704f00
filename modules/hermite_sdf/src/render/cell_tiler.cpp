#include "render/cell_tiler.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>

#include "engine/gpu/allocate_or_refuse.h"
#include "engine/gpu/context.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/vk_check.h"

namespace hsdf {
namespace {

constexpr std::uint32_t kMaxGroupsX = 65535;  // the least maxComputeWorkGroupCount[0] Vulkan allows
constexpr std::uint32_t kWorkgroupSize = 64;  // cell_tiles.comp local_size_x

// CellTile[tiles], the non-empty tile list, the sort workgroups' starts and the pixel masks
// (CELL_TILE_MASK_BITS) of lists of `capacity` entries in all.
VkDeviceSize tileBytes(std::uint32_t tileCount, std::uint32_t tileSize, std::uint32_t capacity) {
  static_assert(CELL_TILE_MASKS_OFFSET(1) == sizeof(shader::CellTile) + 2 * sizeof(std::uint32_t));
  return VkDeviceSize(CELL_TILE_MASKS_OFFSET(tileCount)) +
         VkDeviceSize(CELL_TILE_MASK_WORDS(capacity, tileCount, tileSize * tileSize)) * sizeof(std::uint32_t);
}

void computeToCompute(VkCommandBuffer cmd) {
  constexpr VkAccessFlags2 kReadWrite = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
  engine::gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                             VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, kReadWrite);
}

// The previous frame's draw read the tiles and entries (write after read), then zero the tiles.
void clearTiles(VkCommandBuffer cmd, VkBuffer tiles, std::uint32_t tileCount) {
  engine::gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_2_ALL_GRAPHICS_BIT, 0,
                             VK_PIPELINE_STAGE_2_CLEAR_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, 0);
  vkCmdFillBuffer(cmd, tiles, 0, VkDeviceSize(tileCount) * sizeof(shader::CellTile), 0);
}

// A phase that one workgroup runs over the whole grid (SCAN).
void dispatchPhase(VkCommandBuffer cmd, VkPipelineLayout layout, shader::CellTilePushConstants push, std::uint32_t phase) {
  push.phase = phase;
  vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
  vkCmdDispatch(cmd, 1, 1, 1);
}

// A phase with as many workgroups as the scan wrote into `totals` at `offset` (SORT, MASKS).
void dispatchPhaseIndirect(VkCommandBuffer cmd, VkPipelineLayout layout, shader::CellTilePushConstants push,
                           std::uint32_t phase, VkBuffer totals, VkDeviceSize offset) {
  push.phase = phase;
  vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
  vkCmdDispatchIndirect(cmd, totals, offset);
}

}  // namespace

bool tilesAsPoints(const engine::gpu::Context& context) {
  return context.capabilities().maxPointSize >= float(CELL_TILE_SIZE_MAX);
}

engine::Expected<CellTiler> CellTiler::create(const engine::gpu::Context& context, std::uint32_t frameSlots) {
  ENGINE_TRY_ASSIGN(auto module, engine::gpu::ShaderModule::load(context, "cell_tiles.comp"));
  CellTiler tiler;
  tiler.context_ = &context;
  ENGINE_TRY_ASSIGN(tiler.pipeline_, engine::gpu::Pipeline::createCompute(context, "cell tiles", module.handle(),
                                                                         sizeof(shader::CellTilePushConstants)));
  tiler.slots_.resize(frameSlots);
  // The scan writes the tile draw's command; the CPU reads the entries it needed.
  tiler.totals_ = engine::render::PerFrameBuffer(
      context, frameSlots, VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "hermite cell tile totals");
  return tiler;
}

shader::CellTileTotals CellTiler::lastTotals(std::uint32_t slot) const {
  shader::CellTileTotals totals{};
  const engine::gpu::Buffer& buffer = totals_.buffer(slot);
  if (slots_[slot].recorded && buffer && buffer.mapped()) std::memcpy(&totals, buffer.mapped(), sizeof(totals));
  return totals;
}

// The slot's buffers for this frame's tiles and at least `wanted` entries, at most `limit` (a
// smaller limit than the slot holds shrinks it). The slot's previous frame has completed (its
// fence was waited for), so replacing them is safe.
void CellTiler::ensureBuffers(Slot& slot, std::uint32_t tileCount, std::uint32_t tileSize, std::uint64_t wanted,
                              std::uint32_t limit) {
  constexpr VkBufferUsageFlags kUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
  wanted = std::clamp<std::uint64_t>(wanted, std::min<std::uint64_t>(4096, limit), limit);
  if (slot.capacity < wanted || slot.capacity > limit) {
    // A quarter more than asked: views that move a little do not reallocate every frame.
    const auto capacity = std::uint32_t(std::min<std::uint64_t>(wanted + wanted / 4, limit));
    const VkDeviceSize bytes = VkDeviceSize(capacity) * sizeof(shader::CellTileEntry);
    // Both made before either is replaced: a refusal leaves the slot as it was, its capacity true.
    engine::gpu::Buffer entries(*context_, bytes, kUsage, engine::gpu::MemoryUsage::GpuOnly, "hermite cell tile entries");
    engine::gpu::Buffer sorted(*context_, bytes, kUsage, engine::gpu::MemoryUsage::GpuOnly, "hermite sorted cell tile entries");
    slot.entries = std::move(entries);
    slot.sortedEntries = std::move(sorted);
    slot.capacity = capacity;
    slot.boundSized = !measured(slot);  // wantedEntries took the estimate
  }
  const VkDeviceSize bytes = tileBytes(tileCount, tileSize, slot.capacity);
  if (!slot.tiles || slot.tiles.size() < bytes)
    slot.tiles = engine::gpu::Buffer(*context_, bytes, kUsage | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                     engine::gpu::MemoryUsage::GpuOnly, "hermite cell tiles");
}

void CellTiler::releaseUnneeded(std::uint32_t slotIndex, bool tiling, std::uint64_t entryEstimate,
                                std::uint32_t frames, engine::gpu::DeferredRelease& retired, std::uint64_t lastUse) {
  constexpr std::uint64_t kKeptEntries = std::uint64_t(1) << 16;  // lists this small stay (2.5 MiB with their masks)
  Slot& slot = slots_[slotIndex];
  const bool held = slot.tiles || slot.entries || slot.sortedEntries;
  const bool unneeded = tiling ? slot.capacity > kKeptEntries && slot.capacity / 4 > wantedEntries(slotIndex, entryEstimate)
                               : held;
  // Lists the first frame made by the upper bound go as soon as a frame has measured what it
  // needs (the bound's extra is no history worth keeping); measured ones after `frames` frames.
  const bool boundOversized = tiling && unneeded && slot.boundSized && measured(slot);
  if (slot.idle.due(unneeded, frames) || boundOversized) release(slotIndex, retired, lastUse);
}

void CellTiler::release(std::uint32_t slotIndex, engine::gpu::DeferredRelease& retired, std::uint64_t lastUse) {
  Slot& slot = slots_[slotIndex];
  for (engine::gpu::Buffer* buffer : {&slot.tiles, &slot.entries, &slot.sortedEntries})
    if (*buffer) retired.retire(std::move(*buffer), lastUse);
  slot.capacity = 0;
  slot.boundSized = false;
  slot.idle.reset();
}

std::uint64_t CellTiler::bytesHeld() const {
  std::uint64_t bytes = 0;
  for (const Slot& slot : slots_)
    for (const engine::gpu::Buffer* buffer : {&slot.tiles, &slot.entries, &slot.sortedEntries})
      bytes += *buffer ? buffer->size() : 0;
  return bytes;
}

// The entries to make room for. Before the slot has tiled a frame: the estimate, an upper bound.
// After: what its last (completed) frame needed, scaled by how much the estimate has grown since
// (more objects, a nearer view), so that the lists follow the frame's real need rather than the
// bound, which holds 5-8x as many entries on the bunny (1920x1080, K = 64..256). A frame that
// needs more all the same draws its cells as boxes (an overflow, CellTileTotals::boxDrawCount),
// and the slot's next frame has room.
std::uint64_t CellTiler::wantedEntries(std::uint32_t slot, std::uint64_t entryEstimate) const {
  const Slot& s = slots_[slot];
  if (!measured(s)) return entryEstimate;
  const double growth = std::max(1.0, double(entryEstimate) / double(s.recordedEstimate));
  const double wanted = std::ceil(double(lastTotals(slot).entriesNeeded) * growth);
  return wanted >= 1.8e19 ? std::numeric_limits<std::uint64_t>::max() : std::uint64_t(wanted);
}

bool CellTiler::reserve(std::uint32_t slot, VkExtent2D extent, std::uint32_t tileSize, std::uint64_t entryEstimate,
                        std::uint32_t entryLimit, std::string& refusal) {
  const VkExtent2D grid = tileGrid(extent, tileSize);
  const engine::Status made = engine::gpu::allocateOrRefuse([&] {
    ensureBuffers(slots_[slot], std::max(grid.width * grid.height, 1u), tileSize, wantedEntries(slot, entryEstimate),
                  std::max(entryLimit, 1u));
  });
  if (!made) refusal = made.error().message;
  return made.ok();
}

void CellTiler::dispatchBins(VkCommandBuffer cmd, shader::CellTilePushConstants push, const Frame& frame,
                             std::uint32_t phase) {
  push.phase = phase;
  for (const Ranges& ranges : frame.precisions) {
    if (ranges.count == 0 || ranges.slots == 0) continue;
    push.ranges = ranges.ranges;
    push.keptRanges = ranges.keptRanges;
    push.keptCount = ranges.keptCount;
    push.keptIndices = ranges.keptIndices;
    push.rangeCount = ranges.count;
    push.slotCount = ranges.slots;
    const std::uint32_t groups = (ranges.slots + kWorkgroupSize - 1) / kWorkgroupSize;
    const std::uint32_t groupsX = std::min(groups, kMaxGroupsX);
    vkCmdPushConstants(cmd, pipeline_.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, groupsX, (groups + groupsX - 1) / groupsX, 1);
  }
}

// Sizes the slot's buffers for the frame and resets its totals (the tile draw's vertex count
// included); returns the number of tiles.
std::uint32_t CellTiler::startFrame(Slot& slot, const Frame& frame, VkExtent2D grid) {
  const std::uint32_t tileCount = std::max(grid.width * grid.height, 1u);
  ensureBuffers(slot, tileCount, frame.tileSize, wantedEntries(frame.slot, frame.entryEstimate), std::max(frame.entryLimit, 1u));
  slot.recorded = true;
  slot.recordedEstimate = frame.entryEstimate;
  slot.recordedCapacity = slot.capacity;
  shader::CellTileTotals totals{};
  totals.vertexCount = tilesAsPoints(*context_) ? 1 : 6;
  totals_.upload(frame.slot, &totals, sizeof(totals));
  return tileCount;
}

// What every phase reads (dispatchBins adds each precision's ranges).
shader::CellTilePushConstants CellTiler::pushConstants(const Slot& slot, const Frame& frame, VkExtent2D grid) const {
  shader::CellTilePushConstants push{};
  push.draws = frame.draws;
  push.objects = frame.objects;
  push.frameGlobals = frame.frameGlobals;
  push.tiles = slot.tiles.address();
  push.entries = slot.entries.address();
  push.sortedEntries = slot.sortedEntries.address();
  push.totals = totals_.address(frame.slot);
  push.tilesX = grid.width;
  push.tilesY = grid.height;
  push.tileSize = frame.tileSize;
  push.entryCapacity = slot.capacity;
  return push;
}

void CellTiler::record(VkCommandBuffer cmd, const Frame& frame, engine::gpu::GpuTimer* timer) {
  Slot& slot = slots_[frame.slot];
  const VkExtent2D grid = tileGrid(frame.extent, frame.tileSize);
  const std::uint32_t tileCount = startFrame(slot, frame, grid);

  // The culling pass wrote the kept cells and their counts that COUNT reads (its own barrier hands
  // them to the draws only).
  computeToCompute(cmd);
  // Each phase timed on its own (GPU captures say which one the tiling's time goes to): from the
  // end of everything recorded before it (GpuTimer's bottom-of-pipe begin), through the barrier
  // that waits for its input, to the end of its work.
  const auto phase = [&](const char* name) { return engine::gpu::GpuTimerScope(timer, cmd, name); };
  {
    const auto timing = phase("cells tiling clear");
    clearTiles(cmd, slot.tiles.handle(), tileCount);
  }

  const shader::CellTilePushConstants push = pushConstants(slot, frame, grid);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.handle());
  const VkPipelineLayout layout = pipeline_.layout();
  const VkBuffer totalsBuffer = totals_.buffer(frame.slot).handle();
  {
    const auto timing = phase("cells tiling count");
    engine::gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                               VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                               VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    dispatchBins(cmd, push, frame, CELL_TILES_COUNT);
  }
  {
    const auto timing = phase("cells tiling scan");
    computeToCompute(cmd);
    dispatchPhase(cmd, layout, push, CELL_TILES_SCAN);
  }
  {
    const auto timing = phase("cells tiling scatter");
    computeToCompute(cmd);
    dispatchBins(cmd, push, frame, CELL_TILES_SCATTER);
  }
  // SORT (a workgroup per few non-empty tiles, as the scan grouped them), then MASKS over the sorted lists.
  {
    const auto timing = phase("cells tiling sort");
    engine::gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                               VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
                               VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT |
                                   VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
    dispatchPhaseIndirect(cmd, layout, push, CELL_TILES_SORT, totalsBuffer, offsetof(shader::CellTileTotals, sortGroups));
  }
  {
    const auto timing = phase("cells tiling masks");
    computeToCompute(cmd);
    dispatchPhaseIndirect(cmd, layout, push, CELL_TILES_MASKS, totalsBuffer, offsetof(shader::CellTileTotals, maskGroups));
  }
  engine::gpu::memoryBarrier(
      cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
      VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_2_ALL_GRAPHICS_BIT | VK_PIPELINE_STAGE_2_HOST_BIT,
      VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_HOST_READ_BIT);
}

}  // namespace hsdf
