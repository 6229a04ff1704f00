// Tiled cells (cell_tiler.cpp, cell_tiles.comp, cell_tiles_depth.glsl) against the boxes they
// replace: the same image from one fragment per pixel and tile, for overlapping objects, long lists,
// inside a cell, every tile size, cells spanning the frame, lists past their limit, meshes after
// the tiles; the frame's named timings; Auto per device.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <optional>
#include <set>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "engine/gpu/context.h"
#include "engine/gpu/memory.h"

#include "engine/core/image_io.h"
#include "engine/core/math.h"
#include "engine/gpu/pipeline_statistics.h"
#include "engine/render/components.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/render/cell_feature.h"
#include "cell_test_support.h"
#include "device_tolerances.h"
#include "hermite_test_support.h"
#include "shared/host_device.h"

namespace gputest {
namespace {

using namespace engine;

class TiledCellsTest : public HermiteCellsTest {
 protected:
  // Renders the registry from `camera` with boxes, then with tiles; checks that the tiles drew and
  // that the images agree; returns the prepass fragment invocations of both (boxes, tiles).
  std::pair<std::uint64_t, std::uint64_t> expectTilesDrawTheBoxes(const render::CameraView& camera, const char* label,
                                                                   int minHits = 200) {
    auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
    feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;
    const Frame boxes = renderWith(camera, DEBUG_VIEW_NONE);
    const std::uint64_t boxFragments = prepassFragments(*renderer_);
    EXPECT_FALSE(feature->stats().tiles);
    feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::On;
    const Frame tiles = renderWith(camera, DEBUG_VIEW_NONE);
    const std::uint64_t tileFragments = prepassFragments(*renderer_);
    EXPECT_TRUE(feature->stats().tiles) << label;
    EXPECT_FALSE(feature->stats().earlyDepth) << label << ": tiles have no early depth stage";
    const shader::CellTileTotals totals = feature->tileTotals();
    EXPECT_GT(totals.instanceCount, 0u) << label;
    const TileComparison c = compareTilesWithBoxes(boxes, tiles);
    std::printf("[ %s ] hits %d / %d, coverage differs %d, colour differs %d, depth rel max %.2e, tiles %u, "
                "entries %u, prepass fragments %llu -> %llu\n",
                label, c.hitsBoxes, c.hitsTiles, c.coverageDiffers, c.colourDiffers, c.depthRelativeMax,
                totals.instanceCount, totals.entriesNeeded, static_cast<unsigned long long>(boxFragments),
                static_cast<unsigned long long>(tileFragments));
    EXPECT_GE(c.hitsBoxes, minHits) << label;
    EXPECT_LE(c.coverageDiffers, 0) << label;
    EXPECT_LE(c.colourDiffers, c.hitsBoxes / 500 + 2) << label << ": only where two cells' roots tie";
    // Relative to the depth (reverse-Z): grazing rays at silhouettes, whose depth is ill-conditioned,
    // move by up to ~2e-5 between the two rays (box face or tile depth as the reference point).
    EXPECT_LT(c.depthRelativeMax, 1e-4) << label;
    EXPECT_EQ(countIsolatedPixels(tiles), countIsolatedPixels(boxes)) << label << ": a speck of its own";
    return {boxFragments, tileFragments};
  }

  // The bunny at K = 64 from orbit view 1 (`camera`), drawn as boxes, with tiles on for what follows.
  Frame bunnyAsBoxes(render::CameraView& camera) {
    const auto asset = bakeAsset("bunny", 64);
    EXPECT_NE(asset, nullptr);
    if (!asset) return {};
    addSdf(registry_, asset, hsdf::RenderMethod::Cells);
    auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
    camera = orbitCamera(*asset, 1);
    feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;
    (void)renderWith(camera, DEBUG_VIEW_NONE);  // every frame slot's culled streams made
    const Frame boxes = renderWith(camera, DEBUG_VIEW_NONE);
    feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::On;
    return boxes;
  }
};

// Why: a tile lists every kept cell whose box may cover one of its pixels, sorted nearest first, and
// its fragments stop at the first cell behind their hit; a cell missing from a list (a rectangle
// too small, an entry past the list's capacity in the first frame of a view), a wrong sort or a
// break that comes too early shows as a hole or a hit of a farther surface. The bunny from six
// sides at K = 16 (cells of ~20 pixels: long overlapping lists) and K = 64, fp32 and fp16 records.
TEST_F(TiledCellsTest, TilesDrawTheBoxesImageWithAFragmentPerPixel) {
  createCellRenderer(kSize, kSize);
  const bool inOrder = tolerancesFor(*context_).fragmentsShadeInPrimitiveOrder;
  for (int k : {16, 64}) {
    const auto asset = bakeAsset("bunny", k);
    ASSERT_NE(asset, nullptr);
    for (bool half : {false, true}) {
      registry_ = ecs::Registry();
      registry_.get<hsdf::HermiteSdfRenderable>(addSdf(registry_, asset, hsdf::RenderMethod::Cells)).halfPrecision = half;
      std::uint64_t boxFragments = 0, tileFragments = 0;
      for (int view = half ? 1 : 0; view < 6; view += 2) {
        const std::string label = "bunny K=" + std::to_string(k) + (half ? " fp16" : " fp32") + " view " + std::to_string(view);
        const auto [boxes, tiles] = expectTilesDrawTheBoxes(orbitCamera(*asset, view), label.c_str());
        boxFragments += boxes;
        tileFragments += tiles;
      }
      // On lavapipe, which shades and counts 4x4 blocks, a tile costs its pixels once; a box of a
      // few pixels costs up to 64 invocations, hidden or not.
      if (inOrder && boxFragments > 0) {
        EXPECT_LT(tileFragments * 4, boxFragments) << "K = " << k;
      }
    }
  }
}

// Why: tiles hold cells of several objects, whose rays differ (each in its own grid); the nearest
// hit over all of them must win as the depth test made it win among boxes. Two bunnies overlapping
// on screen, one mirrored and non-uniformly scaled (OBJECT_FLAG_MIRRORED, the dilation's smallest
// scale).
TEST_F(TiledCellsTest, TilesResolveOverlappingObjects) {
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("bunny", 32);
  ASSERT_NE(asset, nullptr);
  const glm::vec3 centre = glm::vec3(asset->surfaceBounds.center());
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  const std::vector<NamedTransform> transforms = userTransforms(centre);
  ASSERT_FALSE(transforms.empty());
  const glm::mat4 shifted = glm::translate(glm::mat4(1.0f), glm::vec3(0.3f * float(asset->surfaceBounds.size().x), 0.0f, 0.1f));
  addSdf(registry_, asset, hsdf::RenderMethod::Cells, shifted * transforms.front().matrix());
  for (int view : {0, 3}) expectTilesDrawTheBoxes(orbitCamera(*asset, view, 2.6f), ("two bunnies view " + std::to_string(view)).c_str());
}

// Why: lavapipe (Mesa's gallivm) ends every loop of a shader invocation once the invocation has
// run 65,535 loop iterations in all, silently (cell_tiles.comp). The masks phase walked 8 tiles of
// 16x16 pixels per workgroup, a lane looping over 4 pixels x every entry of each: lists of a few
// thousand entries (dense scenes, many objects behind each other) ran past the limit and whole
// tiles lost their cells (16x16-pixel holes in a 108-object scene). Thirty bunnies, each shifted by
// a fraction of a cell, behind each other: lists of thousands of entries, in tiles of every size.
TEST_F(TiledCellsTest, LongListsDrawTheBoxesImage) {
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("bunny", 64);
  ASSERT_NE(asset, nullptr);
  const float h = float(asset->field.grid.spacing);
  for (int i = 0; i < 30; ++i)
    addSdf(registry_, asset, hsdf::RenderMethod::Cells,
           glm::translate(glm::mat4(1.0f), glm::vec3(0.013f * h * float(i), 0.007f * h * float(i), -0.6f * h * float(i))));
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  for (std::uint32_t size : {16u, 8u}) {
    feature->settings().tileSize = size;
    const std::string label = "30 bunnies, " + std::to_string(size) + "x" + std::to_string(size) + " tiles";
    expectTilesDrawTheBoxes(orbitCamera(*asset, 1, 1.6f), label.c_str());
    const shader::CellTileTotals totals = feature->tileTotals();
    EXPECT_GT(totals.entriesNeeded, 16u * 2048u) << label << ": lists long enough to have crossed the limit";
  }
}

// Why: where the near plane cuts cells their boxes' corners lie behind the eye; the tile pass then
// lists such a cell in every tile and draws those tiles at the near plane. Inside a cell of the
// torus, and a frame whose size is no multiple of the tile size (edge tiles the frame cuts: their
// points' centres are moved into the frame).
TEST_F(TiledCellsTest, TilesInsideACellAndAtTheFramesEdges) {
  createCellRenderer(203, 117);
  const auto torus = bakeAsset("torus", 16);
  ASSERT_NE(torus, nullptr);
  addSdf(registry_, torus, hsdf::RenderMethod::Cells);
  const std::optional<render::CameraView> inside = insideACellCamera(*torus);
  ASSERT_TRUE(inside);
  expectTilesDrawTheBoxes(*inside, "inside a torus cell");
  EXPECT_GT(renderer_->feature<hsdf::HermiteCellFeature>()->stats().nearCells, 0u);
  render::CameraView wide = orbitCamera(*torus, 2, 1.2f);
  expectTilesDrawTheBoxes(wide, "torus filling a 203x117 frame");
}

// Why: the tiles' binning and the cell culling are compute work recorded in prepare(), outside
// both passes; without scopes of their own a GPU capture cannot say whether the tiles' time goes
// to binning or to drawing, nor which of the binning's five phases it goes to. The
// renderer times prepare() as a whole, the feature names its parts inside it and the tiling its
// phases; a frame without tiles has no tiling scope.
TEST_F(TiledCellsTest, FrameTimingsNameTheCellsComputeInsidePrepare) {
  if (!context_->capabilities().timestamps) GTEST_SKIP() << "no timestamp queries on this device";
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("bunny", 32);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  const auto timing = [&](const std::string& name) -> std::optional<std::pair<std::size_t, double>> {
    const std::vector<gpu::GpuTiming>& timings = renderer_->lastTimings();
    for (std::size_t i = 0; i < timings.size(); ++i)
      if (timings[i].name == name) return std::pair{i, timings[i].milliseconds};
    return std::nullopt;
  };
  for (auto tiles : {hsdf::HermiteCellFeature::Tiles::On, hsdf::HermiteCellFeature::Tiles::Off}) {
    feature->settings().tiles = tiles;
    render(orbitCamera(*asset, 1));
    const bool tiled = tiles == hsdf::HermiteCellFeature::Tiles::On;
    ASSERT_EQ(feature->stats().tiles, tiled);
    const auto prepare = timing("prepare"), culling = timing("cells culling"), tiling = timing("cells tiling");
    ASSERT_TRUE(prepare && culling) << (tiled ? "tiles" : "boxes");
    EXPECT_LT(prepare->first, culling->first) << "culling is timed inside prepare";
    EXPECT_LE(culling->second, prepare->second * 1.001 + 1e-6);
    EXPECT_EQ(bool(tiling), tiled);
    if (tiling) {
      EXPECT_LT(culling->first, tiling->first) << "the tiles bin what the culling kept";
      EXPECT_GT(tiling->second, 0.0);
      EXPECT_LE(culling->second + tiling->second, prepare->second * 1.001 + 1e-6);
      // Its five phases, in their order, inside it; each begins after the one before has ended,
      // so together they fit in the tiling's time.
      double phases = 0.0;
      std::size_t previous = tiling->first;
      for (const char* name : {"cells tiling count", "cells tiling scan", "cells tiling scatter", "cells tiling sort",
                               "cells tiling masks"}) {
        const auto step = timing(name);
        ASSERT_TRUE(step) << name;
        EXPECT_LT(previous, step->first) << name;
        previous = step->first;
        phases += step->second;
      }
      EXPECT_LE(phases, tiling->second * 1.001 + 1e-6);
    } else {
      EXPECT_FALSE(timing("cells tiling count"));
    }
    const auto prepass = timing("depth prepass");
    ASSERT_TRUE(prepass);
    EXPECT_LT(prepare->first, prepass->first) << "prepare's work runs before the passes";
  }
}

// Why: each cell is listed in a tile, and tested by a pixel, only where its screen rectangle holds
// the pixel's centre, and that rectangle is grown by no more than the proxy's dilation (0.02 pixel
// at the cell's centre, in cells of the object's smallest scale) and 1/16 pixel of rounding.
// A rectangle a little too small loses pixels where a ray only grazes a cell: cells a pixel wide
// (K = 192 in 256x256, where every cell edge is near some pixel centre), objects whose axes are
// scaled differently (the dilation follows the smallest scale), and the extreme cameras (a 1x1 or
// 7x300 frame, fields of view of 10 and 150 degrees, the eye inside the grid).
TEST_F(TiledCellsTest, CellRectanglesHoldEveryPixelTheBoxesDraw) {
  createCellRenderer(kSize, kSize);
  {
    const auto fine = bakeAsset("bunny", 192);
    ASSERT_NE(fine, nullptr);
    addSdf(registry_, fine, hsdf::RenderMethod::Cells);
    for (int view : {0, 3}) expectTilesDrawTheBoxes(orbitCamera(*fine, view), ("bunny K=192 view " + std::to_string(view)).c_str());
  }
  const auto asset = bakeAsset("bunny", 48);
  ASSERT_NE(asset, nullptr);
  const glm::vec3 centre = glm::vec3(asset->surfaceBounds.center());
  for (const NamedTransform& t : userTransforms(centre)) {
    registry_ = ecs::Registry();
    addSdf(registry_, asset, hsdf::RenderMethod::Cells, t.matrix());
    expectTilesDrawTheBoxes(orbitAround(worldSphere(*asset, t.matrix()), 1), ("bunny K=48, " + t.label).c_str());
  }
  registry_ = ecs::Registry();
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  const float radius = 0.5f * glm::length(glm::vec3(asset->surfaceBounds.size()));
  for (const CameraSetup& setup : extremeCameras(centre, radius)) {
    createCellRenderer(setup.size.x, setup.size.y);
    expectTilesDrawTheBoxes(setup.camera, ("bunny K=48, " + setup.label).c_str(), 0);
  }
}

// Why: the tile size (Settings::tileSize) reaches the binning (tile counts, each entry's pixels),
// the points' size and position and the fragment's pixel within its tile; one place that kept the
// old size would list a cell in the wrong tile or test the wrong pixel. 4x4 and 16x16 tiles
// against boxes: large cells spanning many tiles (K = 16), small ones (K = 64), and a frame whose
// sides are no multiple of either size (edge tiles cut by the frame).
TEST_F(TiledCellsTest, EveryTileSizeDrawsTheBoxesImage) {
  const auto torus = bakeAsset("torus", 16);
  ASSERT_NE(torus, nullptr);
  for (std::uint32_t size : {4u, 16u}) {
    createCellRenderer(kSize, kSize);
    renderer_->feature<hsdf::HermiteCellFeature>()->settings().tileSize = size;
    const std::string tiles = std::to_string(size) + "x" + std::to_string(size) + " tiles, ";
    for (int k : {16, 64}) {
      const auto asset = bakeAsset("bunny", k);
      ASSERT_NE(asset, nullptr);
      registry_ = ecs::Registry();
      addSdf(registry_, asset, hsdf::RenderMethod::Cells);
      for (int view : {0, 3})
        expectTilesDrawTheBoxes(orbitCamera(*asset, view), (tiles + "bunny K=" + std::to_string(k) + " view " + std::to_string(view)).c_str());
    }
    createCellRenderer(203, 117);
    renderer_->feature<hsdf::HermiteCellFeature>()->settings().tileSize = size;
    registry_ = ecs::Registry();
    addSdf(registry_, torus, hsdf::RenderMethod::Cells);
    expectTilesDrawTheBoxes(orbitCamera(*torus, 2, 1.2f), (tiles + "torus filling a 203x117 frame").c_str());
  }
}

// Why: a tile's fragment keeps its best hit converted into the t of the object it walks
// (cell_tiles_depth.glsl: `best`) and must store the winner's own t (`hitT`), from which the
// resolve rebuilds the hit on the winner's anchor. The two differ only where another object's
// entry is tested after the winner's; a sorted list stops at the first box behind the hit, so
// that needs two surfaces within a cell (HermiteCellsTest.TwoFarObjectsShadeEachHitFromItsOwnAnchor
// could not tell them apart). A list of more than CELL_TILE_SORT_MAX entries is walked unsorted,
// every entry of the pixel's masks: copies of the torus (K = 32) behind each other along an
// orthographic view, each one torus size further back (its own anchor that much deeper), in four
// 16x16 tiles: the front copy hides the rest, so the reference is the front copy's.
TEST_F(TiledCellsTest, UnsortedListsStoreTheWinnersOwnHit) {
  constexpr std::uint32_t kSide = 64;
  constexpr int kCopies = 8;
  createCellRenderer(kSide, kSide);
  const auto asset = bakeAsset("torus", 32);
  ASSERT_NE(asset, nullptr);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::On;
  feature->settings().tileSize = 16;
  const WorldSphere sphere = worldSphere(*asset, glm::mat4(1.0f));
  const float step = 2.0f * sphere.radius;
  const render::CameraView near = orbitAround(sphere, 1);
  const render::CameraView camera =
      orthographicLike(near, 1.05f * sphere.radius, 0.5f * sphere.radius, 3.0f * sphere.radius + float(kCopies) * step);
  const glm::vec3 back = -step * camera.towardViewer();
  for (int i = 0; i < kCopies; ++i)
    addSdf(registry_, asset, hsdf::RenderMethod::Cells, glm::translate(glm::mat4(1.0f), float(i) * back));
  auto reference = hsdf::renderReference(asset->field, camera.view, camera.proj, {int(kSide), int(kSide)});
  ASSERT_TRUE(reference.ok()) << reference.error().message;
  const Frame shaded = renderWith(camera, DEBUG_VIEW_NONE);
  const Frame normals = renderWith(camera, DEBUG_VIEW_NORMALS);
  ASSERT_TRUE(feature->stats().tiles);
  const shader::CellTileTotals totals = feature->tileTotals();
  const ImageComparison c = compareWithReference(shaded, &normals.rgba, *reference, camera, asset->field.grid.spacing);
  const std::vector<bool> wrong = wrongPixels(normals, *reference, kFarNormalDegrees);
  const int off = int(std::count(wrong.begin(), wrong.end(), true));
  std::printf("[ unsorted lists ] tiles %u, entries %u, hits ref %d gpu %d, disagree %d, normals off %d, p99 %.2f deg\n",
              totals.instanceCount, totals.entriesNeeded, c.referenceHits, c.gpuHits, c.disagreements, off,
              c.normalErrorP99Degrees);
  EXPECT_GT(totals.entriesNeeded, totals.instanceCount * CELL_TILE_SORT_MAX) << "no list long enough to be walked unsorted";
  EXPECT_GT(c.referenceHits, 300);
  EXPECT_EQ(c.interiorHoles, 0);
  EXPECT_EQ(c.interiorExtras, 0);
  EXPECT_LE(off, 2);
  EXPECT_LT(c.normalErrorP99Degrees, 2.0);
}

// Why: lavapipe (Mesa's gallivm) ends every loop of a shader invocation once the invocation has
// run 65,535 loop iterations in all, silently. A cell whose box holds the eye spans the whole
// frame, and the binning lane that lists it loops over every tile: 67,600 4x4 tiles in a 1040x1040
// frame, past the limit, so the frame's last tiles never listed it. Here the cell's near box drew
// it anyway (this test passed its image checks before the change, with no huge cell counted), but
// a cell that reaches behind the eye's plane away from the eye has no near box. Such rectangles
// now make the frame draw its boxes (CellTileTotals::hugeCells), on every device: one lane walking
// the whole frame is slow on a GPU too.
TEST_F(TiledCellsTest, CellsSpanningTheFrameDrawTheBoxes) {
  createCellRenderer(1040, 1040);
  const auto torus = bakeAsset("torus", 16);
  ASSERT_NE(torus, nullptr);
  addSdf(registry_, torus, hsdf::RenderMethod::Cells);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  feature->settings().tileSize = 4;
  const std::optional<render::CameraView> inside = insideACellCamera(*torus);
  ASSERT_TRUE(inside);
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;
  const Frame boxes = renderWith(*inside, DEBUG_VIEW_NONE);
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::On;
  const Frame drawn = renderWith(*inside, DEBUG_VIEW_NONE);
  ASSERT_TRUE(feature->stats().tiles);
  const shader::CellTileTotals totals = feature->tileTotals();
  EXPECT_GT(totals.hugeCells, 0u);
  EXPECT_NE(totals.boxDrawCount, 0u) << "the frame's boxes drawn instead";
  const TileComparison c = compareTilesWithBoxes(boxes, drawn);
  EXPECT_GE(c.hitsBoxes, 100000);
  EXPECT_EQ(c.coverageDiffers, 0);
  EXPECT_LE(c.colourDiffers, c.hitsBoxes / 500 + 2);
  EXPECT_LT(c.depthRelativeMax, 1e-4);
}

// Why: the tiles' lists have a limit (Settings::maxTileEntries, a memory cap that very fine grids
// on large frames reach). Lists past it used to be clamped: the cells past the limit went missing,
// holes with no message. Now the scan leaves every tile empty and a GPU-written count draws the
// culled cells' boxes in the same frame: the boxes' image, the overflow in the totals, in the
// first frame at the lower limit (the list shrinks to it) as in the frames after; under a limit
// that fits, the same frames draw tiles again.
TEST_F(TiledCellsTest, ListsPastTheirLimitDrawTheBoxesInstead) {
  createCellRenderer(kSize, kSize);
  render::CameraView camera;
  const Frame boxes = bunnyAsBoxes(camera);
  ASSERT_FALSE(boxes.depth.empty());
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  renderWith(camera, DEBUG_VIEW_NONE);
  const shader::CellTileTotals fitting = feature->tileTotals();
  ASSERT_GT(fitting.instanceCount, 0u);
  EXPECT_EQ(fitting.boxDrawCount, 0u);
  ASSERT_GT(fitting.entriesNeeded / 2, hsdf::HermiteCellFeature::kMinTileEntries);
  const std::uint32_t defaultLimit = feature->settings().maxTileEntries;
  for (std::uint32_t limit : {fitting.entriesNeeded / 2, fitting.entriesNeeded - 1, defaultLimit}) {
    feature->settings().maxTileEntries = limit;
    const bool overflows = limit < fitting.entriesNeeded;
    for (int frame = 0; frame < 3; ++frame) {
      const std::string label = "limit " + std::to_string(limit) + ", frame " + std::to_string(frame);
      const Frame drawn = renderWith(camera, DEBUG_VIEW_NONE);
      ASSERT_TRUE(feature->stats().tiles) << label;
      const shader::CellTileTotals totals = feature->tileTotals();
      EXPECT_EQ(totals.entriesNeeded, fitting.entriesNeeded) << label;
      EXPECT_EQ(totals.boxDrawCount != 0, overflows) << label;
      EXPECT_EQ(totals.instanceCount, overflows ? 0u : fitting.instanceCount) << label;
      const TileComparison c = compareTilesWithBoxes(boxes, drawn);
      EXPECT_GE(c.hitsBoxes, 2000) << label;
      EXPECT_EQ(c.coverageDiffers, 0) << label;
      EXPECT_LE(c.colourDiffers, c.hitsBoxes / 500 + 2) << label;
      EXPECT_LT(c.depthRelativeMax, 1e-4) << label;
    }
  }
}

// Why: the tiles' lists are allocated per frame slot as the frame needs them; where GPU memory
// (or the application's budget) refuses them, the frame must still draw: its culled cells as
// boxes, the image of the boxes, and the tiles once they fit again. Before, the refusal failed the
// frame (the scene runner skipped it with "out of GPU memory").
TEST_F(TiledCellsTest, TileListsThatDoNotFitDrawTheBoxesInstead) {
  createCellRenderer(kSize, kSize);
  render::CameraView camera;
  const Frame boxes = bunnyAsBoxes(camera);
  ASSERT_FALSE(boxes.depth.empty());
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  gpu::Allocator& allocator = context_->allocator();
  // Room for 16 KiB more during the frame: a slot's lists start at 4,096 entries (64 KiB each).
  allocator.setBudget(allocator.stats().usedBytes + 16384);
  renderer_->renderFrame(registry_, camera, render::FrameSettings{});
  allocator.setBudget(gpu::Allocator::kUnlimited);
  EXPECT_FALSE(feature->stats().tiles) << "the tiles were drawn without their lists";
  EXPECT_FALSE(feature->stats().cullingRefused) << "the culling streams were there already";
  EXPECT_TRUE(boxes.depth == renderer_->readbackDepth()) << "the fallback is not the boxes' image";
  EXPECT_TRUE(boxes.rgba == renderer_->readbackColor()) << "the fallback is not the boxes' image";
  const Frame tiled = renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_TRUE(feature->stats().tiles) << "room again, but no tiles";
  const TileComparison c = compareTilesWithBoxes(boxes, tiled);
  EXPECT_GE(c.hitsBoxes, 2000);
  EXPECT_EQ(c.coverageDiffers, 0);
}

// Why: each frame slot's tiles and lists (up to 2^23 entries, twice) grow to what its frames needed
// and would be held for the rest of the run once a scene stops drawing tiles (tiles off, a tracer,
// boxes only). After Settings::releaseAfterFrames of the slot's frames without tiles they must go,
// not before, and the next tiled frame must draw the same image from lists made anew. A mutant
// that never releases keeps them; one that forgets the capacity tiles into released lists.
TEST_F(TiledCellsTest, TileListsOfASlotThatStopsTilingAreReleased) {
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("bunny", 32);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::On;
  const render::CameraView camera = orbitCamera(*asset, 3);
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  const Frame tiled = renderWith(camera, DEBUG_VIEW_NONE);  // both slots tiled
  ASSERT_TRUE(feature->stats().tiles);
  const std::uint64_t held = feature->stats().tileListBytesHeld;
  ASSERT_GT(held, 0u);
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;
  for (int frame = 0; frame < 10; ++frame) (void)renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_EQ(feature->stats().tileListBytesHeld, held) << "released before releaseAfterFrames (120) frames";
  feature->settings().releaseAfterFrames = 3;
  for (int frame = 0; frame < 10 && feature->stats().tileListBytesHeld > 0; ++frame)
    (void)renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_EQ(feature->stats().tileListBytesHeld, 0u) << "the lists were kept while no frame drew tiles";
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::On;
  for (int slot = 0; slot < 2; ++slot) {
    const Frame again = renderWith(camera, DEBUG_VIEW_NONE);
    EXPECT_TRUE(feature->stats().tiles);
    EXPECT_GT(feature->stats().tileListBytesHeld, 0u);
    EXPECT_TRUE(tiled.depth == again.depth) << "tiles from lists made anew changed the depth (slot " << slot << ")";
    EXPECT_TRUE(tiled.rgba == again.rgba) << "tiles from lists made anew changed the colour (slot " << slot << ")";
  }
}

// Why: a frame slot's first tiled frame sizes its lists by an upper bound (every cell as large on
// screen as the nearest one, none culled), several times what its frames need. Lists that stayed
// at the bound held 195 MiB at 1920x1080 for the bunny at K = 256, whose frames needed 140,000
// entries (4.5 MiB). Later frames size them by what the slot's last frame needed, scaled by the
// bound's growth: lists made by the bound are remade as soon as a frame has measured its need,
// and the view keeps its image; a view nearer than the last frames (more entries than they needed) has room, draws
// the boxes' image, and so do the frames after it.
TEST_F(TiledCellsTest, TileListsFollowWhatTheFramesNeed) {
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("bunny", 128);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  const render::CameraView far = orbitCamera(*asset, 1, 3.8f), near = orbitCamera(*asset, 1);
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;
  (void)renderWith(near, DEBUG_VIEW_NONE);
  const Frame nearBoxes = renderWith(near, DEBUG_VIEW_NONE);
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::On;
  (void)renderWith(far, DEBUG_VIEW_NONE);
  const Frame first = renderWith(far, DEBUG_VIEW_NONE);  // both slots' lists made by the bound
  ASSERT_TRUE(feature->stats().tiles);
  const std::uint64_t bound = feature->stats().tileListBytesHeld;
  const std::uint32_t farNeeds = feature->tileTotals().entriesNeeded;
  ASSERT_GT(farNeeds, 1000u);
  for (int frame = 0; frame < 6; ++frame) {
    const Frame steady = renderWith(far, DEBUG_VIEW_NONE);
    EXPECT_EQ(feature->tileTotals().boxDrawCount, 0u) << "steady frame " << frame << " overflowed";
    EXPECT_TRUE(first.depth == steady.depth) << "steady frame " << frame << " changed the depth";
    EXPECT_TRUE(first.rgba == steady.rgba) << "steady frame " << frame << " changed the colour";
  }
  const std::uint64_t steady = feature->stats().tileListBytesHeld;
  std::printf("[ lists ] far view needs %u entries: %.2f MiB held at the bound, %.2f MiB after\n", farNeeds,
              double(bound) / 1048576.0, double(steady) / 1048576.0);
  EXPECT_LT(steady * 3, bound) << "the lists stayed near the bound";
  bool overflowed = false;
  for (int frame = 0; frame < 4; ++frame) {
    const std::string label = "near frame " + std::to_string(frame);
    const Frame drawn = renderWith(near, DEBUG_VIEW_NONE);
    const shader::CellTileTotals totals = feature->tileTotals();
    overflowed = overflowed || totals.boxDrawCount != 0;
    if (frame >= 2) {
      EXPECT_EQ(totals.boxDrawCount, 0u) << label << ": the slot's lists did not grow";
    }
    EXPECT_GT(totals.entriesNeeded, farNeeds) << label;
    const TileComparison c = compareTilesWithBoxes(nearBoxes, drawn);
    EXPECT_GE(c.hitsBoxes, 2000) << label;
    EXPECT_EQ(c.coverageDiffers, 0) << label;
    EXPECT_LE(c.colourDiffers, c.hitsBoxes / 500 + 2) << label;
    EXPECT_LT(c.depthRelativeMax, 1e-4) << label;
  }
  std::printf("[ lists ] the near view needs %u entries; its first frames %s\n", feature->tileTotals().entriesNeeded,
              overflowed ? "overflowed (drawn as boxes)" : "fit");
  // Here the bound grows with the view (its cells' size on screen), and the far frames' need
  // scaled by that growth leaves room for the near ones: no frame of boxes.
  EXPECT_FALSE(overflowed) << "the far view's lists were not scaled by the bound's growth";
}

// Why: the tiles and their fallback draw through vkCmdDrawIndirectCount, the meshes through
// vkCmdDrawIndexedIndirect, in the same passes. On lavapipe (Mesa 22.3) a count buffer once used
// stays in the driver's state for every later indirect draw of the command buffer: the meshes
// drawn after the tiles' fallback (count 0) vanished, the scene runner's ground with them. A
// ground quad under the bunny seen from above, the frame with tiles against the same frame with
// boxes, twice (the frame slots' state).
TEST_F(TiledCellsTest, MeshesDrawnAfterTheTilesStayDrawn) {
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("bunny", 32);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  const glm::vec3 centre(asset->surfaceBounds.center());
  const glm::vec3 size(asset->surfaceBounds.size());
  const ecs::Entity ground = addQuad({centre.x, float(asset->surfaceBounds.min.y), centre.z}, 4.0f * size.x,
                                     {0.6f, 0.6f, 0.6f, 1.0f});
  registry_.get<scene::Transform>(ground).rotation = glm::angleAxis(-1.5707963f, glm::vec3(1, 0, 0));
  scene::updateWorldTransforms(registry_);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  const render::CameraView camera = orbitCamera(*asset, 0, 2.2f);
  const auto groundPixels = [](const Frame& frame) {  // grey: the ground, lit
    int count = 0;
    for (std::size_t i = 0; i + 3 < frame.rgba.size(); i += 4) {
      const int r = frame.rgba[i], g = frame.rgba[i + 1], b = frame.rgba[i + 2];
      count += std::abs(r - g) < 12 && std::abs(g - b) < 12 && r > 90;
    }
    return count;
  };
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;
  const Frame boxes = renderWith(camera, DEBUG_VIEW_NONE);
  ASSERT_GT(groundPixels(boxes), int(kSize * kSize) / 10) << "the ground must be on screen for the test to mean something";
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::On;
  for (int frame = 0; frame < 2; ++frame) {
    const Frame tiles = renderWith(camera, DEBUG_VIEW_NONE);
    ASSERT_TRUE(feature->stats().tiles);
    int differs = 0;
    for (std::size_t i = 0; i < boxes.depth.size(); ++i)
      for (int k = 0; k < 3; ++k)
        if (std::abs(int(boxes.rgba[i * 4 + k]) - int(tiles.rgba[i * 4 + k])) > 8) {
          ++differs;
          break;
        }
    EXPECT_EQ(groundPixels(tiles), groundPixels(boxes)) << "frame " << frame;
    EXPECT_LE(differs, int(boxes.depth.size()) / 500) << "frame " << frame;
  }
}

TEST_F(HermiteCellsTest, TilesAutoFollowsTheDevice) {
  using Tiles = hsdf::HermiteCellFeature::Tiles;
  EXPECT_TRUE(hsdf::HermiteCellFeature::tilesWanted(Tiles::Auto, true));
  EXPECT_FALSE(hsdf::HermiteCellFeature::tilesWanted(Tiles::Auto, false));
  EXPECT_TRUE(hsdf::HermiteCellFeature::tilesWanted(Tiles::On, false));
  EXPECT_FALSE(hsdf::HermiteCellFeature::tilesWanted(Tiles::Off, true));
  createCellRenderer(64, 64);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  EXPECT_EQ(feature->settings().tiles, Tiles::Auto);
  const auto asset = bakeAsset("sphere", 16);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  renderWith(orbitCamera(*asset, 0), DEBUG_VIEW_NONE);
  EXPECT_EQ(feature->stats().tiles,
            context_->capabilities().isSoftwareRasterizer && context_->capabilities().drawIndirectCount);
  feature->settings().cullCells = false;  // tiles bin the culling pass's cells
  renderWith(orbitCamera(*asset, 0), DEBUG_VIEW_NONE);
  EXPECT_FALSE(feature->stats().tiles);
}

}  // namespace
}  // namespace gputest
