// The cell feature's lifecycle, per-frame preparation and the recording of its passes.
#include "hermite_sdf/render/cell_feature.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <string>
#include <unordered_set>
#include <vector>

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

// The renderer's work counters when the frame counts (the capture reads them back), else the
// feature's own heat-map counters when the evals view is on, else none.
VkDeviceAddress counterAddress(const engine::render::FrameContext& frame, bool active,
                               const engine::gpu::PixelBuffer& own) {
  return frame.workCounters ? frame.workCounters : active ? own.address() : 0;
}

}  // namespace

HermiteCellFeature::HermiteCellFeature() : buffers_(std::make_unique<CellBuffers>()) {
  for (auto& batch : batches_) batch = std::make_unique<Batch>();
}

HermiteCellFeature::~HermiteCellFeature() = default;

engine::Status HermiteCellFeature::initialize(const engine::gpu::Context& context,
                                              const engine::render::RendererFormats& formats,
                                              std::uint32_t framesInFlight) {
  context_ = &context;
  draws_ = engine::gpu::IndirectDraws(context);
  drawData_ = engine::render::PerFrameBuffer(context, framesInFlight, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                             "hermite cell draw table");
  drawRecords_ = engine::render::PerFrameBuffer(context, framesInFlight, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                                "hermite cell draws");
  // Storage too: the brick culling pass writes the instance counts of the bricks' commands.
  indirect_ = engine::render::PerFrameBuffer(context, framesInFlight,
                                             VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                             "hermite cell indirect");
  cullObjects_ = engine::render::PerFrameBuffer(context, framesInFlight, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                                "hermite brick cull objects");
  cullTotals_ = engine::render::PerFrameBuffer(context, framesInFlight, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                               "hermite brick cull totals");
  keptBricks_.resize(framesInFlight);
  ENGINE_TRY_ASSIGN(auto culler, BrickCuller::create(context));
  culler_ = std::make_unique<BrickCuller>(std::move(culler));
  cellCullObjectBuffer_ = engine::render::PerFrameBuffer(context, framesInFlight, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                                         "hermite cell cull objects");
  cellCullRangeBuffer_ = engine::render::PerFrameBuffer(context, framesInFlight, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                                        "hermite cell cull ranges");
  keptCellRecords_.resize(framesInFlight);
  keptCellIndices_.resize(framesInFlight);
  keptCellRanges_.resize(framesInFlight);
  keptIdle_.assign(framesInFlight, {});
  keptCulledCells_.assign(framesInFlight, {0, 0});
  slotPreparedFrame_.assign(framesInFlight, kNeverPrepared);
  history_ = std::make_unique<CellHistory>();
  frameSlots_ = framesInFlight;
  ENGINE_TRY_ASSIGN(auto cellCuller, CellCuller::create(context));
  cellCuller_ = std::make_unique<CellCuller>(std::move(cellCuller));
  ENGINE_TRY_ASSIGN(auto tiler, CellTiler::create(context, framesInFlight));
  tiler_ = std::make_unique<CellTiler>(std::move(tiler));
  objects_ = engine::render::PerFrameBuffer(context, framesInFlight, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                            "hermite cell objects");
  formats_ = formats;
  ENGINE_TRY_ASSIGN(pipelines_, describePipelines());
  return {};
}

// engine::gpu::reloadPipelineSet: those only warmed are warmed again from the next frame
// (Settings::warmPipelines), the rest compiled from the new SPIR-V when a frame first needs them.
engine::Status HermiteCellFeature::reloadShaders() {
  return engine::gpu::reloadPipelineSet(*context_, warming_, pipelines_, [this] { return describePipelines(); });
}

engine::Status HermiteCellFeature::createAllPipelines() {
  return engine::gpu::createAll(*context_, pipelines_.all());
}

void HermiteCellFeature::ensureCounters(engine::render::FrameContext& frame) {
  countersActive_ = settings_.heatMapCounters && frame.debugView == DEBUG_VIEW_EVALS && stats_.draws > 0;
  if (!countersActive_) return;
  counters_.ensure(*context_, frame.extent, *frame.retired, frame.frameNumber);
  // Earlier frames read the counters in their shading pass; this frame rewrites them.
  engine::gpu::memoryBarrier(frame.cmd, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                             VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  vkCmdFillBuffer(frame.cmd, counters_.handle(), 0, VK_WHOLE_SIZE, 0);
  engine::gpu::memoryBarrier(frame.cmd, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                             VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, kStorageReadWrite);
}

void HermiteCellFeature::prepare(engine::render::FrameContext& frame) {
  regionStats_.startRegion(frame.frameNumber, stats_);
  drawnAssets_.beginRegion(frame);
  syncAssets(frame);
  buildDraws(frame);
  recordCulling(frame);
  recordTiling(frame);
  stats_.keptStreamBytesHeld = keptStreamBytesHeld();
  stats_.tileListBytesHeld = tiler_->bytesHeld();
  stats_.historyBytesHeld = history_->bytes();
  ensureCounters(frame);
  ensureHitDepths(frame);
  stats_.earlyDepth = earlyDepth_;
  stats_.countedVariant = stats_.draws > 0 && prepassVariant(frame) == kCounted;
  warmPipelines(frame);
}

// The per-pixel hit depths of the early depth stage, zero between frames (the fix-up clears what
// it read). A buffer that cannot be allocated turns early depth off, the frame still draws.
void HermiteCellFeature::ensureHitDepths(engine::render::FrameContext& frame) {
  if (!earlyDepth_) return;
  VkCommandBuffer cmd = frame.cmd;
  const auto made = engine::gpu::allocateOrRefuse(
      [&] { return hitDepths_.ensure(*context_, frame.extent, *frame.retired, frame.frameNumber); });
  if (!made) {
    engine::log::warn("hermite cells: no early depth this frame: {}", made.error().message);
    earlyDepth_ = false;
    return;
  }
  if (*made) {
    vkCmdFillBuffer(cmd, hitDepths_.handle(), 0, VK_WHOLE_SIZE, 0);
    engine::gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                               VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, kStorageReadWrite);
    return;
  }
  // The previous frame's (or view region's) fix-up cleared the pixels it read; this frame's early
  // fragments write them again.
  engine::gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                             VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, kStorageReadWrite);
}

// The production pipelines unless the frame counts work or draws the early depth stage (whose
// variants count when pc.counters is set: they hold buffer writes anyway). The counted variants
// then draw the same image as the production ones, and count what they counted before.
HermiteCellFeature::Variant HermiteCellFeature::prepassVariant(const engine::render::FrameContext& frame) const {
  if (earlyDepth_) return kEarly;
  return counterAddress(frame, countersActive_, counters_) != 0 ? kCounted : kProduction;
}

// What every prepass draw of the cells pushes: the frame, the objects, this slot's draws, the
// evaluation counters and the work totals where the frame counts (0 otherwise).
shader::HermitePushConstants HermiteCellFeature::prepassPush(const engine::render::PassContext& pass) const {
  shader::HermitePushConstants push{};
  push.draw.frameGlobals = pass.frameGlobals;
  push.draw.objects = pass.objects;
  push.draw.debugView = pass.frame.debugView;
  push.draws = drawData_.address(pass.frame.frameSlot);
  push.counters = counterAddress(pass.frame, countersActive_, counters_);
  push.workTotals = pass.frame.workTotals;
  return push;
}

void HermiteCellFeature::recordBatch(engine::render::PassContext& pass, int precision, List list, VkBuffer countBuffer,
                                     VkDeviceSize countOffset) {
  const Batch& batch = *batches_[precision];
  const bool near = list == List::Near;
  const std::uint32_t first = list == List::Late       ? batch.lateFirst
                              : list == List::Near     ? batch.nearFirst
                              : list == List::Fallback ? batch.fallbackFirst
                                                       : batch.frontFirst;
  const std::uint32_t count = near ? batch.nearCount : list == List::Fallback ? batch.fallbackCount : batch.frontCount;
  if (count == 0) return;
  VkCommandBuffer cmd = pass.cmd;
  const bool runs = precision == kRunBatch;
  const bool bricks = precision == kBrickBatch;
  const Variant variant = prepassVariant(pass.frame);
  const int noEarly = withoutEarlyStage(variant);
  Pipelines::Lazy& lazy = bricks ? (near ? pipelines_.bricksNear[noEarly] : pipelines_.bricksFront[noEarly])
                          : runs ? (near ? pipelines_.runsNear[variant] : pipelines_.runsFront[variant])
                          : thinBoxes_ ? (near ? pipelines_.thinNear[noEarly][precision]
                                               : pipelines_.thinFront[noEarly][precision])
                                 : (near ? pipelines_.depthNear[variant][precision]
                                         : pipelines_.depthFront[variant][precision]);
  const Pipeline* pipeline = lazy.getOrLog(*context_);
  if (!pipeline) return;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline->handle());
  const VkBuffer vertexBuffer = batchStream(precision);
  const VkDeviceSize offset = 0;
  vkCmdBindVertexBuffers(cmd, 0, 1, &vertexBuffer, &offset);

  shader::HermitePushConstants push = prepassPush(pass);
  push.hitDepths = earlyDepth_ ? hitDepths_.address() : 0;
  if (bricks && !near && !cullObjectList_.empty()) {
    // The front faces draw the culling pass's kept bricks (the near list: every near brick).
    const Buffer& kept = keptBricks_[pass.frame.frameSlot];
    const VkBuffer keptBuffer = kept.handle();
    vkCmdBindVertexBuffers(cmd, 0, 1, &keptBuffer, &offset);
    push.bricks = kept.address();
    push.brickCells = buffers_->brickCells.address();
  } else if (bricks) {
    push.bricks = buffers_->bricks.address();
    push.brickCells = buffers_->brickCells.address();
  } else if (!runs && (list == List::Front || list == List::Late) && !cellCullRanges_[precision].empty()) {
    // The front faces draw the cell culling pass's kept records (the near list: every near cell;
    // the fallback list: the rows the kept streams could not hold, from the record buffer).
    const VkBuffer keptBuffer = keptCellRecords_[pass.frame.frameSlot][precision].handle();
    vkCmdBindVertexBuffers(cmd, 0, 1, &keptBuffer, &offset);
    push.cellRecords = keptCellIndices_[pass.frame.frameSlot][precision].address();
  }
  recordIndirect(cmd, *pipeline, push, pass.frame.frameSlot, first, count, countBuffer, countOffset);
}

HermiteCellFeature::Variant HermiteCellFeature::withoutEarlyStage(Variant variant) {
  return variant == kCounted ? kCounted : kProduction;
}

void HermiteCellFeature::recordIndirect(VkCommandBuffer cmd, const Pipeline& pipeline, shader::HermitePushConstants push,
                                        std::uint32_t frameSlot, std::uint32_t first, std::uint32_t count,
                                        VkBuffer countBuffer, VkDeviceSize countOffset) {
  const VkShaderStageFlags stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
  // The draws find their HermiteDraw at drawBase + gl_DrawID, which is 0 in each single draw.
  const auto pushBase = [&](std::uint32_t base) {
    push.drawBase = base;
    vkCmdPushConstants(cmd, pipeline.layout(), stages, 0, sizeof(push), &push);
  };
  if (draws_.multiDraw()) pushBase(first);
  draws_.draw(cmd, indirect_.buffer(frameSlot).handle(), first, count, countBuffer, countOffset, pushBase);
}

// The instance stream batch b's draws read: the bricks, the runs, or the records of a precision.
VkBuffer HermiteCellFeature::batchStream(int b) const {
  return b == kBrickBatch ? buffers_->bricks.handle()
         : b == kRunBatch ? buffers_->runs.handle()
                          : buffers_->records[b].handle();
}

void HermiteCellFeature::recordWireframe(engine::render::PassContext& pass, int b) {
  const Batch& batch = *batches_[b];
  if (batch.frontCount == 0) return;
  const Pipeline* pipeline = pipelines_.wire[b].getOrLog(*context_);
  if (!pipeline) return;
  VkCommandBuffer cmd = pass.cmd;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline->handle());
  const VkBuffer vertexBuffer = batchStream(b);
  const VkDeviceSize offset = 0;
  vkCmdBindVertexBuffers(cmd, 0, 1, &vertexBuffer, &offset);
  shader::HermitePushConstants push{};
  push.draw.frameGlobals = pass.frameGlobals;
  push.draw.objects = pass.objects;
  push.draws = drawData_.address(pass.frame.frameSlot);
  recordIndirect(cmd, *pipeline, push, pass.frame.frameSlot, batch.wireFirst, batch.frontCount);
}

void HermiteCellFeature::recordResolve(engine::render::PassContext& pass) {
  recordRectangle(pass, pipelines_.resolve);
}

// The rectangle over the cell objects' screen bounds (cells_resolve.vert) with `pipeline`: the
// shading resolve (which reads the scene set) or the early depth fix-up.
void HermiteCellFeature::recordRectangle(engine::render::PassContext& pass, Pipelines::Lazy& lazy) {
  if (!(screenRect_.x < screenRect_.z && screenRect_.y < screenRect_.w)) return;  // no object on screen
  const Pipeline* made = lazy.getOrLog(*context_);
  if (!made) return;
  const Pipeline& pipeline = *made;
  VkCommandBuffer cmd = pass.cmd;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.handle());
  if (pass.pass == engine::render::Pass::Opaque)
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.layout(), 0, 1, &pass.sceneSet, 0, nullptr);
  shader::HermitePushConstants push{};
  push.draw.frameGlobals = pass.frameGlobals;
  push.draw.objects = pass.objects;
  push.draw.debugView = pass.frame.debugView;
  push.draws = drawData_.address(pass.frame.frameSlot);  // the region's records: each object's anchor
  push.counters = counterAddress(pass.frame, countersActive_, counters_);
  push.hitDepths = earlyDepth_ ? hitDepths_.address() : 0;
  push.screenRect = screenRect_;
  vkCmdPushConstants(cmd, pipeline.layout(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                     sizeof(push), &push);
  vkCmdDraw(cmd, 6, 1, 0, 0);
}

void HermiteCellFeature::recordPass(engine::render::PassContext& pass) {
  if (stats_.draws == 0) return;
  if (pass.pass == engine::render::Pass::Opaque) {
    pass.timer.begin(pass.cmd, "cells shading");
    recordResolve(pass);
    if (pass.frame.debugView == DEBUG_VIEW_WIREFRAME)
      for (int b = 0; b < kBatches; ++b) recordWireframe(pass, b);
    pass.timer.end(pass.cmd);
    return;
  }
  if (pass.occlusionLate) {  // phase 2 of occlusion culling: the culled cells' late commands only
    pass.timer.begin(pass.cmd, "cells prepass late");
    // The rows that did not fit in phase 2's part of the streams, as well as phase 1's again.
    for (int precision = 0; precision < 2; ++precision) {
      recordBatch(pass, precision, List::Late);
      recordBatch(pass, precision, List::Fallback);
    }
    pass.timer.end(pass.cmd);
    return;
  }
  if (!earlyDepth_) recordPrepassDraws(pass);  // else drawn in the early depth stage
}

void HermiteCellFeature::recordEarlyDepth(engine::render::PassContext& pass) {
  if (stats_.draws > 0) recordPrepassDraws(pass);
}

void HermiteCellFeature::recordEarlyDepthResolve(engine::render::PassContext& pass) {
  if (stats_.draws == 0) return;
  pass.timer.begin(pass.cmd, "cells depth fix-up");
  recordRectangle(pass, pipelines_.depthFixup);
  pass.timer.end(pass.cmd);
}

void HermiteCellFeature::recordPrepassDraws(engine::render::PassContext& pass) {
  pass.timer.begin(pass.cmd, "cells prepass");
  if (tiles_) recordTiles(pass);
  for (int precision = 0; precision < kBatches; ++precision) {
    // Tiles draw the culled cells' front lists (every front command of a tiled frame is culled),
    // unless their lists overflowed: then the GPU-written count draws those lists' boxes.
    if (tiles_ && precision < kRunBatch)
      recordBatch(pass, precision, List::Front, tiler_->drawCommand(pass.frame.frameSlot).handle(),
                  CellTiler::kBoxDrawCountOffset);
    else
      recordBatch(pass, precision, List::Front);
    recordBatch(pass, precision, List::Near);
    if (precision < kRunBatch) recordBatch(pass, precision, List::Fallback);
  }
  pass.timer.end(pass.cmd);
}

// The tiling of this frame's culled cells (cell_tiler.h), after the culling pass that kept them.
void HermiteCellFeature::recordTiling(engine::render::FrameContext& frame) {
  if (!tiles_) return;
  const std::uint32_t slot = frame.frameSlot;
  CellTiler::Frame tiling;
  tiling.slot = slot;
  tiling.extent = frame.extent;
  tiling.tileSize = tileSize_;
  tiling.draws = drawData_.address(slot);
  tiling.objects = cellCullObjectBuffer_.address(slot);
  tiling.frameGlobals = frame.frameGlobals;
  tiling.entryEstimate = tileEntryEstimate_;
  tiling.entryLimit = std::max(settings_.maxTileEntries, kMinTileEntries);
  for (int precision = 0; precision < 2; ++precision) {
    const auto count = static_cast<std::uint32_t>(cellCullRanges_[precision].size());
    if (count == 0) continue;
    tiling.precisions[precision] = {cellCullRangeBuffer_.address(slot) + cellCullRangeOffsets_[precision],
                                    keptCellIndices_[slot][precision].address(),
                                    keptCellRanges_[slot][precision].address(),
                                    cullTotals_.address(slot) + offsetof(shader::BrickCullTotals, keptSlots) +
                                        precision * sizeof(std::uint32_t),
                                    count,
                                    keptCapacity_[precision]};
  }
  logTileOverflow(tiler_->lastTotals(slot), tiler_->lastCapacity(slot), tiling.entryLimit);
  {
    const engine::gpu::GpuTimerScope timing(frame.timer, frame.cmd, "cells tiling");
    tiler_->record(frame.cmd, tiling, frame.timer);
  }
  lastTileSlot_ = slot;
  tiledOnce_ = true;
}

// What this slot's previous tiled frame (completed) found: lists that overflowed drew boxes, which
// a user should hear of (the tiles' saving is gone, and the limit is a setting) once, until a
// frame fits again. Lists sized by the slot's earlier frames that a larger frame outgrew (a window
// made larger) are remade at its size by the next frame: that is said at debug level, naming the
// capacity they had (the warning named the setting's limit, which was not reached).
void HermiteCellFeature::logTileOverflow(const shader::CellTileTotals& previous, std::uint32_t capacity,
                                         std::uint32_t limit) {
  if (previous.boxDrawCount != 0 && !tileOverflowLogged_) {
    if (previous.hugeCells > 0)
      engine::log::warn("hermite cells: {} cells each spanned more than {} screen tiles (the eye near the surface): "
                        "the frame drew the cells as boxes instead",
                        previous.hugeCells, CELL_TILE_MAX_CELL_TILES);
    else if (previous.entriesNeeded > limit)
      engine::log::warn("hermite cells: the tiles needed {} list entries, more than the {} they may hold "
                        "(Settings::maxTileEntries): the frame drew the cells as boxes instead",
                        previous.entriesNeeded, limit);
    else
      engine::log::debug("hermite cells: the tiles needed {} list entries, more than the {} this frame slot's lists "
                         "held (sized by its earlier frames; the next frame's are sized for it): the frame drew the "
                         "cells as boxes instead",
                         previous.entriesNeeded, capacity);
    tileOverflowLogged_ = true;
  } else if (previous.boxDrawCount == 0 && previous.entriesNeeded > 0) {
    tileOverflowLogged_ = false;
  }
}

// One quad per non-empty tile (cell_tiles.vert), its instance count written by the tiling's scan.
void HermiteCellFeature::recordTiles(engine::render::PassContext& pass) {
  const std::uint32_t slot = pass.frame.frameSlot;
  const Pipeline* made = pipelines_.tiles[withoutEarlyStage(prepassVariant(pass.frame))].getOrLog(*context_);
  if (!made) return;
  const Pipeline& pipeline = *made;
  vkCmdBindPipeline(pass.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.handle());
  shader::HermitePushConstants push = prepassPush(pass);
  push.tiles = tiler_->tiles(slot);
  push.tileEntries = tiler_->entries(slot);
  push.tileSize = tileSize_;
  vkCmdPushConstants(pass.cmd, pipeline.layout(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                     sizeof(push), &push);
  draws_.draw(pass.cmd, tiler_->drawCommand(slot).handle(), 0, 1);
}

shader::CellTileTotals HermiteCellFeature::tileTotals() const {
  if (!tiledOnce_ || !stats_.tiles) return {};
  return tiler_->lastTotals(lastTileSlot_);
}

void HermiteCellFeature::drawUi() {
  if (!ImGui::CollapsingHeader("Hermite cells", ImGuiTreeNodeFlags_DefaultOpen)) return;
  // Read-only: the application owns the setting (the scene runner's tuning panel writes it).
  const bool wanted = earlyDepthWanted(settings_.earlyDepth, context_->capabilities().isSoftwareRasterizer);
  const char* mode = settings_.earlyDepth == EarlyDepth::Auto ? " (auto)" : "";
  ImGui::TextWrapped("front-to-back rows: %s, early depth: %s%s", settings_.frontToBack ? "on" : "off",
                     stats_.earlyDepth ? "on" : wanted ? "off (objects overlap on screen)" : "off", mode);
  const std::vector<Stats> regions = regionStats();
  for (std::size_t i = 0; i < regions.size(); ++i) {
    const Stats& s = regions[i];
    const std::string view = engine::render::regionPrefix(i, regions.size());
    ImGui::TextWrapped("%sobjects %u, cells %llu, draws %u, near cells %u, outside the view %u, skipped %u",
                       view.c_str(), s.objects, static_cast<unsigned long long>(s.cells), s.draws, s.nearCells,
                       s.culledObjects, s.skippedObjects);
  }
  ImGui::TextWrapped("cell buffers: %.2f MiB (held: %.2f MiB)", double(stats_.gpuBytes) / (1024.0 * 1024.0),
                     double(stats_.gpuBytesHeld) / (1024.0 * 1024.0));
  if (stats_.cullingRefused) ImGui::TextUnformatted("cell culling off: its kept-cell streams do not fit (see the log)");
  if (stats_.keptMayFallBack)
    ImGui::TextWrapped("kept-cell streams: %llu slots, sized by recent frames (rows past them drawn unculled)",
                       static_cast<unsigned long long>(stats_.keptSlots));
  if (stats_.keptStreamBytesHeld + stats_.tileListBytesHeld + stats_.historyBytesHeld > 0)
    ImGui::TextWrapped("held for culling: kept-cell streams %.2f MiB, tile lists %.2f MiB, occlusion history %.2f MiB",
                       double(stats_.keptStreamBytesHeld) / (1024.0 * 1024.0),
                       double(stats_.tileListBytesHeld) / (1024.0 * 1024.0),
                       double(stats_.historyBytesHeld) / (1024.0 * 1024.0));
  const engine::gpu::PipelineCounts pipelines = pipelineCounts();
  ImGui::TextWrapped("pipelines compiled: %u of %u (each when first drawn with)", pipelines.compiled, pipelines.described);
}

}  // namespace hsdf
