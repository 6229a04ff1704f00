// Private to the cell feature's files (cell_feature.cpp, cell_pipelines.cpp, cell_assets.cpp,
// cell_draws.cpp, cell_culling.cpp): the state and helpers more than one of them needs.
#pragma once

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "engine/gpu/buffer.h"
#include "hermite/hermite_host_device.h"
#include "cells/cell_bricks.h"
#include "cells/cell_derived.h"
#include "cells/cell_rows.h"
#include "hermite_sdf/render/cell_feature.h"

namespace hsdf {

using engine::gpu::Buffer;
using engine::gpu::Pipeline;

// Entries of each stream of the cell buffers (cell cones: one per record; brick cones: one per brick).
// Material slots: one per record of the multi-material assets only; palette: their palettes' entries.
struct StreamCounts {
  std::uint32_t records = 0, runs = 0, bricks = 0, brickCells = 0;
  std::uint32_t materialSlots = 0, palette = 0;
};

// The GPU copy of every drawn asset's cell records: one fp32 and one fp16 buffer, each the
// concatenation of the assets' streams, so one vertex-buffer binding serves all objects. A new
// asset is appended while the assets no longer drawn hold less than half of the records (the
// buffers grow by half when short), as are the bricks of an uploaded asset first drawn as bricks;
// they are rebuilt, holding only the assets drawn, when those hold half or more, or the run length
// changes (the kept assets' records copied from the old buffers on the GPU, the new ones written).
struct CellBuffers {
  struct Entry {
    std::shared_ptr<const SdfAsset> asset;
    std::uint32_t firstRecord = 0;  // same index in both buffers
    // The asset's rows and runs (firstRecord relative to the asset's stream): its derived data's
    // (made with the asset, shared by every entry drawing it), or built in the frame for an asset
    // without, and the runs of a run length other than the derived ones'.
    std::shared_ptr<const CellRows> rows;
    std::shared_ptr<const std::vector<shader::CellRunGpu>> runs;
    std::uint32_t firstRun = 0;  // index of (*runs)[0] in the run buffer
    // Whether the asset's bricks and their cones (RenderMethod::CellBricks, brick culling) are in
    // the brick buffers: only for assets some entity draws as bricks, since cells and runs would
    // hold that GPU memory for nothing. Its cells' cones are always in the cell cone buffer (a
    // cone per record either way). Both are the asset's own (SdfAsset::derived, made by the bake
    // job): an upload copies them and builds nothing.
    bool bricksUploaded = false;
    std::uint32_t firstBrick = 0;  // index of bricks()[0] in the brick buffer
    // The bricks in the brick buffers (indices relative to the asset's stream); none unless
    // bricksUploaded.
    const std::vector<shader::CellBrickGpu>& bricks() const;
    // A multi-material asset (SdfAsset::palette): the index of its first record's corner slots in
    // `materialSlots` and of its palette in `palette`; kNoMaterials for one material.
    std::uint32_t firstMaterialSlots = kNoMaterials;
    std::uint32_t firstPaletteEntry = kNoMaterials;
    std::uint64_t lastFrame = 0;           // the last frame that drew the asset
  };
  static constexpr std::uint32_t kNoMaterials = UINT32_MAX;
  std::unordered_map<std::uint64_t, Entry> entries;  // by asset id
  Buffer records[2];
  Buffer runs;  // every asset's runs, firstRecord global (RenderMethod::CellRuns)
  Buffer bricks;      // every asset's CellBrickGpu, firstIndex global (RenderMethod::CellBricks)
  Buffer brickCells;  // the bricks' kept cells: global record indices, brick by brick
  Buffer brickCones;  // CellBrickCone per entry of `bricks`
  Buffer cellCones;   // CellBrickCone per record (same index as `records`); never-cull cones for
                      // an asset without derived data (made by hand)
  // The multi-material assets' corner slots (CellMaterialSlotsGpu, one per record of those assets
  // only) and palettes (HermiteMaterialGpu), read by address in the resolve pass; never made while
  // no drawn asset has materials (then an asset of one material costs nothing more).
  Buffer materialSlots;
  Buffer palette;
  std::uint32_t runLength = 0;  // the maximum run length the runs were built with
  StreamCounts used;            // the entries that hold data; the buffers may have room for more
  std::uint64_t bytes = 0;      // the bytes of those entries
};

// This frame's indirect commands for one record precision: the front-face list, then the
// near-cell list, as ranges of the shared command and draw-data arrays.
struct HermiteCellFeature::Batch {
  std::uint32_t frontFirst = 0, frontCount = 0;
  std::uint32_t nearFirst = 0, nearCount = 0;
  std::uint32_t wireFirst = 0;  // DEBUG_VIEW_WIREFRAME: the front list again with kWireVertices
  std::uint32_t lateFirst = 0;  // occlusion culling: the front list again, drawn in phase 2
  // Culled cells whose kept streams may overflow: the front list again, unculled and empty until
  // the culling pass gives an overflowing row its cells (CellCullRange::fallbackCommand).
  std::uint32_t fallbackFirst = 0, fallbackCount = 0;
};

constexpr VkAccessFlags2 kStorageReadWrite = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;

}  // namespace hsdf
