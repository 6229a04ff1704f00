// The cell feature's indirect draws of a frame: commands per batch, cull ranges, brick draws.
#include "hermite_sdf/render/cell_feature.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <unordered_set>

#include <imgui.h>

#include <fmt/ranges.h>

#include "engine/core/log.h"
#include "engine/core/math.h"
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
#include "render/model_scales.h"
#include "render/near_plane.h"
#include "render/ray_anchor.h"
#include "hermite_sdf/render/lod.h"
#include "hermite_sdf/core/normal_cone.h"

namespace hsdf {

namespace {

// Vertices per instance of every box (cells, thin cells, runs, bricks; box.glsl): the front faces as
// one triangle fan, all six faces (near-plane boxes, drawn by back faces) as one triangle strip: 8
// and 14 vertex-shader invocations per box; the wireframe: the 12 edges.
constexpr std::uint32_t kFanVertices = 8;
constexpr std::uint32_t kStripVertices = 14;
constexpr std::uint32_t kWireVertices = 24;

// The NDC rectangle (x0, y0, x1, y1) that holds the object's grid box on screen, grown by two
// pixels for the proxies' dilation and rasterization; the whole screen when a corner lies at or
// behind the eye plane, where the projection of the box is unbounded.
glm::vec4 screenBounds(const glm::mat4& viewProj, const glm::mat4& model, const Aabb& box, VkExtent2D extent) {
  const glm::vec4 whole(-1.0f, -1.0f, 1.0f, 1.0f);
  glm::vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 p((corner & 1) ? box.max.x : box.min.x, (corner & 2) ? box.max.y : box.min.y,
                       (corner & 4) ? box.max.z : box.min.z);
    const glm::vec4 clip = viewProj * (model * glm::vec4(glm::vec3(p), 1.0f));
    if (!(clip.w > 1e-6f)) return whole;
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    lo = glm::min(lo, ndc);
    hi = glm::max(hi, ndc);
  }
  const glm::vec2 margin(4.0f / float(std::max(extent.width, 1u)), 4.0f / float(std::max(extent.height, 1u)));
  return glm::clamp(glm::vec4(lo - margin, hi + margin), -1.0f, 1.0f);
}

constexpr std::uint32_t kNotCulled = ~0u;

// Twice the most that the proxy box of a cell within two cells of the eye is dilated beyond its
// cell (proxy_dilation.glsl; the object's anisotropy, its largest over its smallest singular value
// (modelScales), widens it in the most shrunk direction's cells). An eye
// inside that dilation but outside the cell sees only the box's back faces, which the front-face
// draw culls: the cell must count as near the eye (drawn by its back faces) though the near plane
// does not reach it. Before, a torus seen from 1e-5 outside a kept cell lost its nearest surface.
// An orthographic camera's proxies are dilated by the same world length at every depth
// (proxy_dilation.glsl), which is `spacing`-dependent in cells: the near plane reaching into a
// cell's dilation cuts its proxy.
double nearDilationCells(const engine::render::CameraView& camera, const ModelScales& scales, double spacing,
                         std::uint32_t viewportHeight) {
  const auto [smallest, largest] = scales;
  const double anisotropy = smallest > 0.0 ? largest / smallest : 1.0;
  if (camera.orthographic()) {
    const double worldPerPixel = double(camera.worldPerPixel(1.0f, viewportHeight));
    const double cells = smallest > 0.0 ? CELL_DILATION_PIXELS * worldPerPixel / (spacing * smallest) : 0.0;
    return 2.0 * std::max(double(CELL_MIN_DILATION), cells * anisotropy);
  }
  // At a view depth of two cells: worldPerPixel = 2 depth / (proj[1][1] H), proj[1][1] = 1 / tan(fovY / 2).
  const double pixels = CELL_DILATION_PIXELS * 2.0 * 2.0 * anisotropy * std::tan(0.5 * double(camera.fovY)) /
                        double(std::max(viewportHeight, 1u));
  return 2.0 * std::max(double(CELL_MIN_DILATION), pixels);
}
constexpr std::size_t kMaxOverlapTestedObjects = 4096;

// The point whose distance orders an object's rows front to back (orderedRows), in grid units: the
// eye; for an orthographic camera, a point far behind its plane along the view axis, from which
// per-axis distance grows with depth along the parallel rays for every cell of the grid (its point
// on the plane would put cells on both sides of it first and last alike).
glm::dvec3 sortEye(const engine::render::CameraView& camera, const glm::mat4& invModel, const glm::dvec3& eyeGrid,
                   const GridSpec& grid) {
  if (!camera.orthographic()) return eyeGrid;
  const glm::dvec3 towardViewer = glm::dmat3(glm::mat3(invModel)) * glm::dvec3(camera.towardViewer()) / grid.spacing;
  const double cells = double(grid.cellsPerAxis());
  const glm::dvec3 centre(0.5 * cells);
  const double beyond = 2.0 * (glm::length(eyeGrid - centre) + 2.0 * cells);
  return eyeGrid + glm::normalize(towardViewer) * beyond;
}

glm::vec4 unite(const glm::vec4& a, const glm::vec4& b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::max(a.z, b.z), std::max(a.w, b.w)};
}

}  // namespace

// The frame's indirect commands and, in step with them, the draw table the shaders read: its
// header, then each command's record. Kept as one array from the start, so the upload copies it
// once (at 10^6 objects the table holds ~10^8 commands).
struct HermiteCellFeature::FrameCommands {
  static constexpr std::size_t kHeaderWords = sizeof(shader::HermiteDrawTableHeader) / sizeof(std::uint32_t);
  std::vector<VkDrawIndirectCommand> commands;
  std::vector<std::uint32_t> table = std::vector<std::uint32_t>(kHeaderWords, 0u);

  std::uint32_t size() const { return static_cast<std::uint32_t>(commands.size()); }
  void append(const std::vector<VkDrawIndirectCommand>& more, const std::vector<std::uint32_t>& records) {
    commands.insert(commands.end(), more.begin(), more.end());
    table.insert(table.end(), records.begin(), records.end());
  }
  // The `count` commands from `first` (a batch's front list) again at the end, each changed by
  // `change`, with their records: the wireframe's, the fallback's and phase 2's lists. Returns
  // where the copy starts.
  template <class Change>
  std::uint32_t appendCopies(std::uint32_t first, std::uint32_t count, Change change) {
    const std::uint32_t start = size();
    for (std::uint32_t i = 0; i < count; ++i) {
      VkDrawIndirectCommand copy = commands[first + i];
      change(copy);
      commands.push_back(copy);
      table.push_back(table[kHeaderWords + first + i]);
    }
    return start;
  }
};

// One frame's draws while buildDraws gathers them, object by object.
struct HermiteCellFeature::FrameDraws {
  std::vector<VkDrawIndirectCommand> commands[kBatches][2];  // [fp32 cells, fp16 cells, runs, bricks][front, near]
  std::vector<std::uint32_t> draws[kBatches][2];     // per command: its record in `records`
  std::vector<shader::HermiteDraw> records;          // one per object (and one for its near cells)
  std::vector<shader::HermiteObject> hermiteObjects;
  std::vector<std::uint32_t> objectIndices;
  std::vector<std::uint32_t> cellCullObject[2];  // per front command of the cell batches: its cull object or kNotCulled
  std::vector<glm::vec4> objectRects;
  bool objectsOverlap = false;  // two cell objects share screen pixels: no early depth (see the header)
  bool drawsBricks = false;     // bricks have no early depth variant: none this frame
  float largestCellPixels = 0.0f;  // of the RenderMethod::Cells objects (ThinBoxes::Auto)
  std::unordered_map<engine::ecs::Entity, std::uint64_t> drawnThisFrame;
  glm::mat4 viewProj{1.0f};
  engine::math::Frustum frustum{};
  ViewAxis axis;  // rayAnchorGrid's
};

// One entity's object while its draws are added: the uploaded entry it draws, its draw record and
// the eye in its grid.
struct HermiteCellFeature::DrawnObject {
  engine::ecs::Entity entity;
  std::uint64_t assetId = 0;
  const CellBuffers::Entry* entry = nullptr;
  glm::mat4 world{1.0f};
  int precision = 0;
  shader::HermiteDraw draw{};
  std::uint32_t record = 0;  // `draw` in FrameDraws::records
  glm::dvec3 eyeGrid{0.0};  // the eye in grid units (an orthographic camera's point)
  glm::dvec3 sortEyeGrid{0.0};  // the point front-to-back order is measured from (sortEye)
  double reachGrid = 0.0;   // how far (in grid units) the near plane reaches around it
};

// This frame's indirect draws of every cell object, uploaded for the prepass, the culling passes and the resolve.
void HermiteCellFeature::buildDraws(engine::render::FrameContext& frame) {
  resetDraws();
  tileSize_ = tileSizeValid(settings_.tileSize) ? settings_.tileSize : CELL_TILE_SIZE;
  if (tileSize_ != settings_.tileSize && !warnedTileSize_) {
    engine::log::warn("hermite cells: tile size {} is not one of {}; drawing {}x{} tiles", settings_.tileSize,
                      fmt::join(kTileSizes, ", "),
                      tileSize_, tileSize_);
    warnedTileSize_ = true;
  }
  FrameDraws f;
  f.viewProj = frame.camera.proj * frame.camera.view;
  f.frustum = engine::math::extractFrustum(f.viewProj);
  f.axis = viewAxis(frame.camera);
  frame.registry.view<HermiteSdfRenderable, engine::scene::WorldTransform>().each(
      [&](engine::ecs::Entity entity, const HermiteSdfRenderable& r, const engine::scene::WorldTransform& world) {
        addObjectDraws(frame, f, entity, r, world.matrix);
      });

  FrameCommands all;
  concatenateBatches(f, all);
  stats_.draws = all.size();
  stats_.drawRecords = static_cast<std::uint32_t>(f.records.size());
  for (shader::BrickCullObject& object : cullObjectList_) object.drawCommand += batches_[kBrickBatch]->frontFirst;
  drawnAssets_.setDrawn(std::move(f.drawnThisFrame));
  if (frame.debugView == DEBUG_VIEW_WIREFRAME) addWireCommands(all);
  chooseCullingPaths(frame, f);
  addFallbackCommands(all);                        // copies of the front lists before they are culled
  cullCellRanges(all.commands, f.cellCullObject);  // after the wireframe's copies, which draw every cell
  if (occlusion_) addLateCommands(all);
  chooseDrawStages(f);
  uploadDraws(frame, f, all);
}

// Which of culling, tiles and occlusion culling this frame uses: what the settings and the device
// allow, and what fits. Each one's GPU memory is had here, before the frame's commands are
// written, so that a refusal changes the path (unculled cells, boxes instead of tiles, culling
// without occlusion) instead of failing the frame.
void HermiteCellFeature::chooseCullingPaths(engine::render::FrameContext& frame, FrameDraws& f) {
  // A frame of more than CELL_TILE_MAX_TILES tiles (16K frames of 8x8 tiles) is past what the
  // tiling's one-workgroup scan walks: boxes.
  const VkExtent2D tileRows = tileGrid(frame.extent, tileSize_);
  const std::uint64_t frameTiles = std::uint64_t(tileRows.width) * tileRows.height;
  const bool culling = settings_.cullCells && !cellCullObjects_.empty();
  tiles_ = culling && context_->capabilities().drawIndirectCount &&
           tilesWanted(settings_.tiles, context_->capabilities().isSoftwareRasterizer) &&
           frameTiles <= CELL_TILE_MAX_TILES;
  // Occlusion's depth margin is relative to depth (occlusionDepthMargin: depth ~ 1 / distance), which
  // an orthographic camera's linear depth does not follow near its far plane: no occlusion culling.
  occlusion_ = culling && settings_.cullOcclusion && !tiles_ && !frame.camera.orthographic();
  std::string refusal;
  if (culling) readKeptDemand(frame.frameSlot);
  const std::array<std::uint64_t, 2> cells = culling ? culledCells(f) : std::array<std::uint64_t, 2>{0, 0};
  releaseIdleSlots(frame);
  const std::array<std::uint64_t, 2> wanted{wantedKeptSlots(0, cells[0]), wantedKeptSlots(1, cells[1])};
  releaseUnneededKeptStreams(frame, wanted);
  const bool refused = culling && !reserveCellCulling(frame.frameSlot, cells, wanted, refusal);
  // The cells whose kept share this slot's totals will hold once the frame is done (none without
  // a culling pass: its totals then say nothing about this frame).
  keptCulledCells_[frame.frameSlot] = refused ? std::array<std::uint64_t, 2>{0, 0} : cells;
  if (refused) {
    dropCellCulling(f);
    tiles_ = occlusion_ = false;
  }
  if (refused != cullingRefused_) {
    if (refused) {
      engine::log::warn("hermite cells: cell culling off, every cell drawn: {}", refusal);
    } else {
      engine::log::info("hermite cells: cell culling back on");
    }
    cullingRefused_ = refused;
  }
  stats_.cullingRefused = refused;
  std::string tilesRefusal;
  tiler_->releaseUnneeded(frame.frameSlot, tiles_, tileEntryEstimate_, settings_.releaseAfterFrames, *frame.retired,
                          frame.slotLastUse());
  if (tiles_ && !tiler_->reserve(frame.frameSlot, frame.extent, tileSize_, tileEntryEstimate_,
                                 std::max(settings_.maxTileEntries, kMinTileEntries), tilesRefusal)) {
    tiles_ = false;  // the culled cells as boxes, as when the lists overflow
    if (!tilesRefused_) engine::log::warn("hermite cells: tiles off, culled cells drawn as boxes: {}", tilesRefusal);
  }
  tilesRefused_ = !tilesRefusal.empty();
  if (historyIdle_.due(!occlusion_ && history_->bytes() > 0, settings_.releaseAfterFrames))
    history_->release(frame.frameNumber, *frame.retired);
  if (occlusion_) {
    // Its buffer did not fit: cull without it.
    if (const engine::Status placed = engine::gpu::allocateOrRefuse([&] { placeHistory(frame); }); !placed) {
      occlusion_ = false;
      if (!warnedHistory_) engine::log::warn("hermite cells: occlusion culling off: {}", placed.error().message);
      warnedHistory_ = true;
    }
  }
}

// Per record precision, the cells of the frame's culled objects: the most the kept streams can be
// asked to hold (each cell is kept in at most one of occlusion culling's phases).
std::array<std::uint64_t, 2> HermiteCellFeature::culledCells(const FrameDraws& f) const {
  std::array<std::uint64_t, 2> cells{0, 0};
  for (int precision = 0; precision < 2; ++precision)
    for (std::size_t i = 0; i < f.cellCullObject[precision].size(); ++i)
      if (f.cellCullObject[precision][i] != kNotCulled) cells[precision] += f.commands[precision][0][i].instanceCount;
  return cells;
}

// The frame's objects drawn without cell culling, as with Settings::cullCells off.
void HermiteCellFeature::dropCellCulling(FrameDraws& f) {
  for (auto& objects : f.cellCullObject) std::fill(objects.begin(), objects.end(), kNotCulled);
  cellCullObjects_.clear();
  cellCullEntities_.clear();
  cellCullFirstRecord_.clear();
  cellCullCells_.clear();
  tileEntryEstimate_ = 0;
  clearKeptStreams();  // no fallback commands either
}

// No kept streams this frame (until reserveCellCulling sizes them): no slots, no fallback commands.
void HermiteCellFeature::clearKeptStreams() {
  for (int precision = 0; precision < 2; ++precision) {
    keptCapacity_[precision] = 0;
    keptFallback_[precision] = false;
  }
  stats_.keptSlots = 0;
  stats_.keptMayFallBack = false;
}

// The stats and culling lists of the previous frame, emptied before this frame's objects fill them.
void HermiteCellFeature::resetDraws() {
  stats_ = Stats{};
  cullObjectList_.clear();
  cullOutputBricks_ = 0;
  cullMaxBricks_ = 0;
  cellCullObjects_.clear();
  cellCullEntities_.clear();
  cellCullFirstRecord_.clear();
  cellCullCells_.clear();
  for (int precision = 0; precision < 2; ++precision) {
    cellCullRanges_[precision].clear();
    batches_[precision]->fallbackCount = 0;
  }
  clearKeptStreams();
  stats_.gpuBytes = buffers_->bytes;
  stats_.uploadedBytes = uploadedBytes_;
  stats_.copiedBytes = copiedBytes_;
  stats_.gpuBytesHeld = buffers_->records[0].size() + buffers_->records[1].size() + buffers_->runs.size() +
                        buffers_->bricks.size() + buffers_->brickCells.size() + buffers_->brickCones.size() +
                        buffers_->cellCones.size();
  tileEntryEstimate_ = 0;
  screenRect_ = glm::vec4(1.0f, 1.0f, -1.0f, -1.0f);  // empty until an object is drawn
}

// One entity's draws: the uploaded asset it draws, its draw record, then its method's commands.
void HermiteCellFeature::addObjectDraws(engine::render::FrameContext& frame, FrameDraws& f, engine::ecs::Entity entity,
                                        const HermiteSdfRenderable& r, const glm::mat4& world) {
  if (!drawsCells(r.method) || !r.asset) return;
  if (!engine::render::drawableTransform(world)) {  // the rays could not be taken into the grid
    stats_.skippedObjects++;
    return;
  }
  auto found = buffers_->entries.find(r.asset->id);
  // An asset not uploaded (refused: its upload did not fit in GPU memory; or still being written
  // in parts) that replaced the entity's field: the field it replaced is still uploaded and is
  // drawn instead, from this very frame on.
  if (found == buffers_->entries.end() && drawsPreviousAsset(r.asset->id))
    if (const std::uint64_t* previous = drawnAssets_.previous(entity)) found = buffers_->entries.find(*previous);
  if (found == buffers_->entries.end()) return;
  f.drawnThisFrame[entity] = found->first;
  // An object whose grid box lies outside the view (or wholly nearer than the near plane) has no
  // pixel: no commands, no culling ranges, no room in the kept streams.
  const Aabb bounds = found->second.asset->cells.grid.bounds();
  if (!engine::math::intersects(f.frustum, world, glm::vec3(bounds.min), glm::vec3(bounds.max))) {
    stats_.culledObjects++;
    return;
  }
  DrawnObject o;
  o.entity = entity;
  o.assetId = found->first;
  o.entry = &found->second;
  o.world = world;
  beginObjectDraw(frame, f, r, o);
  if (r.method == RenderMethod::CellBricks) return addBrickObjectDraws(frame, f, o);
  if (r.method == RenderMethod::CellRuns) return addRunObjectDraws(f, o);
  addCellObjectDraws(frame, f, o);
}

// What the shading pass reads of an object: its records, and a multi-material asset's corner
// slots and palette (0: shaded in the object's colour).
static shader::HermiteObject hermiteObject(const CellBuffers& buffers, const CellBuffers::Entry& entry,
                                          const shader::HermiteDraw& draw, int precision) {
  shader::HermiteObject object{};
  object.gridOriginSpacing = draw.gridOriginSpacing;
  object.records = buffers.records[precision].address();
  object.halfPrecision = std::uint32_t(precision);
  object.flags = draw.flags;
  if (entry.firstMaterialSlots == CellBuffers::kNoMaterials) return object;
  object.materialSlots =
      buffers.materialSlots.address() + VkDeviceAddress(entry.firstMaterialSlots) * sizeof(shader::CellMaterialSlotsGpu);
  object.palette = buffers.palette.address() + VkDeviceAddress(entry.firstPaletteEntry) * sizeof(shader::HermiteMaterialGpu);
  object.firstRecord = entry.firstRecord;
  return object;
}

// The object's GPU scene entry, draw record and Hermite object, its eye in grid units and its
// screen rectangle.
void HermiteCellFeature::beginObjectDraw(engine::render::FrameContext& frame, FrameDraws& f,
                                         const HermiteSdfRenderable& r, DrawnObject& o) {
  const CellBuffers::Entry& entry = *o.entry;
  const GridSpec& grid = entry.asset->cells.grid;  // cells-only assets have no dense field
  o.precision = r.halfPrecision && halfPrecisionFits(grid) ? 1 : 0;  // else fp32, see renderable.h
  const int precision = o.precision;

  shader::ObjectData object = engine::render::GpuScene::makeObject(o.world, r.color, r.roughness, 0.0f, kFeatureId);
  const ModelScales scales = modelScales(o.world);  // once: the dilation on the GPU and the near test here
  object.material.z = float(scales.smallest);       // proxy_dilation.glsl, objectMinScale
  const std::uint32_t objectIndex = frame.scene.addObject(object);
  shader::HermiteDraw& draw = o.draw;
  draw.gridOriginSpacing = glm::vec4(glm::vec3(grid.origin), float(grid.spacing));
  draw.object = objectIndex;
  draw.subdivisions = std::clamp(r.subdivisions, 1u, 64u);
  draw.refineSteps = std::min(r.refineSteps, 16u);
  draw.flags = r.normals == NormalMode::CentralDifferences ? HERMITE_FLAG_NORMALS_CENTRAL : 0u;
  if (r.certified) draw.flags |= HERMITE_FLAG_CERTIFIED;
  if (!settings_.proxyBoxes) draw.flags |= HERMITE_FLAG_WHOLE_CELLS;
  draw.resolution = std::uint32_t(grid.resolution);
  draw.firstCell = entry.firstRecord;
  f.hermiteObjects.push_back(hermiteObject(*buffers_, entry, draw, precision));
  f.objectIndices.push_back(objectIndex);

  // The eye in grid units, and how far (in grid units) the near plane reaches around it.
  o.eyeGrid = eyeInGrid(frame.camera, o.world, grid);
  o.sortEyeGrid = sortEye(frame.camera, object.invModel, o.eyeGrid, grid);
  draw.rayAnchor = glm::vec4(rayAnchorGrid(f.axis, o.world, grid, o.eyeGrid));
  const double dilationCells = nearDilationCells(frame.camera, scales, grid.spacing, frame.extent.height);
  o.reachGrid = double(frame.camera.nearPlaneReachInObject(object.invModel)) / grid.spacing + dilationCells;
  // An orthographic near plane that cannot cut the grid box (grown by the proxies' dilation) cuts
  // no cell: none is near. Its reach around the camera's point spans the whole view, which would
  // make every cell near and draw them all by their back faces.
  const Aabb box = grid.bounds();
  const glm::vec3 dilation(float(dilationCells * grid.spacing));
  if (frame.camera.orthographic() &&
      !nearPlaneMayCut(frame.camera, o.world, glm::vec3(box.min) - dilation, glm::vec3(box.max) + dilation))
    o.reachGrid = -1.0;

  const glm::vec4 rect = screenBounds(f.viewProj, o.world, grid.bounds(), frame.extent);
  // Pairs are compared until one overlaps; past kMaxOverlapTestedObjects the objects are taken to
  // overlap (the early depth stage off: the same image), so that a scene of a million instances
  // does not cost 10^12 comparisons a frame.
  if (!f.objectsOverlap && f.objectRects.size() >= kMaxOverlapTestedObjects) f.objectsOverlap = true;
  if (!f.objectsOverlap) {
    for (const glm::vec4& other : f.objectRects)
      f.objectsOverlap |= rect.x < other.z && other.x < rect.z && rect.y < other.w && other.y < rect.w;
    f.objectRects.push_back(rect);
  }
  screenRect_ = unite(screenRect_, rect);
  stats_.objects++;
  // Runs, bricks and thin cells read their records by address: the draw says which buffer and
  // which precision (the paper's cells ignore it: their records are vertex attributes).
  draw.records = buffers_->records[precision].address();
  if (precision == 1) draw.flags |= HERMITE_FLAG_HALF_RECORDS;
  o.record = addRecord(f, draw);
  f.hermiteObjects.back().drawRecord = o.record;  // the resolve's anchor (cells_resolve.frag)
}

// `draw` as the next record of the frame's draw table, for the commands that share it.
std::uint32_t HermiteCellFeature::addRecord(FrameDraws& f, const shader::HermiteDraw& draw) {
  f.records.push_back(draw);
  return static_cast<std::uint32_t>(f.records.size() - 1);
}

// The object's record with HERMITE_FLAG_NEAR_CELL, for the cells the near plane may cut.
std::uint32_t HermiteCellFeature::addNearRecord(FrameDraws& f, const DrawnObject& o) {
  shader::HermiteDraw nearDraw = o.draw;
  nearDraw.flags |= HERMITE_FLAG_NEAR_CELL;
  return addRecord(f, nearDraw);
}

// RenderMethod::CellBricks: the brick batch's commands, and the object's range of the brick culling pass.
void HermiteCellFeature::addBrickObjectDraws(engine::render::FrameContext& frame, FrameDraws& f, const DrawnObject& o) {
  const CellBuffers::Entry& entry = *o.entry;
  const SdfAsset& asset = *entry.asset;
  f.drawsBricks = true;
  stats_.cells += asset.cells.records.size();
  addBrickDraws(f, entry.bricks(), entry.firstBrick, o);
  if (settings_.cullBricks && !entry.bricks().empty()) {
    // The command just added starts empty and the culling pass counts its kept bricks, which
    // it writes from the object's range of the kept-brick stream on.
    VkDrawIndirectCommand& command = f.commands[kBrickBatch][0].back();
    BrickCuller::ObjectBricks range{entry.firstBrick, command.instanceCount, cullOutputBricks_,
                                    std::uint32_t(f.commands[kBrickBatch][0].size() - 1)};
    cullObjectList_.push_back(
        BrickCuller::cullObject(frame.camera, o.world, asset.cells.grid, asset.boundaryPositive, range));
    cullOutputBricks_ += command.instanceCount;
    cullMaxBricks_ = std::max(cullMaxBricks_, command.instanceCount);
    command.instanceCount = 0;
    command.firstInstance = range.outputFirst;
  }
}

// RenderMethod::CellRuns: the run batch's front commands in row order, and the runs near the eye.
void HermiteCellFeature::addRunObjectDraws(FrameDraws& f, const DrawnObject& o) {
  const CellBuffers::Entry& entry = *o.entry;
  const std::vector<CellRows::Range> rowOrder = orderedRows(*entry.rows, o.sortEyeGrid, settings_.frontToBack);
  for (const CellRows::Range& range : runRanges(*entry.runs, rowOrder)) {
    f.commands[2][0].push_back({kFanVertices, range.count, 0, entry.firstRun + range.first});
    f.draws[2][0].push_back(o.record);
  }
  const std::vector<std::uint32_t> near = runsNearPoint(*entry.runs, o.eyeGrid, o.reachGrid);
  const std::uint32_t nearRecord = near.empty() ? 0 : addNearRecord(f, o);
  for (std::uint32_t run : near) {
    f.commands[2][1].push_back({kStripVertices, 1, 0, entry.firstRun + run});
    f.draws[2][1].push_back(nearRecord);
    stats_.nearCells++;
  }
  stats_.cells += entry.asset->cells.records.size();
  stats_.runs += entry.runs->size();
}

// RenderMethod::Cells: the precision's batch of rows in order (culled cells: ranges of the cell
// culling pass), and the cells near the eye.
void HermiteCellFeature::addCellObjectDraws(engine::render::FrameContext& frame, FrameDraws& f, const DrawnObject& o) {
  const CellBuffers::Entry& entry = *o.entry;
  const SdfAsset& asset = *entry.asset;
  const GridSpec& grid = asset.cells.grid;
  const int precision = o.precision;
  f.largestCellPixels = std::max(f.largestCellPixels, cellPixelsOnScreen(grid, o.world, frame.camera, frame.extent.height));
  // Culled cells: the object's rows become ranges of the culling pass (cullCellRanges), which
  // reads the object's frustum, eye and cone permission from its BrickCullObject.
  std::uint32_t cullObject = kNotCulled;
  if (settings_.cullCells) {
    cullObject = std::uint32_t(cellCullObjects_.size());
    cellCullObjects_.push_back(
        BrickCuller::cullObject(frame.camera, o.world, grid, asset.boundaryPositive, {}));
    cellCullEntities_.emplace_back(o.entity, o.assetId);
    cellCullFirstRecord_.push_back(entry.firstRecord);
    cellCullCells_.push_back(std::uint32_t(asset.cells.records.size()));
    tileEntryEstimate_ +=
        tileEntryEstimate(grid, asset.cells.records.size(), o.world, frame.camera, frame.extent, tileSize_);
  }
  // A culled range is at most CELL_CULL_MAX_RANGE_CELLS cells (one workgroup claims its slots in the
  // kept streams); the pieces of a longer one keep its order.
  const std::uint32_t longest = cullObject == kNotCulled ? ~0u : CELL_CULL_MAX_RANGE_CELLS;
  for (const CellRows::Range& range : orderedRows(*entry.rows, o.sortEyeGrid, settings_.frontToBack)) {
    for (std::uint32_t first = 0; first < range.count; first += longest) {
      const std::uint32_t count = std::min(longest, range.count - first);
      f.commands[precision][0].push_back({kFanVertices, count, 0, entry.firstRecord + range.first + first});
      f.draws[precision][0].push_back(o.record);
      f.cellCullObject[precision].push_back(cullObject);
    }
    stats_.cells += range.count;
  }
  const std::vector<std::uint32_t> near = cellsNearPoint(*entry.rows, asset.cells, o.eyeGrid, o.reachGrid);
  const std::uint32_t nearRecord = near.empty() ? 0 : addNearRecord(f, o);
  for (std::uint32_t record : near) {
    f.commands[precision][1].push_back({kStripVertices, 1, 0, entry.firstRecord + record});
    f.draws[precision][1].push_back(nearRecord);
    stats_.nearCells++;
  }
}

// One upload: [fp32 front][fp32 near][fp16 front][fp16 near][runs front][runs near][bricks front][bricks near].
void HermiteCellFeature::concatenateBatches(const FrameDraws& f, FrameCommands& all) {
  for (int precision = 0; precision < kBatches; ++precision) {
    Batch& batch = *batches_[precision];
    batch.frontFirst = all.size();
    batch.frontCount = static_cast<std::uint32_t>(f.commands[precision][0].size());
    all.append(f.commands[precision][0], f.draws[precision][0]);
    batch.nearFirst = all.size();
    batch.nearCount = static_cast<std::uint32_t>(f.commands[precision][1].size());
    all.append(f.commands[precision][1], f.draws[precision][1]);
  }
}

// DEBUG_VIEW_WIREFRAME: every batch's front list again, drawn as the boxes' edges (cells, runs,
// bricks). A brick command the culling pass fills starts with no instance: its wireframe copy draws
// all of the object's bricks from the brick stream, as the cells' copies draw every cell.
void HermiteCellFeature::addWireCommands(FrameCommands& all) {
  for (int b = 0; b < kBatches; ++b) {
    Batch& batch = *batches_[b];
    batch.wireFirst = all.appendCopies(batch.frontFirst, batch.frontCount,
                                       [](VkDrawIndirectCommand& wire) { wire.vertexCount = kWireVertices; });
  }
  const Batch& bricks = *batches_[kBrickBatch];
  for (const shader::BrickCullObject& object : cullObjectList_) {
    VkDrawIndirectCommand& wire = all.commands[bricks.wireFirst + (object.drawCommand - bricks.frontFirst)];
    wire.instanceCount = object.brickCount;
    wire.firstInstance = object.firstBrick;
  }
}

// The stages that depend on all of the frame's objects: thin boxes and the early depth stage.
void HermiteCellFeature::chooseDrawStages(const FrameDraws& f) {
  thinBoxes_ = thinBoxesWanted(settings_.thinBoxes, context_->capabilities().isSoftwareRasterizer, f.largestCellPixels);
  stats_.thinBoxes = thinBoxes_;
  stats_.largestCellPixels = f.largestCellPixels;
  // Occlusion culling keeps the early depth stage off: the stage leaves the boxes' face depths in
  // the depth buffer until its fix-up, so phase 1 would need its fix-up before the pyramid and
  // phase 2 an early stage and a fix-up of its own over pixels that phase 1 already made final.
  // Culling removes the hidden boxes the stage only made cheaper (on lavapipe; on GPUs the stage
  // gains nothing).
  earlyDepth_ = earlyDepthWanted(settings_.earlyDepth, context_->capabilities().isSoftwareRasterizer) &&
                stats_.draws > 0 && !f.objectsOverlap && !f.drawsBricks && !thinBoxes_ && !occlusion_ && !tiles_;
  stats_.tiles = tiles_;
}

// This frame slot's commands, draw table (records, then the header and each command's record) and
// Hermite objects, and each object's payload address.
void HermiteCellFeature::uploadDraws(engine::render::FrameContext& frame, const FrameDraws& f, FrameCommands& all) {
  if (!all.commands.empty()) {
    indirect_.upload(frame.frameSlot, all.commands);
    drawRecords_.upload(frame.frameSlot, f.records);
    const shader::HermiteDrawTableHeader header{drawRecords_.address(frame.frameSlot), 0};
    std::memcpy(all.table.data(), &header, sizeof(header));
    drawData_.upload(frame.frameSlot, all.table);
  }
  if (!f.hermiteObjects.empty()) {
    objects_.upload(frame.frameSlot, f.hermiteObjects);
    const VkDeviceAddress base = objects_.address(frame.frameSlot);
    for (std::size_t i = 0; i < f.objectIndices.size(); ++i)
      frame.scene.object(f.objectIndices[i]).payload = base + i * sizeof(shader::HermiteObject);
  }
}

// The front-face commands of culled cells (cullObjects: per command of the two cell batches) become
// the culling pass's ranges: each command then draws its range's kept cells, wherever in the kept
// streams the pass appends them, from an instance count of 0 that the pass overwrites. The ranges
// take the commands' order, so the rows stay front to back.
void HermiteCellFeature::cullCellRanges(std::vector<VkDrawIndirectCommand>& commands,
                                        const std::vector<std::uint32_t> cullObjects[2]) {
  for (int precision = 0; precision < 2; ++precision) {
    const Batch& batch = *batches_[precision];
    for (std::uint32_t i = 0; i < batch.frontCount; ++i) {
      if (cullObjects[precision][i] == kNotCulled) continue;
      VkDrawIndirectCommand& command = commands[batch.frontFirst + i];
      const std::uint32_t object = cullObjects[precision][i];
      // The range's first cell in the history: its object's base plus the cell's index in its asset.
      const std::uint32_t historyFirst =
          occlusion_ ? historyBase_[object] + (command.firstInstance - cellCullFirstRecord_[object]) : 0;
      const std::uint32_t fallback = keptFallback_[precision] ? batch.fallbackFirst + i : ~0u;
      cellCullRanges_[precision].push_back(
          {command.firstInstance, command.instanceCount, fallback, batch.frontFirst + i, object, historyFirst, 0, 0});
      command.instanceCount = 0;
      command.firstInstance = 0;
    }
  }
}

// Where the kept streams may not hold every culled cell (keptFallback_), each culled front command
// again, unculled and with no instance, for the culling pass to fill where the row does not fit
// (CellCullRange::fallbackCommand).
void HermiteCellFeature::addFallbackCommands(FrameCommands& all) {
  for (int precision = 0; precision < 2; ++precision) {
    Batch& batch = *batches_[precision];
    batch.fallbackCount = keptFallback_[precision] ? batch.frontCount : 0;
    batch.fallbackFirst = all.appendCopies(batch.frontFirst, batch.fallbackCount,
                                           [](VkDrawIndirectCommand& fallback) { fallback.instanceCount = 0; });
  }
}

// This view region's places in the visibility history for this frame's culled objects.
void HermiteCellFeature::placeHistory(engine::render::FrameContext& frame) {
  std::vector<CellHistory::Object> objects;
  for (std::size_t i = 0; i < cellCullEntities_.size(); ++i)
    objects.push_back({cellCullEntities_[i].first, cellCullEntities_[i].second, cellCullCells_[i]});
  const std::uint32_t regions = std::max(1u, frameSlots_ / std::max(1u, frame.framesInFlight));
  historyBase_ = history_->place(*context_, frame.cmd, objects, frame.viewRegionIndex, regions,
                                 frame.frameNumber, *frame.retired);
}

// Phase 2's commands: the culled front lists again (every front command of the two cell batches is
// culled when occlusion culling is on), each drawing the cells the late culling pass appends for
// its range, from an instance count of 0 that the pass overwrites.
void HermiteCellFeature::addLateCommands(FrameCommands& all) {
  for (int precision = 0; precision < 2; ++precision) {
    Batch& batch = *batches_[precision];
    batch.lateFirst = all.appendCopies(batch.frontFirst, batch.frontCount, [](VkDrawIndirectCommand&) {});
  }
}

// The size on screen, in pixels, of one cell of `grid` placed by `world`, seen from the camera at
// the distance of the grid box's centre (ThinBoxes::Auto: a typical cell of the object, not its
// nearest one as the levels of detail take).
float HermiteCellFeature::cellPixelsOnScreen(const GridSpec& grid, const glm::mat4& world,
                                             const engine::render::CameraView& camera, std::uint32_t viewportHeight) {
  const float scale = largestAxisScale(world);
  const glm::vec3 centre = glm::vec3(world * glm::vec4(glm::vec3(grid.bounds().center()), 1.0f));
  return projectedPixels(scale * float(grid.spacing), glm::length(camera.position - centre), camera, viewportHeight);
}

// At most how many tile entries the object's cells make (cell_tiles.comp): every cell as large on
// screen as one at the grid box's point nearest the eye, its rectangle grown by the dilation and the
// pixel of slack; a box the eye may be inside spans the screen. An upper bound, so that a frame
// slot's first tiled frame has room for every entry; later frames size the lists by what the
// slot's last frame needed, scaled by this estimate's growth (CellTiler::wantedEntries).
std::uint64_t HermiteCellFeature::tileEntryEstimate(const GridSpec& grid, std::uint64_t cells, const glm::mat4& world,
                                                    const engine::render::CameraView& camera, VkExtent2D extent,
                                                    std::uint32_t tileSize) {
  const VkExtent2D tiles = tileGrid(extent, tileSize);
  const std::uint64_t tileCount = std::uint64_t(tiles.width) * tiles.height;
  const Aabb box = grid.bounds();
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 corner((c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y,
                            (c & 4) ? box.max.z : box.min.z);
    const glm::vec3 p = glm::vec3(world * glm::vec4(glm::vec3(corner), 1.0f));
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const float distance = glm::length(glm::max(glm::max(lo - camera.position, camera.position - hi), glm::vec3(0.0f)));
  if (distance <= 2.0f * camera.znear) return cells * tileCount;
  const float pixels =
      projectedPixels(largestAxisScale(world) * float(grid.spacing) * 1.7320508f, distance, camera, extent.height);
  const auto span = std::uint64_t(std::ceil((pixels + 4.0f) / float(tileSize))) + 1;
  return cells * std::min(span * span, tileCount);
}

// A CellBricks object: one command for all its bricks (firstInstance = its first brick; the brick
// culling pass will write instanceCount), and the bricks the near plane may cut by back faces.
void HermiteCellFeature::addBrickDraws(FrameDraws& f, const std::vector<shader::CellBrickGpu>& bricks,
                                       std::uint32_t firstBrick, const DrawnObject& o) {
  const auto count = static_cast<std::uint32_t>(bricks.size());
  if (count == 0) return;  // reported when the bricks could not be built
  f.commands[kBrickBatch][0].push_back({kFanVertices, count, 0, firstBrick});
  f.draws[kBrickBatch][0].push_back(o.record);
  const std::vector<std::uint32_t> near = bricksNearPoint(bricks, o.eyeGrid, o.reachGrid);
  const std::uint32_t nearRecord = near.empty() ? 0 : addNearRecord(f, o);
  for (std::uint32_t brick : near) {
    f.commands[kBrickBatch][1].push_back({kStripVertices, 1, 0, firstBrick + brick});
    f.draws[kBrickBatch][1].push_back(nearRecord);
    stats_.nearCells++;
  }
  stats_.bricks += count;
}

}  // namespace hsdf
