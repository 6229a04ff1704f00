// The cell feature's GPU culling passes: bricks, cells and occlusion's late culling.
#include "hermite_sdf/render/cell_feature.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <unordered_set>

#include <imgui.h>

#include "engine/core/log.h"
#include "engine/ecs/registry.h"
#include "engine/gpu/allocate_or_refuse.h"
#include "engine/gpu/context.h"
#include "engine/gpu/vk_check.h"
#include "engine/render/gpu_scene.h"
#include "engine/scene/transform.h"
#include "hermite/hermite_host_device.h"
#include "cells/cell_bricks.h"
#include "render/brick_culler.h"
#include "render/cell_feature_internal.h"
#include "render/cell_history.h"
#include "cells/cell_rows.h"
#include "render/cell_tiler.h"
#include "hermite_sdf/render/lod.h"
#include "hermite_sdf/core/normal_cone.h"

namespace hsdf {

namespace {

constexpr std::uint32_t kRecordStride[2] = {sizeof(CellRecord), sizeof(CellRecordHalf)};

// A culling pass's output buffer of at least `bytes` (device address, storage, plus `usage`): the
// frame slot's old one while it is large enough.
Buffer& ensureOutput(const engine::gpu::Context& context, Buffer& buffer, VkDeviceSize bytes, VkBufferUsageFlags usage,
                     const char* name) {
  bytes = std::max<VkDeviceSize>(bytes, 4);  // a zero-sized buffer is invalid
  if (!buffer || buffer.size() < bytes)
    buffer = Buffer(context, bytes, usage | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                    engine::gpu::MemoryUsage::GpuOnly, name);
  return buffer;
}

// The bytes of one slot of the kept streams: the record's copy, its record index and its range
// index (the tiling's).
std::uint64_t keptSlotBytes(int precision) { return kRecordStride[precision] + 2 * sizeof(std::uint32_t); }

// The least slots worth making the streams for: below it, the frame draws every cell unculled.
constexpr std::uint64_t kMinKeptSlots = 4096;

}  // namespace

// The share of the culled cells a frame keeps before one has been measured: the frustum and the
// normal cones keep about half the cells of objects in view (59 % of the 10,000-bunny grid's). A
// guess too high holds memory the later frames do not want (streams shrink only past 4x), one too
// low costs a frame whose rows past the streams are drawn unculled.
constexpr double kKeptShareGuess = 0.6;

// The slots the kept streams of `precision` should hold for a frame whose culled objects have
// `cells` cells: all of them while that fits in Settings::keptStreamBytes (no row can fall back);
// else this frame's cells times the share of its culled cells the slot's last completed culling
// frame kept (kKeptShareGuess before there is one), with a quarter to spare, at least that size.
// The share, not the count: a scene or view with ten times the cells wants ten times the slots
// from its first frame on.
std::uint64_t HermiteCellFeature::wantedKeptSlots(int precision, std::uint64_t cells) const {
  const std::uint64_t bytes = keptSlotBytes(precision);
  if (cells * bytes <= settings_.keptStreamBytes) return cells;
  const double share = keptShare_[precision] >= 0.0 ? keptShare_[precision] : kKeptShareGuess;
  const double demand = std::ceil(double(cells) * std::min(share, 1.0) * 1.25);
  return std::min(cells, std::max(settings_.keptStreamBytes / bytes, std::uint64_t(demand)));
}

// What the slot's last culling passes wanted of the kept streams (complete now: its submission was
// waited for), for this frame's sizes; and, once per change, a word when rows fell back.
void HermiteCellFeature::readKeptDemand(std::uint32_t slot) {
  const Buffer& buffer = cullTotals_.buffer(slot);
  for (double& share : keptShare_) share = -1.0;  // until read
  if (!buffer || !buffer.mapped()) return;
  shader::BrickCullTotals previous{};
  std::memcpy(&previous, buffer.mapped(), sizeof(previous));
  for (int precision = 0; precision < 2; ++precision)
    if (const std::uint64_t culled = keptCulledCells_[slot][precision]; culled > 0)
      keptShare_[precision] = double(previous.keptSlots[precision]) / double(culled);
  if (previous.fallbackCells > 0 && !keptOverflowLogged_) {
    engine::log::info("hermite cells: {} cells of culled rows did not fit in the kept-cell streams and were drawn "
                      "unculled; the next frames' streams are sized for the {} + {} slots the frame wanted, as far "
                      "as GPU memory allows",
                      previous.fallbackCells, previous.keptSlots[0], previous.keptSlots[1]);
  }
  keptOverflowLogged_ = previous.fallbackCells > 0;
}

// The slots this slot's kept streams of `precision` hold now (0 while one of them is missing).
std::uint64_t HermiteCellFeature::heldKeptSlots(std::uint32_t slot, int precision) const {
  const Buffer& records = keptCellRecords_[slot][precision];
  const Buffer& indices = keptCellIndices_[slot][precision];
  const Buffer& ranges = keptCellRanges_[slot][precision];
  if (!records || !indices || !ranges) return 0;
  return std::min({records.size() / kRecordStride[precision], indices.size() / 4, ranges.size() / 4});
}

// Releases this slot's kept-cell streams of a precision that have held far more than the slot's
// frames wanted (`wanted` slots this frame, 0 when it culls none of that precision) for
// Settings::releaseAfterFrames of its frames in a row: more than four times as many slots and
// more than keptStreamBytes, or any while nothing is wanted. reserveCellCulling then makes them at
// this frame's size. The slot's previous frame last used them (FrameContext::slotLastUse).
void HermiteCellFeature::releaseUnneededKeptStreams(const engine::render::FrameContext& frame,
                                                    const std::array<std::uint64_t, 2>& wanted) {
  const std::uint32_t slot = frame.frameSlot;
  for (int precision = 0; precision < 2; ++precision) {
    const std::uint64_t held = heldKeptSlots(slot, precision);
    const bool oversized = wanted[precision] == 0
                               ? keptCellRecords_[slot][precision] || keptCellIndices_[slot][precision] ||
                                     keptCellRanges_[slot][precision]
                               : held * keptSlotBytes(precision) > settings_.keptStreamBytes &&
                                     held / 4 > wanted[precision];
    if (keptIdle_[slot][precision].due(oversized, settings_.releaseAfterFrames))
      releaseKeptStreams(frame, slot, precision, frame.slotLastUse());
  }
}

void HermiteCellFeature::releaseKeptStreams(const engine::render::FrameContext& frame, std::uint32_t slot,
                                            int precision, std::uint64_t lastUse) {
  keptIdle_[slot][precision].reset();
  for (Buffer* stream : {&keptCellRecords_[slot][precision], &keptCellIndices_[slot][precision],
                         &keptCellRanges_[slot][precision]})
    if (*stream) frame.retire(std::move(*stream), lastUse);
}

// Marks this frame's slot prepared, and releases the kept streams and tile lists of every other
// slot that no frame has prepared for Settings::releaseAfterFrames frames (a view region no longer
// drawn never prepares its slots again, so their own frames cannot release them). They are retired
// with the frame that last prepared them.
void HermiteCellFeature::releaseIdleSlots(const engine::render::FrameContext& frame) {
  slotPreparedFrame_[frame.frameSlot] = frame.frameNumber;
  const std::uint64_t idle = std::max<std::uint64_t>(settings_.releaseAfterFrames, frame.framesInFlight);
  for (std::uint32_t slot = 0; slot < slotPreparedFrame_.size(); ++slot) {
    const std::uint64_t last = slotPreparedFrame_[slot];
    if (last == kNeverPrepared || frame.frameNumber - last < idle) continue;
    for (int precision = 0; precision < 2; ++precision) releaseKeptStreams(frame, slot, precision, last);
    tiler_->release(slot, *frame.retired, last);
    slotPreparedFrame_[slot] = kNeverPrepared;
  }
}

std::uint64_t HermiteCellFeature::keptStreamBytesHeld() const {
  std::uint64_t bytes = 0;
  for (const auto* streams : {&keptCellRecords_, &keptCellIndices_, &keptCellRanges_})
    for (const auto& slotStreams : *streams)
      for (const Buffer& buffer : slotStreams) bytes += buffer ? buffer.size() : 0;
  return bytes;
}

// Makes this slot's kept-cell streams for the frame's culled objects before their commands are
// written (`wantedSlots`, wantedKeptSlots' sizes; halved while GPU memory, the allocator's budget or one buffer refuses
// them, down to the streams the slot already holds: rows that do not fit then fall back). False,
// with the reason, when the slot holds none and not even kMinKeptSlots fit: the frame draws every
// cell unculled instead of failing.
bool HermiteCellFeature::reserveCellCulling(std::uint32_t slot, const std::array<std::uint64_t, 2>& cells,
                                            const std::array<std::uint64_t, 2>& wantedSlots, std::string& refusal) {
  clearKeptStreams();
  for (int precision = 0; precision < 2; ++precision) {
    if (cells[precision] == 0) continue;
    if (cells[precision] > std::numeric_limits<std::uint32_t>::max()) {
      refusal = fmt::format("{} cells to cull, more than a 32-bit instance index reaches", cells[precision]);
      return false;
    }
    const std::uint64_t stride = kRecordStride[precision];
    // At most what one buffer holds (past it the records' buffer would be refused outright).
    std::uint64_t wanted = std::min(wantedSlots[precision],
                                    std::max<std::uint64_t>(context_->capabilities().maxBufferSize / stride, 1));
    for (;;) {
      const engine::Status made = engine::gpu::allocateOrRefuse([&] {
        const Buffer& records = ensureOutput(*context_, keptCellRecords_[slot][precision], wanted * stride,
                                             VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, "hermite kept cells");
        const Buffer& indices = ensureOutput(*context_, keptCellIndices_[slot][precision],
                                             wanted * sizeof(std::uint32_t), 0, "hermite kept cell indices");
        // The range indices only serve the tiling, but are made in every culled frame: a frame
        // whose tiles come on then has its streams, and stays within the same budget.
        const Buffer& ranges = ensureOutput(*context_, keptCellRanges_[slot][precision], wanted * sizeof(std::uint32_t),
                                            0, "hermite kept cell ranges");
        const std::uint64_t capacity =
            std::min({cells[precision], records.size() / stride, indices.size() / 4, ranges.size() / 4});
        keptCapacity_[precision] = std::uint32_t(capacity);
        keptFallback_[precision] = capacity < cells[precision];
      });
      if (made) break;
      // Half as many, or the streams the slot holds when they are larger (no new buffer), or when
      // nothing of kMinKeptSlots fits, the streams it holds whatever their size.
      const std::uint64_t held = heldKeptSlots(slot, precision);
      const std::uint64_t next = std::max(wanted / 2, held);
      if (next >= wanted || (next < kMinKeptSlots && held == 0)) {
        refusal = fmt::format("the kept-cell streams of {} cells ({} MiB) do not fit: {}", wanted,
                              (wanted * keptSlotBytes(precision)) >> 20, made.error().message);
        return false;
      }
      wanted = next < kMinKeptSlots ? held : next;
    }
  }
  stats_.keptSlots = std::uint64_t(keptCapacity_[0]) + keptCapacity_[1];
  stats_.keptMayFallBack = keptFallback_[0] || keptFallback_[1];
  return true;
}

// The culling passes of this frame slot, bricks and cells, which add up their counts in the slot's
// totals. The totals of the slot's previous passes are complete now (its submission was waited
// for): they become the stats.
void HermiteCellFeature::recordCulling(engine::render::FrameContext& frame) {
  lastCullSlot_ = frame.frameSlot;
  if (cullObjectList_.empty() && cellCullObjects_.empty()) return;
  const engine::gpu::GpuTimerScope timing(frame.timer, frame.cmd, "cells culling");
  cullTotals_.upload(frame.frameSlot, std::vector<shader::BrickCullTotals>(1));
  recordBrickCulling(frame);
  recordCellCulling(frame);
}

// The brick culling pass of this frame slot (brick_culler.h): every culled object's bricks tested
// against the frustum and its normal cones, the kept ones written to the slot's kept-brick stream,
// which the bricks' front-face draws then read instead of the asset buffer.
void HermiteCellFeature::recordBrickCulling(engine::render::FrameContext& frame) {
  if (cullObjectList_.empty()) return;
  cullObjects_.upload(frame.frameSlot, cullObjectList_);
  Buffer& kept = ensureOutput(*context_, keptBricks_[frame.frameSlot],
                              VkDeviceSize(cullOutputBricks_) * sizeof(shader::CellBrickGpu),
                              VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, "hermite kept bricks");
  culler_->record(frame.cmd,
                 {cullObjects_.address(frame.frameSlot), buffers_->bricks.address(), buffers_->brickCones.address(),
                  kept.address(), indirect_.address(frame.frameSlot), cullTotals_.address(frame.frameSlot)},
                 std::uint32_t(cullObjectList_.size()), cullMaxBricks_);
}

// The cell culling pass (cell_cull.comp) of this frame slot: one dispatch per record precision
// over its ranges, writing the slot's kept records (the front faces' vertex stream instead of the
// record buffer), their record indices and the commands' instance counts.
void HermiteCellFeature::recordCellCulling(engine::render::FrameContext& frame) {
  if (cellCullRanges_[0].empty() && cellCullRanges_[1].empty()) return;
  // Per precision: its ranges and packs (CellCuller::rangeUpload; uints, 4-byte aligned as the
  // scalar layout wants).
  std::vector<std::uint32_t> words;
  for (int precision = 0; precision < 2; ++precision) {
    const CellCuller::RangeUpload upload = CellCuller::rangeUpload(cellCullRanges_[precision]);
    cellCullRangeOffsets_[precision] = words.size() * sizeof(std::uint32_t);
    cellCullPackCounts_[precision] = upload.packCount;
    words.insert(words.end(), upload.words.begin(), upload.words.end());
  }
  const std::uint32_t slot = frame.frameSlot;
  cellCullObjectBuffer_.upload(slot, cellCullObjects_);
  cellCullRangeBuffer_.upload(slot, words);
  barrierBeforeCulling(frame.cmd);
  shader::CellCullPushConstants push{};
  if (occlusion_) {
    // The previous frame's phase 2 wrote the history this phase 1 reads.
    engine::gpu::memoryBarrier(frame.cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                               VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, kStorageReadWrite);
    push.history = history_->address();
    push.phase = CELL_CULL_PHASE_EARLY;
  }
  recordCellCullPasses(frame.cmd, slot, push);
  barrierAfterCulling(frame.cmd);
}

// The relative depth margin of the occlusion test (CellCullPushConstants::depthMargin). A hit lies
// at most the search margin beyond its cell: 0.02 pixel of dilation (taken as 0.1 pixel: a depth
// along the ray, any direction), or kMinDilation = 1/4096 cell. At a distance d, p pixels are
// p * 2 d / (proj[1][1] H) world units, a relative depth change of p * 2 / (proj[1][1] H) under
// reverse-Z (depth ~ 1 / d); 1/4096 of a cell is at most ~1e-3 of its distance for any cell not
// larger on screen than the view (taken as 2e-3).
float HermiteCellFeature::occlusionDepthMargin(const engine::render::CameraView& camera, VkExtent2D extent) {
  const float pixelAngle = 2.0f / (std::abs(camera.proj[1][1]) * float(std::max(extent.height, 1u)));
  return 0.1f * pixelAngle + 2.0e-3f;
}

// Occlusion culling's phase 2 (after the renderer built the pyramid of phase 1's depth): every
// culled cell tested against it, the history updated, the visible cells phase 1 did not draw
// appended to the kept streams and counted in the late commands.
void HermiteCellFeature::recordLateCulling(engine::render::PassContext& pass,
                                           const engine::render::DepthPyramidView& pyramid) {
  if (!occlusion_) return;
  pass.timer.begin(pass.cmd, "cells late culling");
  barrierBeforeCulling(pass.cmd);
  // Phase 1 read the history and wrote the first halves of the streams and the commands.
  engine::gpu::memoryBarrier(pass.cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, kStorageReadWrite,
                             VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, kStorageReadWrite);
  shader::CellCullPushConstants push{};
  push.history = history_->address();
  push.pyramid = pyramid.address;
  push.pyramidExtent = pyramid.extent.width | (pyramid.extent.height << 16);
  push.pyramidLevels = pyramid.levels;
  push.phase = CELL_CULL_PHASE_LATE;
  push.depthMargin = occlusionDepthMargin(pass.frame.camera, pyramid.extent);
  recordCellCullPasses(pass.cmd, pass.frame.frameSlot, push);
  barrierAfterCulling(pass.cmd);
  pass.timer.end(pass.cmd);
}

// One cell_cull.comp dispatch per record precision over its ranges, with the slot's buffers (made
// by reserveCellCulling); the phase and occlusion fields of `push` as the caller set them. Phase 2
// writes its commands after phase 1's and appends to the same streams.
void HermiteCellFeature::recordCellCullPasses(VkCommandBuffer cmd, std::uint32_t slot,
                                              shader::CellCullPushConstants push) {
  const bool late = push.phase == CELL_CULL_PHASE_LATE;
  for (int precision = 0; precision < 2; ++precision) {
    const auto rangeCount = static_cast<std::uint32_t>(cellCullRanges_[precision].size());
    if (rangeCount == 0) continue;
    push.objects = cellCullObjectBuffer_.address(slot);
    push.ranges = cellCullRangeBuffer_.address(slot) + cellCullRangeOffsets_[precision];
    push.packCount = cellCullPackCounts_[precision];
    push.records = buffers_->records[precision].address();
    push.cones = buffers_->cellCones.address();
    push.keptRecords = keptCellRecords_[slot][precision].address();
    push.keptIndices = keptCellIndices_[slot][precision].address();
    push.keptRanges = tiles_ ? keptCellRanges_[slot][precision].address() : 0;
    push.commands = indirect_.address(slot);
    push.totals = cullTotals_.address(slot);
    push.rangeCount = rangeCount;
    push.recordWords = kRecordStride[precision] / 4;
    push.recordPrecision = std::uint32_t(precision);
    push.keptCapacity = keptCapacity_[precision];
    const Batch& batch = *batches_[precision];
    push.commandOffset = late ? batch.lateFirst - batch.frontFirst : 0;
    cellCuller_->record(cmd, push);
  }
}

shader::BrickCullTotals HermiteCellFeature::cullTotals() const {
  shader::BrickCullTotals totals{};
  const Buffer& buffer = cullTotals_.buffer(lastCullSlot_);
  const bool culled = !cullObjectList_.empty() || !cellCullObjects_.empty();
  if (culled && buffer && buffer.mapped()) std::memcpy(&totals, buffer.mapped(), sizeof(totals));
  return totals;
}

}  // namespace hsdf
