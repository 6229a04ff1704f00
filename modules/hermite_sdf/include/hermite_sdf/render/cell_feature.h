#pragma once
// The paper's renderer as an engine RenderFeature: every entity with a HermiteSdfRenderable whose
// method is a cell method (Cells, CellRuns, CellBricks) and a WorldTransform is drawn from its kept
// cells. In the paper's form (Settings::thinBoxes off, tiles off) each cell is an instanced box whose
// Hermite data (8 corners x (f, grad f) + cell coordinate) arrive as instance-rate vertex
// attributes from one GPU cell buffer; the other forms (thin boxes, runs, bricks, tiles: below)
// read the same records by buffer device address. Each form has its pipelines (plain, near,
// counted, early), and each pass draws each form's objects with one indirect multi-draw per list
// (front, near, occlusion culling's late list, culling's fallback); per-draw data (object index, grid, subdivisions) is read
// through buffer device address.
//
// Depth prepass: the fragment shader clips the pixel's ray to its cell (and the near plane), finds
// the first root by n equidistant evaluations + linear interpolation + safeguarded Newton steps and
// hands on the hit's depth (early depth, below; else gl_FragDepth with conservative depth: the hit
// is never nearer than the front face), plus the visibility id and the hit's offset from the rays'
// anchor (RendererFormats::hitOffset, pixelRayHitOffset). Boxes are drawn by their front
// faces (one triangle fan of 8 vertices around the corner nearest the eye); cells the near plane may cut are drawn
// by their back faces with a non-conservative variant, so a camera inside the object or inside a
// cell loses no surface.
// Shading pass: each pixel is shaded once: a resolve over the objects' screen bounds reads the visibility buffer
// (object, cell record) and the hit offset, fetches that cell's record by buffer device address,
// rebuilds the hit on the pixel's ray from the anchor and shades it with the exact normal of the
// interpolant.
// Transforms: any invertible affine world matrix (mirroring, non-uniform scale, shear); mirrored
// objects keep their front faces through OBJECT_FLAG_MIRRORED (shaders/hermite/box.glsl).
// Submission order: rows of cells are sorted front to back by the camera's octant so that early
// depth testing rejects hidden cells (switchable, to measure the effect).
// Prepass variants (shaders/hermite/hit_depth.glsl): the production pipelines' fragment shaders
// hold no `discard` and no buffer write (a miss writes the far plane's depth), since on a GPU a
// shader that merely contains either loses early depth rejection (on an H100 that halved the
// prepass); frames that count work (the renderer's work counters, the evaluation heat map) use the
// *_counted variants, and the early depth stage its own *_early variants.
// Early depth (Settings::earlyDepth; Auto: on for software rasterizers only): the boxes are drawn
// in the renderer's early depth stage at the depth of their own faces, so a box behind an already
// found hit fails an early depth test and never runs its search. That pays on lavapipe, which
// shades 4x4 blocks in submission order (40-60 % of the prepass), and not on an H100, where
// fragments run in parallel and out of order and the stage's atomicMax costs early rejection
// (../shared/gpu/h100-b505968/README.md §3b). The hits' true depths go to a per-pixel buffer
// that a fix-up pass writes into the depth buffer before any other prepass draw. Within one object
// the nearest face with a hit belongs to the box with the nearest hit; between objects it need
// not, so a frame whose cell objects overlap on screen draws them by depth as before.
// RenderMethod::CellRuns objects are drawn by the same feature from the same record buffers: one
// box per run of kept cells along x (runs.vert), walked cell by cell in the fragment shader with
// the same search (runs_depth.glsl), records read by address; the shading pass is shared.
// RenderMethod::CellBricks objects likewise: one box per brick of 4x4x4 cells holding a kept cell
// (bricks.vert: 8 vertices, 12 bytes of varyings), whose kept cells the fragment shader walks along
// the ray (bricks_depth.glsl); one indirect command per object (firstInstance = its first brick).
// Bricks have no early depth variant: a frame that draws bricks keeps the early depth stage off.
// Settings::thinBoxes draws RenderMethod::Cells with 8 vertices and 12 bytes of varyings per box
// (cells_thin.vert), the records read by address; no early depth variant either.
// Settings::tiles draws the culled RenderMethod::Cells objects as screen tiles instead of boxes
// (src/render/cell_tiler.h: the kept cells binned into 8x8-pixel tiles by a compute pass, one
// point per non-empty tile whose fragments search the tile's cells nearest first); no early depth
// stage and no occlusion culling in frames that draw tiles.
#include <algorithm>
#include <array>
#include <cstdint>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "engine/ecs/entity.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/deferred_release.h"
#include "engine/gpu/indirect_draws.h"
#include "engine/gpu/lazy_pipeline.h"
#include "engine/gpu/memory.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/pixel_buffer.h"
#include "engine/render/drawn_per_region.h"
#include "engine/render/per_frame_buffer.h"
#include "engine/render/region_stats.h"
#include "engine/render/render_feature.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/render/renderable.h"
#include "hermite/hermite_host_device.h"

namespace hsdf {

struct CellBuffers;  // the uploaded assets (src/render/cell_feature_internal.h)

// A switch the device may decide: Auto (each setting below says for which devices it is on), On,
// Off. One type for the early depth stage, thin boxes and tiles, so that a program reads, writes and
// shows each of them as one kind of value (the samples' settings had four copies of it).
enum class AutoSwitch : std::uint8_t { Auto, On, Off };

class HermiteCellFeature final : public engine::render::RenderFeature {
 public:
  static constexpr std::uint32_t kFeatureId = 2;

  // Whether the boxes are tested at their faces' depth in the early depth stage (see above).
  using EarlyDepth = AutoSwitch;
  // Auto: on exactly for software rasterizers (context.capabilities().isSoftwareRasterizer).
  static bool earlyDepthWanted(EarlyDepth mode, bool softwareRasterizer) {
    return mode == EarlyDepth::On || (mode == EarlyDepth::Auto && softwareRasterizer);
  }

  // Whether RenderMethod::Cells objects are drawn as thin boxes (Settings::thinBoxes). Measured on
  // an H200 (docs/perf/nvidia-h200/): thin boxes cost 10 % more than the paper's where a cell
  // covers ~20 pixels (the bunny at K = 32, 1080p), the same at ~10, 18 % less at ~5 and 42 % less
  // at ~2.5: per box the varyings cost, per fragment the loads by address. Auto: on for hardware
  // rasterizers when the frame's largest cell (kThinBoxesMaxCellPixels, cellPixelsOnScreen) is
  // small; off for software rasterizers, which lose their early depth stage with them (lavapipe:
  // 3-7x the prepass).
  using ThinBoxes = AutoSwitch;
  static constexpr float kThinBoxesMaxCellPixels = 8.0f;
  static bool thinBoxesWanted(ThinBoxes mode, bool softwareRasterizer, float largestCellPixels) {
    return mode == ThinBoxes::On ||
           (mode == ThinBoxes::Auto && !softwareRasterizer && largestCellPixels <= kThinBoxesMaxCellPixels);
  }

  // Whether the culled RenderMethod::Cells objects are drawn as screen tiles (Settings::tiles): the
  // culling pass's kept cells binned into 8x8-pixel tiles (Settings::tileSize; cell_tiles.comp), one quad per tile whose
  // fragments search the tile's cells. Same cells, same search, same image; one fragment per pixel
  // instead of one per box and pixel. Auto: on for software rasterizers, which shade and count whole
  // 4x4 blocks (a box of a few pixels costs 16-64 invocations there; the <= 3 fragment
  // invocations per covered pixel); off for GPUs until one has measured it. Tiles need
  // vkCmdDrawIndirectCount (Vulkan 1.2's drawIndirectCount; their overflow falls back to boxes
  // on the GPU): a device without it draws boxes.
  using Tiles = AutoSwitch;
  static bool tilesWanted(Tiles mode, bool softwareRasterizer) {
    return mode == Tiles::On || (mode == Tiles::Auto && softwareRasterizer);
  }

  struct Settings {
    bool frontToBack = true;  // sort rows of cells by the view octant
    EarlyDepth earlyDepth = EarlyDepth::Auto;
    bool heatMapCounters = true;  // count evaluations per pixel when the debug view asks for it
    // RenderMethod::CellRuns: the most cells one run's box covers. Longer runs mean fewer, larger
    // boxes and longer walks per fragment.
    std::uint32_t maxRunLength = kDefaultMaxRunLength;
    // RenderMethod::CellBricks: a compute pass before the prepass keeps only the bricks inside the
    // frustum that may hold a first hit (normal cones, hermite_sdf/core/normal_cone.h); off draws every
    // brick (to measure what it removes).
    bool cullBricks = true;
    // RenderMethod::Cells: the same compute pass for the cells (cell_cull.comp, each cell with its
    // own normal cone): only the kept cells' boxes are drawn, in the rows' order (front-to-back
    // stays); off draws every cell's box. Cell-bricks and runs ignore it.
    bool cullCells = true;
    // With cullCells: two-phase occlusion culling of the cells against the depth pyramid (the
    // scheme of zeux/niagara; cell_cull.comp): the cells visible in this view region's previous
    // frame are drawn first, the renderer builds the pyramid of that depth, every other cell is
    // tested against it and only those that may be visible are drawn after. Same image. The
    // early depth stage is off in frames that use it (see buildDraws). Bricks and runs ignore it.
    // Off by default: on the bunny it removes only 4-8 % of the boxes the frustum and cones keep
    // (docs/perf/cells-breakdown-lavapipe.md), at the price of the early depth stage on lavapipe
    // and of a depth copy, a pyramid and a second culling pass on every device; no GPU has
    // measured it yet.
    bool cullOcclusion = false;
    // Cells, runs and bricks: each kept cell is drawn (boxes, tiles) and searched over its proxy
    // box, the part of the cell that can hold its zero set (cells.h, "Proxy boxes"): the same
    // roots, ~0.57x the boxes' surface on the bunny, so fewer box fragments, tile entries and
    // searches. Off: the paper's proxy, the whole cell.
    bool proxyBoxes = true;
    // RenderMethod::Cells: each box's vertices hand on 12 bytes (cells_thin.vert), the fragment
    // shader reading the cell's record by address (cells_thin_depth.glsl), instead of the paper's
    // Hermite data as varyings. Same search, same image. Thin boxes have no early depth variant:
    // a frame that draws them keeps the stage off. See ThinBoxes for Auto.
    ThinBoxes thinBoxes = ThinBoxes::Auto;
    // RenderMethod::Cells with cullCells: screen tiles instead of boxes (see Tiles). Occlusion
    // culling and the early depth stage are off in frames that draw tiles; the cells the near plane
    // may cut are still drawn as boxes too.
    Tiles tiles = Tiles::Auto;
    // The tiles' side in pixels: 4, 8 or 16 (tileSizeValid; another value draws 8). Smaller tiles
    // list fewer cells a pixel cannot see (each fragment reads its tile's list) but make more
    // tiles to bin, sort and draw.
    std::uint32_t tileSize = CELL_TILE_SIZE;
    // The most tile-list entries (16 bytes each, held twice: the scatter's and the sorted lists)
    // per frame slot. A frame whose tiles need more draws its culled cells as boxes instead (the
    // same image, decided on the GPU: CellTileTotals::boxDrawCount) and logs it; the lists grow to
    // what a frame needed, up to this. At least kMinTileEntries.
    std::uint32_t maxTileEntries = 1u << 23;
    // RenderMethod::Cells with cullCells: the bytes per frame slot and record precision up to which
    // the kept-cell streams (cell_cull.comp's copies of the kept records, their record and range
    // indices) hold every cell of the frame's culled objects, so that no row can fall back. Past
    // it (scenes of many instances: 10,000 bunnies at K = 32 would want 5.9 GB) they hold the
    // frame's culled cells times the share the slot's previous culling frame kept (0.6 before one
    // has) with a quarter to spare, at least this: a row whose kept cells no longer fit is drawn
    // whole and unculled (the same image, more boxes; BrickCullTotals::fallbackCells) and the
    // next frames' streams grow to what the frame wanted.
    std::uint64_t keptStreamBytes = std::uint64_t(256) << 20;
    // The buffers sized by earlier frames give memory back after this many of a frame slot's
    // frames in a row that did not want them: its kept-cell streams of a precision larger than
    // keptStreamBytes and more than four times what its frames want (a smaller scene, objects out
    // of view, a lower K), or any while the slot culls no cell of that precision (culling off, a
    // tracer); its tile lists larger than 2^20 entries and more than four times what its frames
    // want, or any while it draws no tiles; occlusion culling's history after as many frames
    // without occlusion culling; the assets no entity has drawn as cells for as many frames
    // (destroyed, given another asset or a tracer) once they hold at least half of the uploaded
    // records, or when no asset is drawn any more (dropping them re-uploads the rest: at half, the
    // uploads stay within twice what is dropped; a new asset is appended beside them until then, and
    // comes with that rebuild past it); and every buffer of a frame slot not prepared for as many
    // frames (a view region no longer drawn: the split screen turned off). The next frame that
    // needs them makes them at its size.
    // Otherwise they only grow: a camera that swings back and forth does not reallocate them.
    std::uint32_t releaseAfterFrames = 120;
    // From the second frame with objects of this module (drawn here or by a tracer:
    // hasSdfObjects) on, the pipelines a switch of method or record precision would need next are
    // compiled on a worker thread at low priority (warmPipelines()), so that the frame after the
    // switch binds them instead of compiling them; after a shader reload, from the next frame.
    // Off: that frame compiles them (tens to hundreds of milliseconds on the render thread).
    bool warmPipelines = true;
    // The most bytes of cell records (fp32, fp16 and the cell's cone: kRecordUploadBytes a cell)
    // one frame writes into the GPU buffers when new assets come: a larger asset is written over
    // several frames, one new asset after another, at least one record a frame, and drawn from the
    // frame its last records are in, never half uploaded (until then its entity draws the asset it
    // replaced in that view region, if that is still uploaded, or nothing). That frame also writes the asset's runs,
    // bricks and material slots (small beside the records). A rebuild (a new run length, idle
    // assets dropped) copies the records of the assets it keeps on the GPU (Stats::copiedBytes)
    // and writes only the new ones, under this budget too; 0: no limit.
    std::uint64_t uploadBytesPerFrame = std::uint64_t(32) << 20;
  };
  // The bytes a cell costs in Settings::uploadBytesPerFrame: its fp32 and fp16 records and its cone.
  static const std::uint64_t kRecordUploadBytes;
  static constexpr std::uint32_t kMinTileEntries = 64;
  static constexpr std::uint32_t kTileSizes[] = {4, 8, 16};  // the sides Settings::tileSize may take
  static bool tileSizeValid(std::uint32_t size) {
    return std::find(std::begin(kTileSizes), std::end(kTileSizes), size) != std::end(kTileSizes);
  }
  struct Stats {
    std::uint32_t objects = 0;
    std::uint64_t cells = 0;        // instances drawn in the last frame
    std::uint32_t draws = 0;        // indirect commands in the last frame
    // HermiteDraw records of its draw table: one per object, one more for an object with near
    // cells; every command of an object shares them (HermiteDrawTableHeader).
    std::uint32_t drawRecords = 0;
    std::uint32_t nearCells = 0;    // cells (or runs) drawn by their back faces
    std::uint64_t runs = 0;         // run boxes of RenderMethod::CellRuns objects (their cells are in `cells`)
    std::uint64_t bricks = 0;       // brick boxes of RenderMethod::CellBricks objects (their cells are in `cells`)
    std::uint32_t skippedObjects = 0;  // transform not invertible (e.g. scaled to zero): not drawn
    std::uint32_t culledObjects = 0;   // grid box outside the view: not drawn
    std::uint64_t gpuBytes = 0;     // cell buffers: the bytes of the uploaded assets
    std::uint64_t gpuBytesHeld = 0; // cell buffers: their size (room for assets appended later)
    // Bytes of cell buffers uploaded from the CPU since initialize(): a new asset adds its own
    // (appended), a rebuild the new assets' and every kept asset's runs, bricks and materials.
    std::uint64_t uploadedBytes = 0;
    // Bytes of cell records (fp32, fp16, cell cones) a rebuild copied on the GPU from the old
    // buffers since initialize(): the assets it kept.
    std::uint64_t copiedBytes = 0;
    bool earlyDepth = false;        // the last frame drew the boxes in the early depth stage
    bool countedVariant = false;    // the last frame's prepass used the *_counted pipelines
    bool thinBoxes = false;         // the last frame drew its RenderMethod::Cells objects as thin boxes
    float largestCellPixels = 0.0f; // of those objects: the largest cell's size on screen, pixels
    bool tiles = false;             // the last frame drew its culled RenderMethod::Cells objects as tiles
    // Settings::cullCells was on but the last frame drew every cell unculled: its frame slot held
    // no kept-cell streams and not even streams of a few thousand cells fitted in GPU memory, the
    // allocator's budget or one buffer (see reserveCellCulling).
    bool cullingRefused = false;
    // The kept-cell streams' slots this frame (both precisions) and whether they hold fewer than
    // the culled objects' cells (Settings::keptStreamBytes): then rows may fall back.
    std::uint64_t keptSlots = 0;
    bool keptMayFallBack = false;
    // The bytes held by the buffers sized by earlier frames (Settings::releaseAfterFrames): every
    // frame slot's kept-cell streams, its tile lists with their tiles, and occlusion culling's
    // visibility history.
    std::uint64_t keptStreamBytesHeld = 0;
    std::uint64_t tileListBytesHeld = 0;
    std::uint64_t historyBytesHeld = 0;
  };

  HermiteCellFeature();
  ~HermiteCellFeature() override;
  std::string_view name() const override { return "hermite cells"; }
  engine::Status initialize(const engine::gpu::Context& context, const engine::render::RendererFormats& formats,
                            std::uint32_t framesInFlight) override;
  void prepare(engine::render::FrameContext& frame) override;
  void recordPass(engine::render::PassContext& pass) override;
  bool usesEarlyDepth() const override { return earlyDepth_; }
  void recordEarlyDepth(engine::render::PassContext& pass) override;
  void recordEarlyDepthResolve(engine::render::PassContext& pass) override;
  bool usesOcclusionCulling() const override { return occlusion_; }
  void recordLateCulling(engine::render::PassContext& pass, const engine::render::DepthPyramidView& pyramid) override;
  void drawUi() override;
  engine::Status reloadShaders() override;
  engine::Status createAllPipelines() override;
  // The feature's pipelines: described at creation, compiled when a frame first draws with one.
  engine::gpu::PipelineCounts pipelineCounts() { return engine::gpu::countPipelines(pipelines_.all()); }
  // Waits until the pipelines being warmed (Settings::warmPipelines) are compiled; none: returns.
  void waitForWarmPipelines();

  Settings& settings() { return settings_; }
  const Stats& stats() const { return stats_; }
  // Every view region's stats of the last frame, in drawing order (stats() is the last region's).
  std::vector<Stats> regionStats() const { return regionStats_.all(stats_); }
  // The last culling passes' counts (bricks and culled cells tested, kept, culled by frustum and
  // by cone, the two passes summed); valid once the frame that recorded them has completed (e.g.
  // after Renderer::finish), zero when that frame culled nothing.
  shader::BrickCullTotals cullTotals() const;
  // The tile draw of the last tiled frame (Stats::tiles): its non-empty tiles (instanceCount) and the
  // entries its lists needed; valid once that frame has completed, zero without tiles.
  shader::CellTileTotals tileTotals() const;
  // Whether the cells of `assetId` were refused (their upload did not fit in GPU memory): the
  // asset is not drawn, and tried again only once memory has been given back or the budget raised
  // (engine::gpu::MemoryRefusal). An entity whose asset was refused keeps drawing the asset
  // it drew before, if any (a re-bake past the budget: no frame without the object); the caller
  // can put that asset back into the component (the Viewer does, so the tuning names it).
  bool refused(std::uint64_t assetId) const { return refused_.contains(assetId); }
  // Whether a new asset is being uploaded over several frames (Settings::uploadBytesPerFrame) and
  // is not drawn yet.
  bool uploading() const;

 private:
  static float cellPixelsOnScreen(const GridSpec& grid, const glm::mat4& world, const engine::render::CameraView& camera,
                                 std::uint32_t viewportHeight);
  struct AssetRows;
  struct Batch;
  struct AssetDemand;
  struct AssetUpload;
  struct FrameDraws;
  struct FrameCommands;
  struct DrawnObject;
  void syncAssets(const engine::render::FrameContext& frame);
  bool idleAssetsToDrop(const engine::render::FrameContext& frame) const;  // Settings::releaseAfterFrames
  AssetDemand collectAssetDemand(const engine::render::FrameContext& frame);
  void appendAsset(CellBuffers& rebuilt, AssetUpload& u, const std::shared_ptr<const SdfAsset>& asset,
                   const AssetDemand& d) const;
  bool appendNewAssets(const engine::render::FrameContext& frame, const AssetDemand& d);
  void createAssetBuffers(CellBuffers& rebuilt, const AssetUpload& u) const;
  void copyResidentRecords(const engine::render::FrameContext& frame, std::unique_ptr<CellBuffers> old,
                           const AssetUpload& u);
  void settlePendingCopies(const engine::render::FrameContext& frame);
  void commitAssetBuffers(const engine::render::FrameContext& frame, CellBuffers rebuilt, const AssetUpload& u);
  void refuseNewAssets(const engine::render::FrameContext& frame,
                       const std::vector<std::shared_ptr<const SdfAsset>>& wanted, const std::string& why,
                       VkDeviceSize needed);
  void forgetRefusalsThatMayFit();
  void uploadInParts(const engine::render::FrameContext& frame, AssetDemand& d);
  bool anotherRegionsPartial(const engine::render::FrameContext& frame) const;
  bool partsWait(const engine::render::FrameContext& frame, const SdfAsset& first) const;
  bool writeRecordPart(const engine::render::FrameContext& frame, std::uint32_t count);
  void carryPartialUpload(AssetUpload& u) const;
  bool drawsPreviousAsset(std::uint64_t assetId) const;
  void keepPreviousAsset(const engine::render::FrameContext& frame, engine::ecs::Entity entity, bool bricks,
                         AssetDemand& d);
  void buildDraws(engine::render::FrameContext& frame);
  void resetDraws();
  void addObjectDraws(engine::render::FrameContext& frame, FrameDraws& f, engine::ecs::Entity entity,
                      const HermiteSdfRenderable& r, const glm::mat4& world);
  void beginObjectDraw(engine::render::FrameContext& frame, FrameDraws& f, const HermiteSdfRenderable& r,
                       DrawnObject& o);
  void addBrickObjectDraws(engine::render::FrameContext& frame, FrameDraws& f, const DrawnObject& o);
  void addRunObjectDraws(FrameDraws& f, const DrawnObject& o);
  void addCellObjectDraws(engine::render::FrameContext& frame, FrameDraws& f, const DrawnObject& o);
  void concatenateBatches(const FrameDraws& f, FrameCommands& all);
  void addWireCommands(FrameCommands& all);
  void chooseDrawStages(const FrameDraws& f);
  void uploadDraws(engine::render::FrameContext& frame, const FrameDraws& f, FrameCommands& all);
  void recordCulling(engine::render::FrameContext& frame);
  void recordBrickCulling(engine::render::FrameContext& frame);
  void recordCellCulling(engine::render::FrameContext& frame);
  void cullCellRanges(std::vector<VkDrawIndirectCommand>& commands, const std::vector<std::uint32_t> cullObjects[2]);
  void chooseCullingPaths(engine::render::FrameContext& frame, FrameDraws& f);
  std::array<std::uint64_t, 2> culledCells(const FrameDraws& f) const;
  bool reserveCellCulling(std::uint32_t slot, const std::array<std::uint64_t, 2>& cells,
                          const std::array<std::uint64_t, 2>& wantedSlots, std::string& refusal);
  std::uint64_t wantedKeptSlots(int precision, std::uint64_t cells) const;
  std::uint64_t heldKeptSlots(std::uint32_t slot, int precision) const;
  void clearKeptStreams();
  void releaseUnneededKeptStreams(const engine::render::FrameContext& frame,
                                  const std::array<std::uint64_t, 2>& wanted);
  // Retires the slot's kept-cell streams of `precision`, last used by frame `lastUse`.
  void releaseKeptStreams(const engine::render::FrameContext& frame, std::uint32_t slot, int precision,
                          std::uint64_t lastUse);
  void releaseIdleSlots(const engine::render::FrameContext& frame);
  std::uint64_t keptStreamBytesHeld() const;
  void readKeptDemand(std::uint32_t slot);
  void addFallbackCommands(FrameCommands& all);
  void dropCellCulling(FrameDraws& f);
  void placeHistory(engine::render::FrameContext& frame);
  static float occlusionDepthMargin(const engine::render::CameraView& camera, VkExtent2D extent);
  void addLateCommands(FrameCommands& all);
  void recordCellCullPasses(VkCommandBuffer cmd, std::uint32_t slot, shader::CellCullPushConstants push);
  void ensureCounters(engine::render::FrameContext& frame);
  void ensureHitDepths(engine::render::FrameContext& frame);
  void recordPrepassDraws(engine::render::PassContext& pass);
  // countBuffer (at countOffset): a GPU-written count that caps the batch's draws
  // (vkCmdDrawIndirectCount); none by default.
  // The lists of a batch (Batch): front faces, near cells (back faces), occlusion culling's phase 2,
  // and the culled rows that did not fit in the kept streams (drawn unculled).
  enum class List : std::uint8_t { Front, Near, Late, Fallback };
  void recordBatch(engine::render::PassContext& pass, int precision, List list, VkBuffer countBuffer = VK_NULL_HANDLE,
                   VkDeviceSize countOffset = 0);
  VkBuffer batchStream(int batch) const;
  void recordWireframe(engine::render::PassContext& pass, int batch);  // DEBUG_VIEW_WIREFRAME: batch b's box edges
  void recordIndirect(VkCommandBuffer cmd, const engine::gpu::Pipeline& pipeline, shader::HermitePushConstants push,
                      std::uint32_t frameSlot, std::uint32_t first, std::uint32_t count,
                      VkBuffer countBuffer = VK_NULL_HANDLE, VkDeviceSize countOffset = 0);
  void recordResolve(engine::render::PassContext& pass);
  void recordTiling(engine::render::FrameContext& frame);
  void recordTiles(engine::render::PassContext& pass);
  void logTileOverflow(const shader::CellTileTotals& previous, std::uint32_t capacity, std::uint32_t limit);
  shader::HermitePushConstants prepassPush(const engine::render::PassContext& pass) const;
  static std::uint64_t tileEntryEstimate(const GridSpec& grid, std::uint64_t cells, const glm::mat4& world,
                                         const engine::render::CameraView& camera, VkExtent2D extent,
                                         std::uint32_t tileSize);
  void recordRectangle(engine::render::PassContext& pass, engine::gpu::LazyPipeline& pipeline);

  const engine::gpu::Context* context_ = nullptr;
  Settings settings_;
  Stats stats_;
  engine::render::RegionStats<Stats> regionStats_;
  // The prepass's fragment-shader variants (shaders/hermite/hit_depth.glsl).
  enum Variant : int {
    kProduction = 0,  // cells_depth{,_near}.frag: no discard, no buffer write
    kCounted = 1,     // *_counted.frag: + the evaluation counters, in frames that count work
    kEarly = 2,       // cells_depth_early.frag (front faces at their own depth), *_near_early.frag
    kVariants = 3,
    kBrickVariants = 2,  // cell bricks: production and counted only
  };
  // Described when the feature is created, compiled when a frame first draws with one
  // (engine/gpu/lazy_pipeline.h): most processes draw with a few of them.
  struct Pipelines {
    using Lazy = engine::gpu::LazyPipeline;
    // [variant][precision]: precision 0 = fp32, 1 = fp16 records.
    Lazy depthFront[kVariants][2];
    Lazy depthNear[kVariants][2];
    Lazy wire[4];  // DEBUG_VIEW_WIREFRAME: the boxes' edges, per batch (kBatches)
    Lazy runsFront[kVariants];  // RenderMethod::CellRuns, both precisions
    Lazy runsNear[kVariants];
    Lazy bricksFront[kBrickVariants];  // RenderMethod::CellBricks, both precisions
    Lazy bricksNear[kBrickVariants];
    Lazy thinFront[kBrickVariants][2];  // Settings::thinBoxes, per precision (the cell attribute)
    Lazy thinNear[kBrickVariants][2];
    Lazy tiles[kBrickVariants];  // Settings::tiles, both precisions
    Lazy resolve;
    Lazy depthFixup;  // the hits' true depth after the early stage
    // Every pipeline above, in one fixed order (a reload pairs the old set with the fresh one).
    std::vector<Lazy*> all();
  };
  Variant prepassVariant(const engine::render::FrameContext& frame) const;
  void warmPipelines(const engine::render::FrameContext& frame);
  std::vector<engine::gpu::LazyPipeline*> likelyNextPipelines(Variant base);
  void appendWithoutEarlyStage(std::vector<engine::gpu::LazyPipeline*>& set, Variant base);
  void appendFirstFrame(std::vector<engine::gpu::LazyPipeline*>& set, Variant base);
  engine::Expected<Pipelines> describePipelines() const;
  engine::Status describeCellPipelines(Pipelines& p, const engine::gpu::SharedShaderModule& vert,
                                       const engine::gpu::SharedShaderModule& runsVert) const;
  engine::Status describeRunPipelines(Pipelines& p, const engine::gpu::SharedShaderModule& runsVert, int variant,
                                      const char* variantName) const;
  engine::Status describeWirePipelines(Pipelines& p, const engine::gpu::SharedShaderModule& wireFrag) const;
  void describeResolvePipelines(Pipelines& p, const engine::gpu::SharedShaderModule& resolveVert,
                                const engine::gpu::SharedShaderModule& resolveFrag,
                                const engine::gpu::SharedShaderModule& fixupFrag) const;
  engine::Status describeBrickPipelines(Pipelines& p) const;
  engine::Status describeThinCellPipelines(Pipelines& p) const;
  engine::Status describeTilePipelines(Pipelines& p) const;
  // Bricks and thin cells have only the production and counted variants (buildDraws keeps the early
  // depth stage off in frames that draw them): the variant of those two that `variant` stands for.
  static Variant withoutEarlyStage(Variant variant);
  void addBrickDraws(FrameDraws& f, const std::vector<shader::CellBrickGpu>& bricks, std::uint32_t firstBrick,
                     const DrawnObject& o);
  static std::uint32_t addRecord(FrameDraws& f, const shader::HermiteDraw& draw);
  static std::uint32_t addNearRecord(FrameDraws& f, const DrawnObject& o);

  engine::render::RendererFormats formats_;
  Pipelines pipelines_;
  // Compiles likelyNextPipelines() on a worker; declared after pipelines_ so that it is stopped
  // and joined before they are destroyed. Stopped before a reload replaces them.
  engine::gpu::PipelineWarming warming_;
  // Replaced buffers are retired with the frame (FrameContext::retire): commands recorded before
  // the replacement (an earlier view region of the frame, frames still in flight) still read them.
  std::unique_ptr<struct CellBuffers> buffers_;
  // Assets whose upload ran out of GPU memory (reported once, tried again once memory may fit
  // them: forgetRefusalsThatMayFit), and a run length refused the same way (0: none).
  std::unordered_map<std::uint64_t, engine::gpu::MemoryRefusal> refused_;
  std::optional<engine::gpu::MemoryRefusal> runsRefusal_;
  // The asset id each entity drew in each view region's last frame (drawn instead of a refused one
  // or one still written in parts).
  engine::render::DrawnPerRegion<std::uint64_t> drawnAssets_;
  std::uint32_t refusedRunLength_ = 0;
  std::uint64_t uploadedBytes_ = 0;  // Stats::uploadedBytes
  std::uint64_t copiedBytes_ = 0;    // Stats::copiedBytes
  // The copies of a rebuild's kept records, recorded in the commands of a frame not submitted yet,
  // and the old buffers they read: held (not retired) until that frame is submitted. A frame that
  // fails while it is recorded is not; its next try (the same frame number, from a view region no
  // later than the one that recorded them) records them again.
  struct PendingCopies {
    std::uint64_t frameNumber = 0;
    std::uint32_t region = 0;  // the view region that recorded them (FrameContext::viewRegionIndex)
    std::unique_ptr<CellBuffers> from;
    std::vector<engine::gpu::BufferCopy> copies;
  };
  std::optional<PendingCopies> pendingCopies_;
  // The new asset whose records are being written over several frames (Settings::
  // uploadBytesPerFrame), after the records the buffers hold (CellBuffers::used): no entry points
  // there until all are in. A rebuild of the buffers carries its records written so far over.
  struct PartialUpload {
    std::shared_ptr<const SdfAsset> asset;
    std::uint32_t written = 0;  // its records in the buffers so far
    std::uint32_t region = 0;   // the view region that began it (FrameContext::viewRegionIndex)
    std::uint64_t frame = 0;    // the frame that last wrote a part of it
    std::uint32_t first = 0;    // its first record's index in the buffers
  };
  std::optional<PartialUpload> partial_;
  std::optional<std::uint64_t> partsFrame_;  // the frame that last wrote records in parts: one round a frame
  // New assets not drawn yet after that round (uploading()), counted over the view regions of the
  // frame `waitingFrame_`.
  std::size_t assetsWaiting_ = 0;
  std::optional<std::uint64_t> waitingFrame_;
  engine::render::PerFrameBuffer drawData_;     // the draw table: HermiteDrawTableHeader, a record per command
  engine::render::PerFrameBuffer drawRecords_;  // its HermiteDraw records
  engine::render::PerFrameBuffer indirect_;
  engine::render::PerFrameBuffer objects_;  // shader::HermiteObject per drawn object
  engine::gpu::PixelBuffer counters_{"hermite evaluation counters"};  // the heat map's evaluations per pixel
  bool countersActive_ = false;
  engine::gpu::PixelBuffer hitDepths_{"hermite cell hit depths"};  // the nearest hit's depth bits (early depth)
  bool earlyDepth_ = false;  // this frame's boxes are drawn in the early depth stage
  bool thinBoxes_ = false;   // this frame draws its RenderMethod::Cells objects as thin boxes
  bool tiles_ = false;       // this frame draws its culled RenderMethod::Cells objects as tiles
  std::uint64_t tileEntryEstimate_ = 0;  // this frame's culled cells' tile entries, at most
  std::uint32_t tileSize_ = CELL_TILE_SIZE;  // this frame's (Settings::tileSize, checked)
  bool warnedTileSize_ = false;
  bool cullingRefused_ = false;  // the previous frame's culling did not fit (logged once per change)
  bool warnedHistory_ = false;   // occlusion culling's history or streams did not fit once (logged once)
  bool tilesRefused_ = false;    // the previous frame's tile lists did not fit (logged once per change)
  std::unique_ptr<class CellTiler> tiler_;
  std::uint32_t lastTileSlot_ = 0;
  bool tiledOnce_ = false;
  bool tileOverflowLogged_ = false;  // logTileOverflow: said until a frame fits again
  glm::vec4 screenRect_{1.0f, 1.0f, -1.0f, -1.0f};  // NDC bounds of this frame's cell objects (resolve)
  engine::gpu::IndirectDraws draws_;  // every indirect draw of the feature (see its header)
  // Brick culling (Settings::cullBricks): this frame's objects, the kept-brick stream's size and the
  // most bricks of one object; per frame slot the objects, totals and kept-brick stream.
  std::unique_ptr<class BrickCuller> culler_;
  std::vector<shader::BrickCullObject> cullObjectList_;
  std::uint32_t cullOutputBricks_ = 0;
  std::uint32_t cullMaxBricks_ = 0;
  std::uint32_t lastCullSlot_ = 0;
  engine::render::PerFrameBuffer cullObjects_;
  engine::render::PerFrameBuffer cullTotals_;
  std::vector<engine::gpu::Buffer> keptBricks_;
  // Cell culling (Settings::cullCells): this frame's culled objects and, per record precision, its
  // ranges (the culled objects' front-face commands), the kept streams' slots (keptCapacity_) and
  // the share of its culled cells the last completed frame kept (keptShare_); per frame slot and precision the kept
  // records, their record indices and (for the tiling) their range indices (cell_cull.comp).
  std::unique_ptr<class CellCuller> cellCuller_;
  std::vector<shader::BrickCullObject> cellCullObjects_;
  std::vector<shader::CellCullRange> cellCullRanges_[2];
  // Where each precision's ranges start in the slot's range buffer (bytes; its packs' first
  // ranges follow them, cell_cull.comp) and how many packs it has: set by recordCellCulling.
  VkDeviceSize cellCullRangeOffsets_[2] = {0, 0};
  std::uint32_t cellCullPackCounts_[2] = {0, 0};
  std::uint32_t keptCapacity_[2] = {0, 0};
  // The share of its culled cells the slot's last culling frame kept (negative: not measured),
  // and per frame slot the culled cells of its last frame whose culling pass ran (what
  // readKeptDemand divides its totals' append cursor by).
  double keptShare_[2] = {-1.0, -1.0};
  std::vector<std::array<std::uint64_t, 2>> keptCulledCells_;
  bool keptFallback_[2] = {false, false};  // the streams hold fewer slots than the ranges have cells
  bool keptOverflowLogged_ = false;
  engine::render::PerFrameBuffer cellCullObjectBuffer_;
  engine::render::PerFrameBuffer cellCullRangeBuffer_;
  std::vector<std::array<engine::gpu::Buffer, 2>> keptCellRecords_;
  std::vector<std::array<engine::gpu::Buffer, 2>> keptCellIndices_;
  std::vector<std::array<engine::gpu::Buffer, 2>> keptCellRanges_;
  // Per frame slot and precision: the slot's frames in a row whose streams were more than they
  // wanted (Settings::releaseAfterFrames).
  std::vector<std::array<engine::gpu::IdleFrames, 2>> keptIdle_;
  // Per frame slot: the frame that last prepared it (kNeverPrepared: none since its buffers went).
  static constexpr std::uint64_t kNeverPrepared = ~std::uint64_t(0);
  std::vector<std::uint64_t> slotPreparedFrame_;
  // Occlusion culling (Settings::cullOcclusion) this frame: phase 2 appends to the same kept
  // streams and its late commands follow the wireframe's.
  // Per culled object of this frame: its history entry and its first record; the history itself.
  bool occlusion_ = false;
  engine::gpu::IdleFrames historyIdle_;  // frames without occlusion culling (Settings::releaseAfterFrames)
  std::vector<std::pair<engine::ecs::Entity, std::uint64_t>> cellCullEntities_;
  std::vector<std::uint32_t> cellCullFirstRecord_;
  std::vector<std::uint32_t> cellCullCells_;
  std::vector<std::uint32_t> historyBase_;
  std::unique_ptr<class CellHistory> history_;
  std::uint32_t frameSlots_ = 1;  // framesInFlight given to initialize (frames in flight x view regions)
  static constexpr int kRunBatch = 2;  // batches: fp32 cells, fp16 cells, runs, bricks
  static constexpr int kBrickBatch = 3;
  static constexpr int kBatches = 4;
  std::unique_ptr<Batch> batches_[kBatches];
};

}  // namespace hsdf
