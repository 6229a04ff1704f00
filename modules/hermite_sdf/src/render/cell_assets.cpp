// The cell feature's GPU copy of the drawn assets: records, runs, bricks and normal cones.
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
#include "engine/gpu/context.h"
#include "engine/gpu/vk_check.h"
#include "engine/render/gpu_scene.h"
#include "engine/scene/transform.h"
#include "hermite/hermite_host_device.h"
#include "cells/cell_bricks.h"
#include "render/brick_culler.h"
#include "render/cell_feature_internal.h"
#include "render/cell_history.h"
#include "render/cell_rows.h"
#include "hermite_sdf/render/lod.h"
#include "hermite_sdf/core/normal_cone.h"

namespace hsdf {

namespace {

// The asset's bricks: those built for it before (they depend on the asset only), else built now. A
// grid too large for brick coordinates is reported and gets no bricks (its CellBricks objects
// draw nothing).
CellBricks bricksOf(const SdfAsset& asset, const std::unordered_map<std::uint64_t, CellBuffers::Entry>& built) {
  if (auto old = built.find(asset.id); old != built.end() && old->second.bricksBuilt) return old->second.bricks;
  auto bricks = buildCellBricks(asset.cells);
  if (bricks) return std::move(*bricks);
  engine::log::warn("hermite cells: '{}' cannot be drawn as cell bricks: {}", asset.name, bricks.error().message);
  return {};
}

// The normal cones of the asset's bricks (brick culling), cached like the bricks. Cones that cannot
// be built (they only fail for bricks inconsistent with the stream) are replaced by cones that
// never cull, so the culling pass keeps every brick and the object still draws.
std::vector<shader::CellBrickCone> conesOf(const SdfAsset& asset, const CellBricks& bricks,
                                           const std::unordered_map<std::uint64_t, CellBuffers::Entry>& built) {
  if (auto old = built.find(asset.id); old != built.end() && old->second.bricksBuilt) return old->second.cones;
  auto cones = brickGradientCones(asset.cells, bricks.bricks, bricks.cellRecords);
  if (cones) return std::move(*cones);
  engine::log::warn("hermite cells: '{}': no brick normal cones: {}", asset.name, cones.error().message);
  return std::vector<shader::CellBrickCone>(bricks.bricks.size(), neverCullCone());
}

// The normal cone of each of the asset's cells (cell culling), cached like the bricks' cones.
std::vector<shader::CellBrickCone> cellConesOf(const SdfAsset& asset,
                                               const std::unordered_map<std::uint64_t, CellBuffers::Entry>& built) {
  if (auto old = built.find(asset.id); old != built.end() && old->second.cellConesBuilt) return old->second.cellCones;
  return cellGradientCones(asset.cells);
}

}  // namespace

void HermiteCellFeature::syncAssets(const engine::render::FrameContext& frame) {
  std::vector<std::shared_ptr<const SdfAsset>> wanted;
  std::unordered_set<std::uint64_t> seen;
  std::unordered_set<std::uint64_t> asBricks;  // assets some entity draws as cell bricks
  std::unordered_set<std::uint64_t> asCulledCells;  // ... as culled cells (RenderMethod::Cells, Settings::cullCells)
  bool missing = false;
  frame.registry.view<HermiteSdfRenderable>().each([&](engine::ecs::Entity entity, const HermiteSdfRenderable& r) {
    if (!drawnAsCells(r.method) || !r.asset || r.asset->cells.records.empty()) return;
    const bool bricks = r.method == RenderMethod::CellBricks;
    const bool culledCells = r.method == RenderMethod::Cells && settings_.cullCells;
    if (refused_.contains(r.asset->id)) {
      // The entity still draws the asset the refused one replaced (buildDraws): keep it uploaded.
      if (auto previous = drawnAssets_.find(entity); previous != drawnAssets_.end())
        if (auto kept = buffers_->entries.find(previous->second); kept != buffers_->entries.end()) {
          if (bricks) asBricks.insert(kept->first);
          if (culledCells) asCulledCells.insert(kept->first);
          if (seen.insert(kept->first).second) {
            wanted.push_back(kept->second.asset);
            kept->second.lastFrame = frame.frameNumber;
          }
        }
      return;
    }
    if (bricks) asBricks.insert(r.asset->id);
    if (culledCells) asCulledCells.insert(r.asset->id);
    if (!seen.insert(r.asset->id).second) return;
    wanted.push_back(r.asset);
    auto entry = buffers_->entries.find(r.asset->id);
    if (entry == buffers_->entries.end())
      missing = true;
    else
      entry->second.lastFrame = frame.frameNumber;
  });
  for (std::uint64_t id : asBricks)  // an uploaded asset now drawn as bricks: build its bricks
    if (auto entry = buffers_->entries.find(id); entry != buffers_->entries.end() && !entry->second.bricksBuilt)
      missing = true;
  for (std::uint64_t id : asCulledCells)  // ... now drawn as culled cells: build its cell cones
    if (auto entry = buffers_->entries.find(id); entry != buffers_->entries.end() && !entry->second.cellConesBuilt)
      missing = true;
  const bool runsStale = !wanted.empty() && buffers_->runLength != settings_.maxRunLength &&
                         settings_.maxRunLength != refusedRunLength_;  // the setting changed
  if (!missing && !runsStale) return;

  // View regions call prepare() once per region: an asset an earlier region of this frame drew
  // stays (its draws are recorded already and the next frame draws it again).
  for (const auto& [id, entry] : buffers_->entries)
    if (entry.lastFrame == frame.frameNumber && seen.insert(id).second) wanted.push_back(entry.asset);

  // Rebuild the concatenated buffers with the assets drawn now (assets no longer drawn are dropped).
  // The old buffers may be referenced by commands recorded earlier in this frame and by frames in
  // flight: they are retired below, and freed once this frame has completed (prepare()).
  CellBuffers rebuilt;
  std::vector<CellRecord> full;
  std::vector<CellRecordHalf> half;
  std::vector<shader::CellRunGpu> runs;
  std::vector<shader::CellBrickGpu> bricks;
  std::vector<std::uint32_t> brickCells;
  std::vector<shader::CellBrickCone> cones;
  std::vector<shader::CellBrickCone> cellCones;
  for (const auto& asset : wanted) {
    CellBuffers::Entry entry;
    entry.asset = asset;
    entry.firstRecord = static_cast<std::uint32_t>(full.size());
    if (!buffers_->entries.contains(asset->id)) entry.rows = buildCellRows(asset->cells);  // else moved below
    entry.runs = buildCellRuns(asset->cells, settings_.maxRunLength);
    entry.firstRun = static_cast<std::uint32_t>(runs.size());
    for (shader::CellRunGpu run : entry.runs) {
      run.firstRecord += entry.firstRecord;
      runs.push_back(run);
    }
    const auto old = buffers_->entries.find(asset->id);
    entry.bricksBuilt = asBricks.contains(asset->id) || (old != buffers_->entries.end() && old->second.bricksBuilt);
    if (entry.bricksBuilt) {
      entry.bricks = bricksOf(*asset, buffers_->entries);
      entry.cones = conesOf(*asset, entry.bricks, buffers_->entries);
    }
    cones.insert(cones.end(), entry.cones.begin(), entry.cones.end());
    entry.cellConesBuilt =
        asCulledCells.contains(asset->id) || (old != buffers_->entries.end() && old->second.cellConesBuilt);
    if (entry.cellConesBuilt) {
      entry.cellCones = cellConesOf(*asset, buffers_->entries);
      cellCones.insert(cellCones.end(), entry.cellCones.begin(), entry.cellCones.end());
    } else {
      cellCones.resize(cellCones.size() + asset->cells.records.size(), neverCullCone());
    }
    entry.firstBrick = static_cast<std::uint32_t>(bricks.size());
    for (shader::CellBrickGpu brick : entry.bricks.bricks) {
      brick.firstIndex += static_cast<std::uint32_t>(brickCells.size());
      bricks.push_back(brick);
    }
    for (std::uint32_t record : entry.bricks.cellRecords) brickCells.push_back(entry.firstRecord + record);
    full.insert(full.end(), asset->cells.records.begin(), asset->cells.records.end());
    half.insert(half.end(), asset->cellsHalf.records.begin(), asset->cellsHalf.records.end());
    rebuilt.entries.emplace(asset->id, std::move(entry));
  }
  // Vertex attributes in the prepass; read by address in the resolve pass.
  constexpr VkBufferUsageFlags usage = VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                       VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
  try {
    rebuilt.records[0] = engine::gpu::createBufferWithData(*context_, full.data(), full.size() * sizeof(CellRecord),
                                                           usage, "hermite cells fp32");
    rebuilt.records[1] = engine::gpu::createBufferWithData(*context_, half.data(),
                                                           half.size() * sizeof(CellRecordHalf), usage,
                                                           "hermite cells fp16");
    rebuilt.runs = engine::gpu::createBufferWithData(*context_, runs.data(), runs.size() * sizeof(shader::CellRunGpu),
                                                     VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, "hermite cell runs");
    // Never empty (a zero-sized buffer is invalid): a padding entry no draw reaches.
    if (bricks.empty()) bricks.push_back({});
    if (brickCells.empty()) brickCells.push_back(0);
    if (cones.empty()) cones.push_back({});
    if (cellCones.empty()) cellCones.push_back({});
    rebuilt.bricks = engine::gpu::createBufferWithData(*context_, bricks.data(), bricks.size() * sizeof(shader::CellBrickGpu),
                                                       usage, "hermite cell bricks");
    rebuilt.brickCells = engine::gpu::createBufferWithData(
        *context_, brickCells.data(), brickCells.size() * sizeof(std::uint32_t),
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT, "hermite cell brick cells");
    rebuilt.brickCones = engine::gpu::createBufferWithData(
        *context_, cones.data(), cones.size() * sizeof(shader::CellBrickCone),
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT, "hermite cell brick cones");
    rebuilt.cellCones = engine::gpu::createBufferWithData(
        *context_, cellCones.data(), cellCones.size() * sizeof(shader::CellBrickCone),
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT, "hermite cell cones");
  } catch (const engine::gpu::VulkanError& e) {
    if (e.result() != VK_ERROR_OUT_OF_DEVICE_MEMORY) throw;
    refuseNewAssets(frame, wanted, e.what());  // the old buffers stay: what was drawn is drawn
    return;
  }
  // Only now: a failed allocation above must leave the old entries whole.
  for (auto& [id, entry] : rebuilt.entries)
    if (auto old = buffers_->entries.find(id); old != buffers_->entries.end()) entry.rows = std::move(old->second.rows);
  rebuilt.runLength = settings_.maxRunLength;
  rebuilt.bytes = full.size() * sizeof(CellRecord) + half.size() * sizeof(CellRecordHalf) +
                  runs.size() * sizeof(shader::CellRunGpu) + bricks.size() * sizeof(shader::CellBrickGpu) +
                  brickCells.size() * sizeof(std::uint32_t) +
                  (cones.size() + cellCones.size()) * sizeof(shader::CellBrickCone);
  for (auto& [id, entry] : rebuilt.entries) entry.lastFrame = frame.frameNumber;
  retired_.retire(std::move(buffers_), frame.frameNumber);
  buffers_ = std::make_unique<CellBuffers>(std::move(rebuilt));
  engine::log::debug("hermite cells: {} assets, {} records uploaded", buffers_->entries.size(), full.size());
}

// The rebuilt buffers did not fit in GPU memory. The assets this rebuild was for (new ones, or a
// new run length) are refused for good, each reported once, so later frames neither retry nor
// report them again; the assets already uploaded keep drawing from the old buffers.
void HermiteCellFeature::refuseNewAssets(const engine::render::FrameContext& frame,
                                         const std::vector<std::shared_ptr<const SdfAsset>>& wanted,
                                         const std::string& why) {
  bool refusedAny = false;
  for (const auto& asset : wanted) {
    if (buffers_->entries.contains(asset->id)) continue;
    refused_.insert(asset->id);
    refusedAny = true;
    frame.reportDropped(fmt::format("hermite cells: '{}' ({} cells) is not drawn: out of GPU memory ({})", asset->name,
                                    asset->cells.records.size(), why));
  }
  if (refusedAny) return;
  refusedRunLength_ = settings_.maxRunLength;
  frame.reportDropped(fmt::format("hermite cells: cell runs of length {} are not built: out of GPU memory ({}); the "
                                  "runs of length {} stay",
                                  settings_.maxRunLength, why, buffers_->runLength));
}

}  // namespace hsdf
