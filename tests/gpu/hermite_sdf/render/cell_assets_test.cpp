// The cell feature's uploads of the drawn assets (src/render/cell_assets.cpp): what the frame that
// first draws an asset, or draws it in a new form, costs the render thread.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "cells/cell_derived.h"
#include "cells/cell_rows.h"
#include "hermite_sdf/core/bake_job.h"
#include "hermite_sdf/core/normal_cone.h"
#include "hermite_sdf/core/sdf_asset.h"
#include "hermite_sdf/render/cell_feature.h"
#include "cell_test_support.h"
#include "shared/host_device.h"
#include "hermite_test_support.h"

namespace gputest {
namespace {

using namespace engine;

// The bunny through the one bake job (sparse: the cells alone), on its worker thread, as the
// samples bake it. Fails the test on error.
std::shared_ptr<const hsdf::SdfAsset> bakeBunnyOnWorker(int resolution) {
  auto source = hsdf::BakeSource::fromPathOrShape(sampleAsset("bunny.glb").string());
  EXPECT_TRUE(source.ok()) << source.error().message;
  if (!source) return nullptr;
  hsdf::BakeSettings settings;
  settings.resolution = resolution;
  settings.band = hsdf::BakeBand::Sparse;
  hsdf::BakeJob job(std::move(*source), settings);
  hsdf::BakeJob::Result baked = job.wait();
  EXPECT_TRUE(baked.ok()) << baked.error().message;
  return baked ? *baked : nullptr;
}

// Milliseconds the render thread spends in renderFrame (prepare, recording, submission; the
// read-back after it is not counted).
double frameMilliseconds(render::Renderer& renderer, const ecs::Registry& registry, const render::CameraView& camera) {
  const auto start = std::chrono::steady_clock::now();
  const bool drawn = renderer.renderFrame(registry, camera, render::FrameSettings{});
  EXPECT_TRUE(drawn);
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Why: the cones and bricks are seconds of work at K >= 1024, the rows and runs tens of
// milliseconds; the frame that first draws an asset, or draws it in a new form (culled cells,
// bricks, runs), must take them from the asset (the bake job made them on its worker thread) and
// build none on the render thread, while still culling with them: real cones reach the GPU, so the
// cone test removes cells and bricks (never-cull cones would draw the same image and remove none).
// A run length other than the asset's runs' is built then (more runs when shorter).
TEST_F(HermiteCellsTest, FramesDrawingANewAssetBuildNoConesRowsOrRunsOnTheRenderThread) {
  createCellRenderer(kSize, kSize);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;  // the cull totals of boxes
  const auto asset = bakeBunnyOnWorker(64);
  ASSERT_NE(asset, nullptr);
  const render::CameraView camera = orbitCamera(*asset, 0);
  const std::uint64_t before = hsdf::gradientConesBuiltOnThisThread();
  const std::uint64_t rowsBefore = hsdf::cellRowsAndRunsBuiltOnThisThread();
  const ecs::Entity entity = addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_GT(feature->cullTotals().coneCulled, 0u) << "culled cells: no cell removed by its cone";
  registry_.get<hsdf::HermiteSdfRenderable>(entity).method = hsdf::RenderMethod::CellBricks;
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_GT(feature->stats().bricks, 0u);
  EXPECT_GT(feature->cullTotals().coneCulled, 0u) << "bricks: no brick removed by its cone";
  registry_.get<hsdf::HermiteSdfRenderable>(entity).method = hsdf::RenderMethod::CellRuns;
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  const std::uint64_t runs = feature->stats().runs;
  EXPECT_GT(runs, 0u);
  EXPECT_EQ(hsdf::gradientConesBuiltOnThisThread(), before) << "the render thread built normal cones";
  EXPECT_EQ(hsdf::cellRowsAndRunsBuiltOnThisThread(), rowsBefore) << "the render thread built rows or runs";
  feature->settings().maxRunLength = hsdf::kDefaultMaxRunLength / 2;
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_GT(feature->stats().runs, runs) << "shorter runs, not the asset's";
}

// Why: the asset's own runs are of the default length; a run length set otherwise at run time gets
// runs built in its frame, and the runs written to the GPU must be those the draws index (a fresh
// renderer at that length would share a mismatch, so the check is the CPU reference). So: a torus
// drawn as runs of the default length, then of half of it, matches the reference.
TEST_F(HermiteCellsTest, RunsOfAnotherLengthThanTheAssetsMatchTheReference) {
  createCellRenderer(kSize, kSize);
  const auto torus = bakeAsset("torus", 16);
  ASSERT_NE(torus, nullptr);
  const render::CameraView camera = orbitCamera(*torus, 0);
  addSdf(registry_, torus, hsdf::RenderMethod::CellRuns, glm::mat4(1.0f), 3);
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  renderer_->feature<hsdf::HermiteCellFeature>()->settings().maxRunLength = hsdf::kDefaultMaxRunLength / 2;
  expectMatchesReference(compareView(*torus, camera, "torus, runs of half the default length"));
}

// Why: an asset made by hand carries no cones or bricks; its culled cells must still be drawn
// whole (cones that never cull), with the image of the same cells drawn unculled, not with holes.
TEST_F(HermiteCellsTest, AnAssetWithoutDerivedDataIsDrawnUnculled) {
  createCellRenderer(kSize, kSize);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;
  const auto baked = bakeAsset("torus", 24);
  ASSERT_NE(baked, nullptr);
  auto byHand = std::make_shared<hsdf::SdfAsset>(*baked);  // a copy keeps the id: `baked` is not drawn here
  byHand->derived = nullptr;
  const render::CameraView camera = orbitCamera(*baked, 1);
  addSdf(registry_, byHand, hsdf::RenderMethod::Cells);
  feature->settings().cullCells = false;
  const Frame unculled = renderWith(camera, DEBUG_VIEW_NONE);
  feature->settings().cullCells = true;
  const Frame culled = renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_GT(feature->cullTotals().tested, 0u) << "the culling pass ran";
  EXPECT_EQ(feature->cullTotals().coneCulled, 0u) << "cones of no cells culled some";
  ASSERT_GT(std::count_if(culled.depth.begin(), culled.depth.end(), [](float d) { return d > 0.0f; }), 500);
  EXPECT_TRUE(unculled.depth == culled.depth);
  EXPECT_TRUE(unculled.rgba == culled.rgba);
}

// Why: an uploaded asset first drawn as bricks must get its bricks appended beside the records it
// has, not a rebuild of every drawn asset's buffers (the bunny at K = 256: 0.6-3.4 s); the tricky
// part is the second asset, whose records do not start at 0: its bricks' cells must point at its
// own records in the shared buffer. So: the upload grows by the bricks' bytes alone (their boxes,
// cones and cell indices), and the frame equals a fresh renderer's that drew the asset as bricks
// from the start.
TEST_F(HermiteCellsTest, AnUploadedAssetFirstDrawnAsBricksUploadsItsBricksAlone) {
  createCellRenderer(kSize, kSize);
  const auto sphere = bakeAsset("sphere", 24);
  const auto torus = bakeAsset("torus", 32);
  ASSERT_NE(sphere, nullptr);
  ASSERT_NE(torus, nullptr);
  const glm::mat4 beside = glm::translate(glm::mat4(1.0f), glm::vec3(-2.5f, 0.0f, 0.0f));
  addSdf(registry_, sphere, hsdf::RenderMethod::Cells, beside);
  const ecs::Entity entity = addSdf(registry_, torus, hsdf::RenderMethod::Cells);
  const render::CameraView camera = orbitCamera(*torus, 0, 2.6f);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  const std::uint64_t uploaded = feature->stats().uploadedBytes;
  registry_.get<hsdf::HermiteSdfRenderable>(entity).method = hsdf::RenderMethod::CellBricks;
  const Frame switched = renderWith(camera, DEBUG_VIEW_NONE);
  const std::uint64_t bricks = feature->stats().bricks;
  ASSERT_GT(bricks, 0u);
  EXPECT_EQ(feature->stats().uploadedBytes - uploaded,
            bricks * (sizeof(shader::CellBrickGpu) + sizeof(shader::CellBrickCone)) +
                torus->cells.records.size() * sizeof(std::uint32_t));
  createCellRenderer(kSize, kSize);  // a fresh feature: the torus's bricks uploaded with its records
  const Frame fresh = renderWith(camera, DEBUG_VIEW_NONE);
  ASSERT_GT(std::count_if(fresh.depth.begin(), fresh.depth.end(), [](float d) { return d > 0.0f; }), 500);
  EXPECT_TRUE(switched.depth == fresh.depth);
  EXPECT_TRUE(switched.rgba == fresh.rgba);
}

using Cells = hsdf::HermiteCellFeature;

std::int64_t coveredPixels(const Frame& frame) {
  return std::count_if(frame.depth.begin(), frame.depth.end(), [](float d) { return d > 0.0f; });
}

// Why: an asset copied and given other records after make*Asset carries the rows and runs of the
// records it was made with; the feature must build its own (as for an asset without derived data),
// or its cells and runs draw ranges of records that are not where those rows and runs say. So: the
// copy with a slab of cells taken out of the middle of its stream, drawn as cells and as runs,
// equals the same records with their own derived data.
TEST_F(HermiteCellsTest, AnAssetWhoseRecordsChangedAfterItWasMadeDrawsItsOwnRowsAndRuns) {
  const auto baked = bakeAsset("torus", 24);
  ASSERT_NE(baked, nullptr);
  auto changed = std::make_shared<hsdf::SdfAsset>(*baked);  // a copy keeps the id: `baked` is not drawn here
  const std::uint16_t slab = baked->cells.records[baked->cells.records.size() / 2].z;
  std::erase_if(changed->cells.records, [slab](const hsdf::CellRecord& r) { return r.z == slab; });
  changed->cellsHalf = hsdf::toHalf(changed->cells);
  changed->proxyBoxes = hsdf::proxyBoxCodes(changed->cells);
  changed->proxyBoxesHalf = hsdf::proxyBoxCodes(changed->cellsHalf);
  ASSERT_EQ(hsdf::matchingDerived(*changed), nullptr) << "the copy's derived data must be of other records";
  auto own = std::make_shared<hsdf::SdfAsset>(*changed);
  own->derived = hsdf::deriveCellData(own->cells).value();
  ASSERT_NE(hsdf::matchingDerived(*own), nullptr);
  const render::CameraView camera = orbitCamera(*baked, 1);
  for (const hsdf::RenderMethod method : {hsdf::RenderMethod::Cells, hsdf::RenderMethod::CellRuns}) {
    Frame frames[2];
    for (int drawn = 0; drawn < 2; ++drawn) {  // a fresh renderer each: both assets have the same id
      registry_.clear();
      createCellRenderer(kSize, kSize);
      auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
      feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;
      feature->settings().cullCells = false;  // the copy has no cones of its own records
      addSdf(registry_, drawn == 0 ? changed : own, method);
      frames[drawn] = renderWith(camera, DEBUG_VIEW_NONE);
    }
    ASSERT_GT(coveredPixels(frames[1]), 500);
    EXPECT_EQ(differingPixels(frames[0], frames[1]), 0u) << hsdf::renderMethodName(method);
  }
}

// Why: with a budget per frame, a new asset larger than it must be written over several frames, no
// frame writing more than the budget (floored to whole records: a record is the item that is not
// split), and must not be drawn before its last records are in (a frame drawing it half uploaded
// shows holes or stale memory): background until then. Tricky: the budget is not a whole number of
// records; the asset goes into empty buffers (no rebuild may write it again in the last frame, which
// also brings the small streams: runs, bricks); and the image once whole must equal exactly the
// image of the same asset uploaded in one frame by budget 0 (no limit, as before), which must draw
// it in its first frame.
TEST_F(HermiteCellsTest, ANewAssetLargerThanTheBudgetIsWrittenInPartsAndDrawnOnlyOnceWhole) {
  const auto torus = bakeAsset("torus", 32);
  ASSERT_NE(torus, nullptr);
  const render::CameraView camera = orbitCamera(*torus, 0);
  createCellRenderer(kSize, kSize);
  auto* feature = renderer_->feature<Cells>();
  feature->settings().uploadBytesPerFrame = 0;
  addSdf(registry_, torus, hsdf::RenderMethod::Cells);
  const Frame whole = renderWith(camera, DEBUG_VIEW_NONE);
  ASSERT_GT(coveredPixels(whole), 500) << "budget 0: not drawn in its first frame";
  EXPECT_FALSE(feature->uploading());
  const std::uint64_t wholeBytes = feature->stats().uploadedBytes;
  const std::uint64_t records = torus->cells.records.size();
  ASSERT_GT(wholeBytes, records * Cells::kRecordUploadBytes) << "the small streams (runs) are uploaded too";

  createCellRenderer(kSize, kSize);  // a fresh feature, the same entity
  feature = renderer_->feature<Cells>();
  const std::uint64_t perFrame = records / 4 + 1;
  feature->settings().uploadBytesPerFrame = perFrame * Cells::kRecordUploadBytes + Cells::kRecordUploadBytes / 2;
  const std::uint64_t parts = (records + perFrame - 1) / perFrame;
  ASSERT_EQ(parts, 4u);
  std::uint64_t before = 0;
  for (std::uint64_t part = 1; part <= parts; ++part) {
    const Frame frame = renderWith(camera, DEBUG_VIEW_NONE);
    const std::uint64_t written = feature->stats().uploadedBytes - before;
    before = feature->stats().uploadedBytes;
    if (part < parts) {
      EXPECT_EQ(written, perFrame * Cells::kRecordUploadBytes) << "frame " << part;
      EXPECT_TRUE(feature->uploading()) << "frame " << part;
      EXPECT_EQ(coveredPixels(frame), 0) << "drawn before all of it was uploaded, frame " << part;
      continue;
    }
    const std::uint64_t last = records - (parts - 1) * perFrame;
    EXPECT_EQ(written, last * Cells::kRecordUploadBytes + (wholeBytes - records * Cells::kRecordUploadBytes));
    EXPECT_FALSE(feature->uploading());
    EXPECT_TRUE(frame.depth == whole.depth) << "the image once whole differs from one uploaded in one frame";
    EXPECT_TRUE(frame.rgba == whole.rgba);
  }
  EXPECT_EQ(before, wholeBytes) << "written again (a rebuild) or not all of it";
}

// Why: a re-bake (the panel's new K) replaces the entity's asset; while the new one is written in
// parts the entity must keep drawing the old one (no frame without the object, never the new one
// half uploaded), then draw the new one from the frame its last part is in. Tricky: no entity names
// the old asset any more, yet it must stay uploaded and drawn; the new one's records go after the
// old one's (not at 0), and its image must equal the new asset's uploaded in one frame.
TEST_F(HermiteCellsTest, AReplacedAssetIsDrawnUntilItsReplacementIsWhole) {
  const auto coarse = bakeAsset("torus", 16);
  const auto fine = bakeAsset("torus", 40);
  ASSERT_NE(coarse, nullptr);
  ASSERT_NE(fine, nullptr);
  const render::CameraView camera = orbitCamera(*fine, 0);
  createCellRenderer(kSize, kSize);
  renderer_->feature<Cells>()->settings().uploadBytesPerFrame = 0;
  const ecs::Entity entity = addSdf(registry_, coarse, hsdf::RenderMethod::Cells);
  const Frame old = renderWith(camera, DEBUG_VIEW_NONE);
  registry_.get<hsdf::HermiteSdfRenderable>(entity).asset = fine;
  const Frame replaced = renderWith(camera, DEBUG_VIEW_NONE);
  ASSERT_GT(coveredPixels(old), 500);
  ASSERT_FALSE(old.depth == replaced.depth) << "the two K must draw apart for the test to tell them apart";

  createCellRenderer(kSize, kSize);
  auto* feature = renderer_->feature<Cells>();
  const std::uint64_t records = fine->cells.records.size();
  ASSERT_LT(coarse->cells.records.size(), records / 3);
  const std::uint64_t perFrame = records / 3;
  feature->settings().uploadBytesPerFrame = perFrame * Cells::kRecordUploadBytes;
  const std::uint64_t parts = (records + perFrame - 1) / perFrame;
  registry_.get<hsdf::HermiteSdfRenderable>(entity).asset = coarse;
  const Frame first = renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_TRUE(first.depth == old.depth) << "the coarse asset fits the budget: drawn in its first frame";
  registry_.get<hsdf::HermiteSdfRenderable>(entity).asset = fine;
  int frames = 0;
  for (; frames < 10; ++frames) {
    const Frame frame = renderWith(camera, DEBUG_VIEW_NONE);
    if (!feature->uploading()) {
      EXPECT_TRUE(frame.depth == replaced.depth);
      EXPECT_TRUE(frame.rgba == replaced.rgba);
      break;
    }
    EXPECT_TRUE(frame.depth == old.depth) << "frame " << frames << " did not draw the old asset";
    EXPECT_TRUE(frame.rgba == old.rgba) << "frame " << frames;
  }
  EXPECT_EQ(std::uint64_t(frames), parts - 1) << "the old asset drawn in every frame but the last part's";
}

// Why: new assets that the budget holds together are written in one frame, one after the other, and
// the frame's budget left after one that is whole goes to the next (a level streaming in many small
// assets must not take a frame each). Tricky: the second asset's records go after the first's,
// which are not appended yet when it is written; whichever comes first, the frame draws exactly
// the whole one, and the next frame both, as a frame uploading both at once draws them.
TEST_F(HermiteCellsTest, TheBudgetLeftByAWholeAssetGoesToTheNext) {
  const auto sphere = bakeAsset("sphere", 24);
  const auto torus = bakeAsset("torus", 32);
  ASSERT_NE(sphere, nullptr);
  ASSERT_NE(torus, nullptr);
  const glm::mat4 beside = glm::translate(glm::mat4(1.0f), glm::vec3(-2.5f, 0.0f, 0.0f));
  const render::CameraView camera = orbitCamera(*torus, 0, 2.6f);
  createCellRenderer(kSize, kSize);
  renderer_->feature<Cells>()->settings().uploadBytesPerFrame = 0;
  const ecs::Entity sphereEntity = addSdf(registry_, sphere, hsdf::RenderMethod::Cells, beside);
  const Frame sphereOnly = renderWith(camera, DEBUG_VIEW_NONE);
  addSdf(registry_, torus, hsdf::RenderMethod::Cells);
  const Frame both = renderWith(camera, DEBUG_VIEW_NONE);
  registry_.destroy(sphereEntity);
  const Frame torusOnly = renderWith(camera, DEBUG_VIEW_NONE);
  ASSERT_GT(coveredPixels(sphereOnly), 500);
  ASSERT_GT(coveredPixels(torusOnly), 500);

  createCellRenderer(kSize, kSize);
  auto* feature = renderer_->feature<Cells>();
  const std::uint64_t small = std::min(sphere->cells.records.size(), torus->cells.records.size());
  const std::uint64_t large = std::max(sphere->cells.records.size(), torus->cells.records.size());
  // Whichever comes first is whole within the budget and the other is not.
  feature->settings().uploadBytesPerFrame = (large + small / 2) * Cells::kRecordUploadBytes;
  addSdf(registry_, sphere, hsdf::RenderMethod::Cells, beside);
  const Frame first = renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_TRUE(feature->uploading());
  EXPECT_TRUE(first.depth == sphereOnly.depth || first.depth == torusOnly.depth)
      << "not exactly one of them drawn whole";
  const Frame second = renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_FALSE(feature->uploading());
  EXPECT_TRUE(second.depth == both.depth);
  EXPECT_TRUE(second.rgba == both.rgba);
}

// The objects of the rebuild tests: assets of their own, side by side in a 4 x 2 grid (slot).
struct Placed {
  std::shared_ptr<const hsdf::SdfAsset> asset;
  hsdf::RenderMethod method;
  bool halfPrecision;
  int slot;
};

ecs::Entity addPlaced(ecs::Registry& registry, const Placed& p) {
  const glm::vec3 center(p.asset->surfaceBounds.center());
  const float scale = 3.0f / float(glm::length(p.asset->surfaceBounds.size()));
  const glm::mat4 m = glm::translate(glm::mat4(1.0f), glm::vec3((float(p.slot % 4) - 1.5f) * 1.9f,
                                                                (float(p.slot / 4) - 0.5f) * 1.9f, 0.0f));
  const ecs::Entity entity = addSdf(registry, p.asset, p.method, glm::translate(glm::scale(m, glm::vec3(scale)), -center));
  registry.get<hsdf::HermiteSdfRenderable>(entity).halfPrecision = p.halfPrecision;
  return entity;
}

// The per-record bytes (fp32 and fp16 records, cell cones) of the objects' assets.
std::uint64_t recordBytes(const std::vector<Placed>& objects) {
  std::uint64_t bytes = 0;
  for (const Placed& p : objects) {
    EXPECT_EQ(p.asset->cellsHalf.records.size(), p.asset->cells.records.size());
    bytes += p.asset->cells.records.size() * Cells::kRecordUploadBytes;
  }
  return bytes;
}

// Why: a rebuild of the cell buffers (the assets no longer drawn dropped, or a new run length)
// wrote every drawn asset's records from the CPU again in its frame (the bunny at K = 256: 47 MB);
// the records the old buffers hold must instead be copied on the GPU, and only the assets they lack
// written. Tricky: the kept records move (the dropped asset came first, the new one goes first), so
// cells, fp16 cells, runs and bricks must all find them at their new indices, and the copies,
// recorded in the frame's commands, must be done before that frame's culling passes and draws read
// them (sync validation checks the barrier). So: the CPU writes exactly what the rebuilt buffers
// hold less the kept records, the GPU copies exactly those, and the rebuild frame and the next
// equal the frames of a fresh feature drawing the same objects.
TEST_F(HermiteCellsTest, ARebuildCopiesTheKeptRecordsAndWritesOnlyTheNewAssets) {
  constexpr std::uint32_t size = 96;
  const Placed dropped{bakeAsset("sphere", 56), hsdf::RenderMethod::Cells, false, 0};
  const std::vector<Placed> kept{{bakeAsset("torus", 24), hsdf::RenderMethod::Cells, true, 1},
                                 {bakeAsset("box", 20), hsdf::RenderMethod::CellRuns, false, 2},
                                 {bakeAsset("torus", 28), hsdf::RenderMethod::CellBricks, false, 3},
                                 {bakeAsset("sphere", 20), hsdf::RenderMethod::Cells, false, 5}};
  const Placed arriving{bakeAsset("box", 18), hsdf::RenderMethod::Cells, false, 4};
  const std::uint64_t keptBytes = recordBytes(kept);
  ASSERT_GE(recordBytes({dropped}), keptBytes) << "the dropped asset must hold half of the records: a rebuild";
  const render::CameraView camera =
      render::CameraView::lookAt(glm::vec3(0.0f, 0.0f, 9.0f), glm::vec3(0.0f), 0.9f, 0.1f, 1.0f);
  // The first rebuild's frames draw the cells unculled and untiled: the prepass then reads the
  // records as vertex attributes, which synchronization validation tracks (reads by address it
  // does not). The second rebuild's frames cull, so its copied cell cones are read.
  const auto unculled = [](Cells& cells, bool on) {
    cells.settings().tiles = on ? Cells::Tiles::Off : Cells::Settings{}.tiles;
    cells.settings().cullCells = !on;
  };
  createCellRenderer(size, size);
  auto* feature = renderer_->feature<Cells>();
  feature->settings().releaseAfterFrames = 1000;  // no timed release: the half rule alone
  unculled(*feature, true);
  const ecs::Entity droppedEntity = addPlaced(registry_, dropped);
  for (const Placed& p : kept) addPlaced(registry_, p);
  (void)renderWith(camera, DEBUG_VIEW_NONE);

  // The dropped asset's entity goes and a new asset comes: the buffers are rebuilt.
  ASSERT_TRUE(registry_.destroy(droppedEntity));
  addPlaced(registry_, arriving);
  std::uint64_t uploaded = feature->stats().uploadedBytes, copied = feature->stats().copiedBytes;
  const Frame rebuilt = renderWith(camera, DEBUG_VIEW_NONE);
  const Cells::Stats& stats = feature->stats();
  EXPECT_EQ(stats.gpuBytesHeld, stats.gpuBytes) << "no rebuild: the buffers kept room";
  EXPECT_EQ(stats.copiedBytes - copied, keptBytes) << "the kept records are not what the GPU copied";
  EXPECT_EQ(stats.uploadedBytes - uploaded, stats.gpuBytes - keptBytes) << "the CPU wrote more than the new asset";
  const Frame afterRebuild = renderWith(camera, DEBUG_VIEW_NONE);

  // A new run length: every asset is kept, every record copied.
  std::vector<Placed> drawn = kept;
  drawn.push_back(arriving);
  unculled(*feature, false);
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  feature->settings().maxRunLength = 3;
  uploaded = stats.uploadedBytes;
  copied = stats.copiedBytes;
  const Frame rerun = renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_EQ(stats.copiedBytes - copied, recordBytes(drawn));
  EXPECT_EQ(stats.uploadedBytes - uploaded, stats.gpuBytes - recordBytes(drawn));
  const Frame afterRerun = renderWith(camera, DEBUG_VIEW_NONE);

  for (const std::uint32_t runLength : {8u, 3u}) {  // a fresh feature, the same objects
    createCellRenderer(size, size);
    renderer_->feature<Cells>()->settings().maxRunLength = runLength;
    unculled(*renderer_->feature<Cells>(), runLength == 8);
    (void)renderWith(camera, DEBUG_VIEW_NONE);
    const Frame fresh = renderWith(camera, DEBUG_VIEW_NONE);
    ASSERT_GT(coveredPixels(fresh), std::int64_t(size * size / 8));
    const Frame& first = runLength == 8 ? rebuilt : rerun;
    const Frame& next = runLength == 8 ? afterRebuild : afterRerun;
    EXPECT_TRUE(first.depth == fresh.depth) << "run length " << runLength << ": the rebuild frame";
    EXPECT_TRUE(first.rgba == fresh.rgba) << "run length " << runLength << ": the rebuild frame";
    EXPECT_TRUE(next.depth == fresh.depth) << "run length " << runLength << ": the frame after";
    EXPECT_TRUE(next.rgba == fresh.rgba) << "run length " << runLength << ": the frame after";
  }
}

// A feature drawn after the cell feature whose prepare throws once when told to: the frame fails
// while it is recorded, after the cell feature recorded its work, and nothing of it is submitted.
class FailingFeature final : public render::RenderFeature {
 public:
  std::string_view name() const override { return "failing"; }
  Status initialize(const gpu::Context&, const render::RendererFormats&, std::uint32_t) override { return {}; }
  void prepare(render::FrameContext&) override {
    if (std::exchange(failNext, false)) throw std::runtime_error("a frame failing while it is recorded");
  }
  void recordPass(render::PassContext&) override {}
  bool failNext = false;
};

// Why: a rebuild copies the kept records in its frame's commands, and a frame that fails while it
// is recorded (a later feature's upload out of memory, a failed driver call) is never submitted;
// the rebuilt buffers would then hold nothing of the kept assets for good. The next try of that
// frame must copy them again, from the old buffers, which must still be alive. So: the frame
// after the failed one, and the one after it, equal a fresh feature's frames.
TEST_F(HermiteCellsTest, ARebuildWhoseFrameFailsCopiesTheKeptRecordsInTheNextTry) {
  constexpr std::uint32_t size = 96;
  const Placed dropped{bakeAsset("sphere", 40), hsdf::RenderMethod::Cells, false, 0};
  const Placed kept{bakeAsset("torus", 24), hsdf::RenderMethod::Cells, false, 1};
  const Placed arriving{bakeAsset("box", 16), hsdf::RenderMethod::CellRuns, false, 2};
  ASSERT_GE(recordBytes({dropped}), recordBytes({kept})) << "the dropped asset must hold half of the records";
  const render::CameraView camera =
      render::CameraView::lookAt(glm::vec3(0.0f, 0.0f, 9.0f), glm::vec3(0.0f), 0.9f, 0.1f, 1.0f);
  const auto unculled = [this] {  // the records as vertex attributes, which sync validation tracks
    auto* cells = renderer_->feature<Cells>();
    cells->settings().tiles = Cells::Tiles::Off;
    cells->settings().cullCells = false;
    cells->settings().releaseAfterFrames = 1000;
  };
  createCellRenderer(size, size);
  unculled();
  auto failing = std::make_unique<FailingFeature>();
  FailingFeature* failer = failing.get();
  ASSERT_TRUE(renderer_->addFeature(std::move(failing)).ok());
  const ecs::Entity droppedEntity = addPlaced(registry_, dropped);
  addPlaced(registry_, kept);
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  ASSERT_TRUE(registry_.destroy(droppedEntity));
  addPlaced(registry_, arriving);
  const std::uint64_t copied = renderer_->feature<Cells>()->stats().copiedBytes;
  failer->failNext = true;
  EXPECT_THROW((void)renderer_->renderFrame(registry_, camera, render::FrameSettings{}), std::runtime_error);
  const Frame retried = renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_EQ(renderer_->feature<Cells>()->stats().copiedBytes - copied, recordBytes({kept})) << "no rebuild";
  const Frame next = renderWith(camera, DEBUG_VIEW_NONE);

  createCellRenderer(size, size);  // a fresh feature, the same objects
  unculled();
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  const Frame fresh = renderWith(camera, DEBUG_VIEW_NONE);
  ASSERT_GT(coveredPixels(fresh), std::int64_t(size * size / 20));
  EXPECT_TRUE(retried.depth == fresh.depth) << "the retried frame";
  EXPECT_TRUE(retried.rgba == fresh.rgba) << "the retried frame";
  EXPECT_TRUE(next.depth == fresh.depth) << "the frame after it";
  EXPECT_TRUE(next.rgba == fresh.rgba) << "the frame after it";
}

// Why: the sides of a split screen may draw one entity in other forms (the Viewer's compared side at
// another K, or by a sphere tracer, swaps its asset or method in for its region). While one side's
// new asset is written in parts, that side must keep drawing the asset it drew, and the other side
// its own, every frame; then the side draws its new one, written once. Tricky: the asset an entity
// drew last is one per entity and view region (one per entity drew the other side's asset on the
// side whose new one was not whole, and nothing at all when the other side was traced); a side with
// nothing new must leave the other side's partial upload alone (dropped, it began again every frame
// and was never whole); and a side whose upload appends to or rebuilds the buffers must keep the
// assets only the other side draws (dropped, they are written again). Each case against the split
// frames of a renderer without a budget, which draws each asset in the frame that first wants it
// (the traced side is background: the renderer has the cells alone).
TEST_F(HermiteCellsTest, EachSideOfASplitScreenDrawsItsOwnAssetWhileTheOthersIsWrittenInParts) {
  constexpr std::uint32_t kSide = kSize / 2;
  const auto coarse = bakeAsset("torus", 16);
  const auto fine = bakeAsset("torus", 40);
  const auto other = bakeAsset("sphere", 16);
  ASSERT_TRUE(coarse && fine && other);
  const render::CameraView camera = orbitCamera(*fine, 0);
  std::shared_ptr<const hsdf::SdfAsset> drawn[2];
  hsdf::RenderMethod methods[2] = {hsdf::RenderMethod::Cells, hsdf::RenderMethod::Cells};
  ecs::Entity entity;
  const render::FrameSettings split = splitInHalves(kSide, kSide, [&](std::uint32_t side) {
    auto& r = registry_.get<hsdf::HermiteSdfRenderable>(entity);
    r.asset = drawn[side];
    r.method = methods[side];
  });
  const auto start = [&](std::uint64_t budget, std::shared_ptr<const hsdf::SdfAsset> left,
                         std::shared_ptr<const hsdf::SdfAsset> right) {
    createCellRenderer(kSide, kSide);
    renderer_->feature<Cells>()->settings().uploadBytesPerFrame = budget;
    registry_ = ecs::Registry();
    entity = addSdf(registry_, left, hsdf::RenderMethod::Cells);
    drawn[0] = std::move(left);
    drawn[1] = std::move(right);
  };
  // The bytes a fresh feature uploads for `asset` alone, whole.
  const auto wholeBytes = [&](const std::shared_ptr<const hsdf::SdfAsset>& asset) {
    start(0, asset, asset);
    (void)renderWith(camera, split);
    return renderer_->feature<Cells>()->stats().uploadedBytes;
  };
  const std::uint64_t fineBytes = wholeBytes(fine);
  const std::uint64_t records = fine->cells.records.size();
  const std::uint64_t perFrame = records / 3;
  ASSERT_LT(std::max(coarse->cells.records.size(), other->cells.records.size()), perFrame)
      << "each side's first asset fits a frame's budget (each region uploads its own)";
  struct Case {
    int side;                        // the side whose asset changes
    hsdf::RenderMethod otherMethod;  // the other side's
  };
  for (const Case c : {Case{0, hsdf::RenderMethod::Cells}, Case{1, hsdf::RenderMethod::Cells},
                       Case{0, hsdf::RenderMethod::HermiteSphereTrace}}) {
    const std::string label = fmt::format("side {} changes, the other drawn by method {}", c.side, int(c.otherMethod));
    methods[c.side] = hsdf::RenderMethod::Cells;
    methods[1 - c.side] = c.otherMethod;
    const auto pair = [&](std::shared_ptr<const hsdf::SdfAsset> changed) {
      return c.side == 0 ? std::pair{changed, other} : std::pair{other, changed};
    };
    // The references: budget 0 draws each asset in the frame that first wants it.
    start(0, pair(coarse).first, pair(coarse).second);
    const Frame before = renderWith(camera, split);
    drawn[c.side] = fine;
    const Frame after = renderWith(camera, split);
    ASSERT_FALSE(before.depth == after.depth) << "the two K must draw apart for the test to tell them apart";

    start(perFrame * Cells::kRecordUploadBytes, pair(coarse).first, pair(coarse).second);
    auto* feature = renderer_->feature<Cells>();
    const Frame first = renderWith(camera, split);
    EXPECT_EQ(differingPixels(first, before), 0u) << label << ": each asset fits the budget, drawn at once";
    const std::uint64_t uploaded = feature->stats().uploadedBytes;
    drawn[c.side] = fine;
    int frames = 0;
    for (; frames < 10; ++frames) {
      const Frame frame = renderWith(camera, split);
      if (!feature->uploading()) {
        EXPECT_EQ(differingPixels(frame, after), 0u) << label << ": the new asset once whole";
        break;
      }
      EXPECT_EQ(differingPixels(frame, before), 0u)
          << label << ", frame " << frames << ": a side did not draw the asset it drew before";
    }
    EXPECT_EQ(std::uint64_t(frames), (records + perFrame - 1) / perFrame - 1) << label;
    EXPECT_EQ(feature->stats().uploadedBytes - uploaded, fineBytes)
        << label << ": more than the new asset written (the other side's asset again)";
  }
}

// The assets of the tests of uploads in parts: the torus at K = 16 and at K = 40, with a budget
// that writes the fine one in three or four parts (the coarse one fits a frame's), and a camera.
struct PartsAssets {
  std::shared_ptr<const hsdf::SdfAsset> coarse = bakeAsset("torus", 16);
  std::shared_ptr<const hsdf::SdfAsset> fine = bakeAsset("torus", 40);
  std::uint64_t records = fine ? fine->cells.records.size() : 0;
  std::uint64_t perFrame = records / 3;  // records a frame
  std::uint64_t parts = perFrame ? (records + perFrame - 1) / perFrame : 0;
  std::uint64_t budget() const { return perFrame * Cells::kRecordUploadBytes; }
  render::CameraView camera() const { return orbitCamera(*fine, 0); }
};

// Why: a rebuild of the cell buffers (a new run length, idle assets dropped) while a new asset is
// written in parts began that upload again from its first record (its records so far were after
// the old buffers' and not in the new ones), and an asset whose last part came in the rebuild's
// frame had all its records written from the CPU again. Both are on the GPU already: the rebuild
// must copy them, and the upload go on where it was. So, with the run length changed in a middle
// part's frame and in the last part's: the asset is whole after as many frames as without the
// change, each asset's bytes are written once (the coarse one's runs again at the new length, not
// its records), the GPU copies the kept and the carried records, and every frame equals the frame a
// renderer without a budget draws (the coarse asset until the fine one is whole).
TEST_F(HermiteCellsTest, AnAssetWrittenInPartsGoesOnThroughARebuild) {
  constexpr std::uint32_t kSide = kSize / 2;
  const PartsAssets a;
  ASSERT_TRUE(a.coarse && a.fine);
  const auto& [coarse, fine, records, perFrame, parts] = a;
  const render::CameraView camera = a.camera();
  const std::uint32_t runLengths[2] = {Cells::Settings{}.maxRunLength, Cells::Settings{}.maxRunLength / 2};
  ecs::Entity entity;
  // A fresh feature drawing `asset` as runs of `runLength`, writing `budget` bytes a frame.
  const auto start = [&](std::uint64_t budget, std::uint32_t runLength, std::shared_ptr<const hsdf::SdfAsset> asset) {
    createCellRenderer(kSide, kSide);
    renderer_->feature<Cells>()->settings().uploadBytesPerFrame = budget;
    renderer_->feature<Cells>()->settings().maxRunLength = runLength;
    registry_ = ecs::Registry();
    entity = addSdf(registry_, std::move(asset), hsdf::RenderMethod::CellRuns);
  };
  struct Reference {
    Frame frame;
    std::uint64_t bytes;  // what a fresh feature writes for the asset alone
  };
  const auto reference = [&](const std::shared_ptr<const hsdf::SdfAsset>& asset, std::uint32_t runLength) {
    start(0, runLength, asset);
    Frame frame = renderWith(camera, DEBUG_VIEW_NONE);
    return Reference{std::move(frame), renderer_->feature<Cells>()->stats().uploadedBytes};
  };
  const Reference coarseBefore = reference(coarse, runLengths[0]);
  const Reference coarseAfter = reference(coarse, runLengths[1]);
  const Reference fineAfter = reference(fine, runLengths[1]);
  ASSERT_GT(coveredPixels(coarseAfter.frame), 500);
  ASSERT_FALSE(coarseAfter.frame.depth == fineAfter.frame.depth) << "the two K must draw apart";
  ASSERT_LT(coarse->cells.records.size(), perFrame) << "the coarse asset fits a frame's budget";
  const std::uint64_t coarseRecordBytes = coarse->cells.records.size() * Cells::kRecordUploadBytes;
  const std::uint64_t once = coarseBefore.bytes + (coarseAfter.bytes - coarseRecordBytes) + fineAfter.bytes;
  for (const std::uint64_t changeAt : {std::uint64_t(2), parts}) {  // the part whose frame has the new run length
    const std::string label = fmt::format("run length changed in part {} of {}", changeAt, parts);
    start(a.budget(), runLengths[0], coarse);
    auto* feature = renderer_->feature<Cells>();
    EXPECT_EQ(differingPixels(renderWith(camera, DEBUG_VIEW_NONE), coarseBefore.frame), 0u) << label;
    registry_.get<hsdf::HermiteSdfRenderable>(entity).asset = fine;
    std::uint64_t frames = 0;
    while (frames < 3 * parts) {
      if (++frames == changeAt) feature->settings().maxRunLength = runLengths[1];
      const Frame frame = renderWith(camera, DEBUG_VIEW_NONE);
      if (!feature->uploading()) {
        EXPECT_EQ(differingPixels(frame, fineAfter.frame), 0u) << label << ": the fine asset once whole";
        break;
      }
      EXPECT_EQ(differingPixels(frame, frames < changeAt ? coarseBefore.frame : coarseAfter.frame), 0u)
          << label << ", frame " << frames << ": not the coarse asset";
    }
    const Cells::Stats& stats = feature->stats();
    std::printf("[ parts ] %s: whole after %llu frames, %llu B written (each asset once: %llu), %llu B copied\n",
                label.c_str(), static_cast<unsigned long long>(frames), static_cast<unsigned long long>(stats.uploadedBytes),
                static_cast<unsigned long long>(once), static_cast<unsigned long long>(stats.copiedBytes));
    EXPECT_EQ(frames, parts) << label << ": frames until the fine asset was drawn (begun again?)";
    EXPECT_EQ(stats.uploadedBytes, once) << label << ": bytes written twice";
    const std::uint64_t carried = changeAt < parts ? changeAt * perFrame : records;
    EXPECT_EQ(stats.copiedBytes, coarseRecordBytes + carried * Cells::kRecordUploadBytes)
        << label << ": the GPU did not copy the kept and the fine asset's written records";
  }
}

// Why: each side of a split screen may write its own new asset in parts, one asset at a time. A
// new asset on a side drawn before the side whose large asset was being written began its own
// upload in that frame's round, so the large one began again: a level streaming small assets into
// one side every frame starved a large one on the other side for good. The large one must be whole
// after as many frames as alone, whichever side it is on, the other side drawing what it drew
// until then (its small assets look alike: each frame's is another asset of the same sphere).
TEST_F(HermiteCellsTest, ALargeAssetInPartsOnOneSideIsWholeWhileTheOtherSideStreamsSmallOnes) {
  constexpr std::uint32_t kSide = kSize / 2;
  const PartsAssets a;
  ASSERT_TRUE(a.coarse && a.fine);
  const auto& [coarse, fine, records, perFrame, parts] = a;
  std::vector<std::shared_ptr<const hsdf::SdfAsset>> stream;  // the small side's asset of each frame
  for (int i = 0; i < 12; ++i) stream.push_back(bakeAsset("sphere", 16));
  for (const auto& asset : stream) ASSERT_NE(asset, nullptr);
  const render::CameraView camera = a.camera();
  std::shared_ptr<const hsdf::SdfAsset> drawn[2];
  ecs::Entity entity;
  const render::FrameSettings split = splitInHalves(kSide, kSide, [&](std::uint32_t side) {
    registry_.get<hsdf::HermiteSdfRenderable>(entity).asset = drawn[side];
  });
  const auto start = [&](std::uint64_t budget) {
    createCellRenderer(kSide, kSide);
    renderer_->feature<Cells>()->settings().uploadBytesPerFrame = budget;
    registry_ = ecs::Registry();
    entity = addSdf(registry_, coarse, hsdf::RenderMethod::Cells);
  };
  ASSERT_LT(std::max(coarse->cells.records.size(), stream[0]->cells.records.size()), perFrame);
  for (const int large : {0, 1}) {  // the side whose asset is written in parts
    const int small = 1 - large;
    start(0);  // the references: each asset drawn in the frame that first wants it
    drawn[small] = stream[0];
    drawn[large] = coarse;
    const Frame before = renderWith(camera, split);
    drawn[large] = fine;
    const Frame after = renderWith(camera, split);
    ASSERT_FALSE(before.depth == after.depth);

    start(a.budget());
    auto* feature = renderer_->feature<Cells>();
    drawn[small] = stream[0];
    drawn[large] = coarse;
    EXPECT_EQ(differingPixels(renderWith(camera, split), before), 0u) << "side " << large;
    const std::uint64_t uploaded = feature->stats().uploadedBytes;
    drawn[large] = fine;
    std::size_t frames = 0;
    while (frames + 1 < stream.size()) {
      drawn[small] = stream[++frames];
      const Frame frame = renderWith(camera, split);
      if (differingPixels(frame, after) == 0) break;
      EXPECT_EQ(differingPixels(frame, before), 0u) << "side " << large << ", frame " << frames;
    }
    std::printf("[ parts ] large asset on side %d, a new small one each frame on the other: drawn after %zu frames "
                "(%zu: never), %llu B written\n",
                large, frames, stream.size() - 1,
                static_cast<unsigned long long>(feature->stats().uploadedBytes - uploaded));
    EXPECT_EQ(frames, parts) << "side " << large << ": frames until the large asset was drawn";
  }
}

// Why: a rebuild copies the kept records in its frame's commands, submitted once the frame is
// recorded; a part of a new asset that a later view region of that frame wrote went in its own
// submission before them, and the buffers grown for it took the rebuilt buffers' contents without
// the kept records: the kept assets then drew from memory nothing wrote, for good. That region's
// parts must wait a frame. So, a split whose left side has nothing new while the run length
// changes (it rebuilds) in the frame the right side's asset becomes one written in parts: every
// frame equals the frame of a renderer without a budget (the right side's old asset until the new
// one is whole, one frame later than without the rebuild).
TEST_F(HermiteCellsTest, APartWrittenInARebuildsFrameWaitsForItsCopies) {
  constexpr std::uint32_t kSide = kSize / 2;
  const PartsAssets a;
  const auto other = bakeAsset("sphere", 16);
  ASSERT_TRUE(a.coarse && a.fine && other);
  const auto& [coarse, fine, records, perFrame, parts] = a;
  const render::CameraView camera = a.camera();
  std::shared_ptr<const hsdf::SdfAsset> drawn[2] = {other, coarse};
  ecs::Entity entity;
  const render::FrameSettings split = splitInHalves(kSide, kSide, [&](std::uint32_t side) {
    registry_.get<hsdf::HermiteSdfRenderable>(entity).asset = drawn[side];
  });
  const std::uint32_t runLength = Cells::Settings{}.maxRunLength / 2;
  const auto start = [&](std::uint64_t budget) {
    createCellRenderer(kSide, kSide);
    renderer_->feature<Cells>()->settings().uploadBytesPerFrame = budget;
    renderer_->feature<Cells>()->settings().tiles = Cells::Tiles::Off;  // the records as vertex attributes
    registry_ = ecs::Registry();
    entity = addSdf(registry_, other, hsdf::RenderMethod::Cells);
    drawn[1] = coarse;
  };
  start(0);  // the references, at the new run length
  renderer_->feature<Cells>()->settings().maxRunLength = runLength;
  const Frame before = renderWith(camera, split);
  drawn[1] = fine;
  const Frame after = renderWith(camera, split);
  ASSERT_FALSE(before.depth == after.depth);

  start(a.budget());
  auto* feature = renderer_->feature<Cells>();
  (void)renderWith(camera, split);
  feature->settings().maxRunLength = runLength;
  drawn[1] = fine;
  std::uint64_t frames = 0;
  const std::uint64_t copied = feature->stats().copiedBytes;
  while (frames < 3 * parts) {
    ++frames;
    const Frame frame = renderWith(camera, split);
    if (!feature->uploading()) {
      EXPECT_EQ(differingPixels(frame, after), 0u) << "the new asset once whole";
      break;
    }
    EXPECT_EQ(differingPixels(frame, before), 0u) << "frame " << frames << ": not what the sides drew before";
  }
  EXPECT_GT(feature->stats().copiedBytes, copied) << "no rebuild";
  EXPECT_EQ(frames, parts + 1) << "frames until the new asset was drawn";
}

// A walk's scene: one entity that each side of an optional split draws in its own form, a second
// object that comes and goes, and the cell settings; `log` lists the changes, so a failure replays.
struct StreamWalk {
  struct Side {
    std::shared_ptr<const hsdf::SdfAsset> asset;
    hsdf::RenderMethod method = hsdf::RenderMethod::Cells;
    bool half = false;
  };
  std::vector<std::shared_ptr<const hsdf::SdfAsset>> pool;
  ecs::Registry* registry = nullptr;
  ecs::Entity entity, second;
  glm::mat4 beside{1.0f};
  Side sides[2];
  bool split = false;
  Cells::Settings cells;
  std::string log;

  // The frame's settings: the split's regions show each side's form, else the entity shows side 0's.
  render::FrameSettings frameSettings(std::uint32_t width, std::uint32_t height) {
    if (split) return splitInHalves(width, height, [this](std::uint32_t side) { show(sides[side]); });
    show(sides[0]);
    return {};
  }
  void show(const Side& side) {
    auto& r = registry->get<hsdf::HermiteSdfRenderable>(entity);
    r.asset = side.asset;
    r.method = side.method;
    r.halfPrecision = side.half;
  }
  // One random change of frame `frame`, added to the log.
  void change(std::mt19937& random, int frame) {
    const auto pick = [&random](std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(random); };
    static constexpr hsdf::RenderMethod kMethods[] = {hsdf::RenderMethod::Cells, hsdf::RenderMethod::CellRuns,
                                                      hsdf::RenderMethod::CellBricks};
    Side& side = sides[pick(2)];
    const std::string name = &side == &sides[0] ? "side0" : "side1";
    switch (pick(9)) {
      case 0:
        side.asset = pool[pick(pool.size())];
        return note(frame, name + ".K", side.asset->cells.grid.resolution);
      case 1:
        side.method = kMethods[pick(3)];
        return note(frame, name + ".method", int(side.method));
      case 2:
        side.half = !side.half;
        return note(frame, name + ".fp16", side.half);
      case 3:
        split = !split;
        return note(frame, "split", split);
      case 4:
        cells.maxRunLength = 4u << pick(3);
        return note(frame, "runs", cells.maxRunLength);
      case 5:
        cells.tiles = cells.tiles == Cells::Tiles::On ? Cells::Tiles::Off : Cells::Tiles::On;
        return note(frame, "tiles", int(cells.tiles));
      case 6:
        cells.cullOcclusion = !cells.cullOcclusion;
        return note(frame, "occlusion", cells.cullOcclusion);
      case 7:
        registry->get<hsdf::HermiteSdfRenderable>(second).asset = pool[pick(pool.size())];
        return note(frame, "second.asset", registry->get<hsdf::HermiteSdfRenderable>(second).asset->cells.grid.resolution);
      default:  // destroyed and made again: the new entity takes the freed index
        registry->destroy(second);
        second = addSdf(*registry, pool[pick(pool.size())], kMethods[pick(3)], beside);
        return note(frame, "second.again", second);
    }
  }
  template <class T>
  void note(int frame, const std::string& what, const T& value) {
    log += fmt::format(" {}:{}={}", frame, what, value);
  }
};

// Why: a game changes settings while assets stream in (the sides of a split at other K, a level of
// detail switching, the panel's method, fp16, run length, tiles, occlusion culling), and the cell
// feature keeps state for all of it from frame to frame (an asset written in parts and the region
// that began it, the asset each entity drew per view region, runs of the old length, bricks
// uploaded or not, an object destroyed and made again on a reused index). However the walk went,
// once no upload is pending the frame must be the one a fresh renderer draws of the same scene
// and settings (uploading every asset in its first frame). Seeded; HSDF_STREAM_WALKS=N walks N
// seeds (1 here), each of 24 frames with 1-2 random changes a frame, settled and compared at
// frames 8, 16 and 24. The message lists the walk, so a failure replays.
TEST_F(HermiteCellsTest, WalksThroughSettingsWhileAssetsStreamSettleOnAFreshRenderersFrame) {
  const std::vector<std::shared_ptr<const hsdf::SdfAsset>> pool = {bakeAsset("torus", 16), bakeAsset("torus", 40),
                                                                   bakeAsset("sphere", 16), bakeAsset("box", 24)};
  for (const auto& asset : pool) ASSERT_NE(asset, nullptr);
  const render::CameraView camera = orbitCamera(*pool[1], 0, 2.6f);
  constexpr std::uint32_t kSide = kSize / 2;
  const char* seedsText = std::getenv("HSDF_STREAM_WALKS");
  const int seeds = seedsText ? std::max(1, std::atoi(seedsText)) : 1;
  int settles = 0;
  for (int seed = 1; seed <= seeds; ++seed) {
    std::mt19937 random(std::uint32_t(20261207 + seed));
    StreamWalk walk;
    walk.pool = pool;
    walk.registry = &registry_;
    walk.beside = glm::translate(glm::mat4(1.0f), glm::vec3(-1.2f, 0.3f, -0.5f));
    walk.sides[0].asset = pool[0];
    walk.sides[1].asset = pool[2];
    walk.cells.tiles = Cells::Tiles::Off;
    walk.cells.uploadBytesPerFrame = pool[1]->cells.records.size() / 3 * Cells::kRecordUploadBytes;
    createCellRenderer(kSide, kSide);
    auto* feature = renderer_->feature<Cells>();
    registry_ = ecs::Registry();
    walk.entity = addSdf(registry_, pool[0], hsdf::RenderMethod::Cells);
    walk.second = addSdf(registry_, pool[3], hsdf::RenderMethod::Cells, walk.beside);
    for (int frame = 1; frame <= 24; ++frame) {
      const int changes = 1 + int(random() % 2);
      for (int c = 0; c < changes; ++c) walk.change(random, frame);
      feature->settings() = walk.cells;
      (void)renderWith(camera, walk.frameSettings(kSide, kSide));
      if (frame % 8 != 0) continue;
      // Settled: no upload pending (at most 12 frames).
      Frame settled = renderWith(camera, walk.frameSettings(kSide, kSide));
      for (int extra = 0; extra < 12 && feature->uploading(); ++extra)
        settled = renderWith(camera, walk.frameSettings(kSide, kSide));
      ASSERT_FALSE(feature->uploading()) << "seed " << seed << ": still uploading after 12 frames; walk:" << walk.log;
      render::Renderer fresh(*context_, render::RendererDesc{}, VkExtent2D{kSide, kSide});
      ASSERT_TRUE(fresh.addFeature(std::make_unique<Cells>()).ok());
      fresh.feature<Cells>()->settings() = walk.cells;
      fresh.feature<Cells>()->settings().uploadBytesPerFrame = 0;
      fresh.renderFrame(registry_, camera, walk.frameSettings(kSide, kSide));
      Frame freshFrame = settled;
      freshFrame.rgba = fresh.readbackColor();
      freshFrame.depth = fresh.readbackDepth();
      EXPECT_GT(coveredPixels(settled), 100) << "seed " << seed << ", frame " << frame;
      EXPECT_EQ(differingPixels(settled, freshFrame), 0u)
          << "seed " << seed << ", frame " << frame << " differs from a fresh renderer's; walk:" << walk.log;
      ++settles;
    }
  }
  std::printf("[ stream walks ] %d seeds, %d settled frames compared\n", seeds, settles);
}

// Not a check, a measurement (docs/perf/render-changes-session31.md): the render-thread time of the
// frame that first draws the bunny (K = 128, 256; unculled cells), of the frames that then draw it
// as culled cells, bricks and runs, each followed by a frame of the same form (what the form costs
// without any upload); then of the frame that first draws 200 spheres (K = 16) of their own as
// culled cells. Run by hand:
//   hermite_cells_gpu_tests --gtest_also_run_disabled_tests --gtest_filter='*FirstDrawFrameTimes'
TEST_F(HermiteCellsTest, DISABLED_FirstDrawFrameTimes) {
  createCellRenderer(kSize, kSize);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;
  feature->settings().uploadBytesPerFrame = 0;  // each asset whole in its first frame (FirstDrawFramesUnderTheBudget)
  for (const int resolution : {128, 256}) {
    const auto asset = bakeBunnyOnWorker(resolution);
    ASSERT_NE(asset, nullptr);
    const render::CameraView camera = orbitCamera(*asset, 0);
    feature->settings().cullCells = false;
    const ecs::Entity entity = addSdf(registry_, asset, hsdf::RenderMethod::Cells);
    struct Step {
      const char* label;
      hsdf::RenderMethod method;
      bool cullCells;
    };
    for (const Step step : {Step{"first draw, unculled cells", hsdf::RenderMethod::Cells, false},
                            Step{"culled cells", hsdf::RenderMethod::Cells, true},
                            Step{"bricks", hsdf::RenderMethod::CellBricks, true},
                            Step{"runs", hsdf::RenderMethod::CellRuns, true}}) {
      registry_.get<hsdf::HermiteSdfRenderable>(entity).method = step.method;
      feature->settings().cullCells = step.cullCells;
      const double first = frameMilliseconds(*renderer_, registry_, camera);
      (void)renderer_->readbackDepth();
      const double next = frameMilliseconds(*renderer_, registry_, camera);
      (void)renderer_->readbackDepth();
      std::printf("[ K = %d, %zu cells ] %-28s frame %8.1f ms, next frame %6.1f ms\n", resolution,
                  asset->cells.records.size(), step.label, first, next);
    }
    registry_.destroy(entity);
  }
  // Many small assets of their own (a game's level), first drawn in one frame as culled cells.
  feature->settings().cullCells = true;
  constexpr int kAssets = 200;
  hsdf::BakeSettings settings;
  settings.resolution = 16;
  for (int i = 0; i < kAssets; ++i) {
    hsdf::BakeJob job(hsdf::BakeSource::fromShape("sphere"), settings);
    hsdf::BakeJob::Result sphere = job.wait();
    ASSERT_TRUE(sphere.ok()) << sphere.error().message;
    const glm::mat4 place = glm::translate(glm::mat4(1.0f), glm::vec3(float(i % 20) * 2.5f, float(i / 20) * 2.5f, 0.0f));
    addSdf(registry_, *sphere, hsdf::RenderMethod::Cells, place);
  }
  const render::CameraView camera =
      render::CameraView::lookAt(glm::vec3(24.0f, 12.0f, 60.0f), glm::vec3(24.0f, 12.0f, 0.0f), 0.9f, 0.1f, 1.0f);
  const double first = frameMilliseconds(*renderer_, registry_, camera);
  (void)renderer_->readbackDepth();
  const double next = frameMilliseconds(*renderer_, registry_, camera);
  (void)renderer_->readbackDepth();
  std::printf("[ %d spheres, K = 16 ] first draw, culled cells   frame %8.1f ms, next frame %6.1f ms\n", kAssets, first,
              next);
}


// Not a check, a measurement (docs/perf/render-changes-session34.md, -session35.md): the
// render-thread time of every frame from the one that first wants the bunny (K = 128, 256; unculled
// cells, pipelines compiled by the frames of a small asset drawn before and by their warmer,
// buffers made) until it is drawn, and the MB each uploads, then of one frame more (the drawing
// alone), with no limit (budget 0, every record in the first frame) and with the default budget per
// frame, alternated twice (the first run after a bake also pays for new memory). Run by hand:
//   hermite_cells_gpu_tests --gtest_also_run_disabled_tests --gtest_filter='*FirstDrawFramesUnderTheBudget'
TEST_F(HermiteCellsTest, DISABLED_FirstDrawFramesUnderTheBudget) {
  const std::uint64_t defaultBudget = hsdf::HermiteCellFeature::Settings{}.uploadBytesPerFrame;
  const auto sphere = bakeAsset("sphere", 16);
  ASSERT_NE(sphere, nullptr);
  for (const int resolution : {128, 256}) {
    const auto asset = bakeBunnyOnWorker(resolution);
    ASSERT_NE(asset, nullptr);
    const render::CameraView camera = orbitCamera(*asset, 0);
    for (const std::uint64_t budget : {std::uint64_t(0), defaultBudget, std::uint64_t(0), defaultBudget}) {
      registry_.clear();
      createCellRenderer(kSize, kSize);
      auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
      feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;
      feature->settings().cullCells = false;
      feature->settings().uploadBytesPerFrame = budget;
      addSdf(registry_, sphere, hsdf::RenderMethod::Cells, glm::translate(glm::mat4(1.0f), glm::vec3(4.0f, 0.0f, 0.0f)));
      for (int warm = 0; warm < 2; ++warm) (void)frameMilliseconds(*renderer_, registry_, camera);
      feature->waitForWarmPipelines();  // as a viewer's seconds before the asset comes: no compile measured
      renderer_->finish();
      addSdf(registry_, asset, hsdf::RenderMethod::Cells);
      std::string frames;
      double slowest = 0.0;
      int count = 0;
      std::uint64_t uploaded = feature->stats().uploadedBytes;
      do {
        const double ms = frameMilliseconds(*renderer_, registry_, camera);
        (void)renderer_->readbackDepth();
        frames += fmt::format(" {:.1f} ({:.1f} MB)", ms, double(feature->stats().uploadedBytes - uploaded) * 1e-6);
        uploaded = feature->stats().uploadedBytes;
        slowest = std::max(slowest, ms);
        ++count;
      } while (feature->uploading() && count < 1000);
      const double next = frameMilliseconds(*renderer_, registry_, camera);  // drawn, nothing uploaded
      (void)renderer_->readbackDepth();
      std::printf("[ K = %d, %zu cells ] budget %3llu MiB: %d frames until drawn, slowest %.1f ms:%s; next %.1f ms\n",
                  resolution, asset->cells.records.size(), static_cast<unsigned long long>(budget >> 20), count,
                  slowest, frames.c_str(), next);
    }
  }
}


// Milliseconds of renderFrame and of the wait for the frame's GPU work (finish): the CPU time of a
// frame that records GPU copies includes them.
double frameAndFinishMilliseconds(render::Renderer& renderer, const ecs::Registry& registry,
                                  const render::CameraView& camera) {
  const auto start = std::chrono::steady_clock::now();
  EXPECT_TRUE(renderer.renderFrame(registry, camera, render::FrameSettings{}));
  renderer.finish();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Not a check, a measurement (docs/perf/render-changes-session38.md, docs/reliability.md): the
// frames of two rebuilds of the cell buffers, each frame's renderFrame + finish and the MB it
// wrote from the CPU and copied on the GPU, at 64x64: 16 bunnies (K = 48, assets of their own) of
// which 8 are then no longer drawn (releaseAfterFrames = 2: the idle release rebuilds), and the
// bunny at K = 256 whose run length changes (8 -> 4 -> 8 -> 4 -> 8). Run by hand:
//   hermite_cells_gpu_tests --gtest_also_run_disabled_tests --gtest_filter='*RebuildFrameTimes'
TEST_F(HermiteCellsTest, DISABLED_RebuildFrameTimes) {
  createCellRenderer(64, 64);  // small: the frames are mostly drawing on lavapipe
  auto* feature = renderer_->feature<Cells>();
  feature->settings().releaseAfterFrames = 2;
  const auto frameLine = [&](const char* label, double ms, std::uint64_t uploaded, std::uint64_t copied) {
    std::printf("%-36s %8.1f ms, written %6.1f MB, copied %6.1f MB\n", label, ms,
                double(feature->stats().uploadedBytes - uploaded) * 1e-6, double(feature->stats().copiedBytes - copied) * 1e-6);
  };
  const auto measured = [&](const char* label, const render::CameraView& camera) {
    const std::uint64_t uploaded = feature->stats().uploadedBytes, copied = feature->stats().copiedBytes;
    const double ms = frameAndFinishMilliseconds(*renderer_, registry_, camera);
    frameLine(label, ms, uploaded, copied);
  };
  std::vector<ecs::Entity> bunnies;
  for (int i = 0; i < 16; ++i) {
    const auto asset = bakeBunnyOnWorker(48);
    ASSERT_NE(asset, nullptr);
    const glm::mat4 place = glm::translate(glm::mat4(1.0f), glm::vec3(float(i % 4) * 1.2f, float(i / 4) * 1.2f, 0.0f));
    bunnies.push_back(addSdf(registry_, asset, hsdf::RenderMethod::Cells, place));
  }
  const render::CameraView many =
      render::CameraView::lookAt(glm::vec3(1.8f, 1.8f, 8.0f), glm::vec3(1.8f, 1.8f, 0.0f), 0.9f, 0.1f, 1.0f);
  for (int warm = 0; warm < 3; ++warm) (void)frameAndFinishMilliseconds(*renderer_, registry_, many);
  feature->waitForWarmPipelines();
  std::printf("16 bunnies, K = 48: %.1f MB of cell buffers\n", double(feature->stats().gpuBytes) * 1e-6);
  for (int i = 0; i < 8; ++i) registry_.destroy(bunnies[std::size_t(i)]);
  for (int frame = 0; frame < 6; ++frame) measured(fmt::format("8 of 16 dropped, frame {}", frame).c_str(), many);

  registry_.clear();
  const auto bunny = bakeBunnyOnWorker(256);
  ASSERT_NE(bunny, nullptr);
  addSdf(registry_, bunny, hsdf::RenderMethod::Cells);
  const render::CameraView camera = orbitCamera(*bunny, 0);
  for (int warm = 0; warm < 3; ++warm) (void)frameAndFinishMilliseconds(*renderer_, registry_, camera);
  feature->waitForWarmPipelines();
  for (const std::uint32_t runLength : {4u, 8u, 4u, 8u}) {
    feature->settings().maxRunLength = runLength;
    measured(fmt::format("K = 256 ({} cells), run length {}", bunny->cells.records.size(), runLength).c_str(), camera);
    measured("  next frame", camera);
  }
}

}  // namespace
}  // namespace gputest
