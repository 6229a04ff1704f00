// The culling passes before the cells' prepass (cell_culling.cpp, brick_culler.cpp, cell_cull.comp,
// brick_cull.comp; the two-phase occlusion culling against the depth pyramid): what they remove
// never changes the image, and they remove work.
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

#include "engine/core/image_io.h"
#include "engine/core/math.h"
#include "engine/gpu/context.h"
#include "engine/gpu/memory.h"
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

// Why: the brick culling pass (brick_cull.comp) decides on the GPU which bricks are drawn, from
// normal cones and the frustum; a brick it wrongly removes is a hole, and one it keeps needlessly
// is only cost. So: the image (depth and colour) is identical with culling on and off, on a
// concave object seen from several sides, the pass reports that it removed bricks, and the
// prepass rasterizes fewer fragments (pipeline statistics: what lavapipe counts before the depth
// test falls only when boxes are not drawn).
TEST_F(HermiteCellsTest, BrickCullingKeepsTheImageAndDrawsFewerBricks) {
  createCellRenderer(kSize, kSize);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  const auto asset = bakeAsset("bunny", 64);
  ASSERT_NE(asset, nullptr);
  ASSERT_TRUE(asset->boundaryPositive);
  addSdf(registry_, asset, hsdf::RenderMethod::CellBricks);
  auto fragments = [&] {
    const auto* s = gpu::findStatistics(renderer_->lastPipelineStatistics(), "depth prepass");
    return s ? s->fragmentShaderInvocations : 0;
  };
  std::uint64_t tested = 0, kept = 0, allSum = 0, culledSum = 0;
  const bool inOrder = tolerancesFor(*context_).fragmentsShadeInPrimitiveOrder;
  for (int view = 0; view < 6; ++view) {
    SCOPED_TRACE("view " + std::to_string(view));
    const render::CameraView camera = orbitCamera(*asset, view);
    feature->settings().cullBricks = false;
    const Frame all = renderWith(camera, DEBUG_VIEW_NONE);
    const std::uint64_t allFragments = fragments();
    EXPECT_EQ(feature->cullTotals().tested, 0u) << "no culling pass when it is off";
    feature->settings().cullBricks = true;
    const Frame culled = renderWith(camera, DEBUG_VIEW_NONE);
    const shader::BrickCullTotals totals = feature->cullTotals();
    EXPECT_EQ(totals.tested, feature->stats().bricks);
    EXPECT_EQ(totals.kept + totals.frustumCulled + totals.coneCulled, totals.tested);
    tested += totals.tested;
    kept += totals.kept;
    ASSERT_GT(std::count_if(culled.depth.begin(), culled.depth.end(), [](float d) { return d > 0.0f; }), 500);
    EXPECT_TRUE(all.depth == culled.depth) << "culling changed the depth";
    EXPECT_TRUE(all.rgba == culled.rgba) << "culling changed the colour";
    allSum += allFragments;
    culledSum += fragments();
    // In primitive order (lavapipe) every view's count can only fall. A GPU counts the fragments
    // its early depth test let through, which depends on the order its parallel fragments happen to
    // write depth: one H200 view of six had 0.6 % more with culling; the six views together fall.
    if (allFragments > 0 && inOrder) {
      EXPECT_LE(fragments(), allFragments);
    }
  }
  EXPECT_LT(kept, tested) << "the cones removed no brick of the bunny in six views";
  if (allSum > 0) {
    EXPECT_LT(culledSum, allSum) << "culling drew no fewer prepass fragments over six views";
  }
}

// Why: the cell culling pass (cell_cull.comp) decides on the GPU which cells' boxes are drawn and
// rewrites the draws to read its kept-record stream (attribute boxes, with and without the early
// depth stage, and thin boxes; fp32 and fp16 records). A cell it wrongly removes is a hole, a
// wrong record index a wrong shade, and a lost order a different winner where hits tie. So: depth
// and colour identical with culling on and off on the concave bunny from several sides, the pass
// reports that its cones and the frustum removed cells, and the prepass rasterizes fewer fragments.
// Then from inside a cell, where the near plane lies in the grid: the cone test must stay off (no
// cone-culled cell) and the image must still be the same.
TEST_F(HermiteCellsTest, CellCullingKeepsTheImageAndDrawsFewerBoxes) {
  createCellRenderer(kSize, kSize);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  feature->settings().cullOcclusion = false;  // frustum and cones alone (occlusion: the test below)
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;  // boxes, culled or not (tiles: TiledCells*)
  const auto asset = bakeAsset("bunny", 64);
  ASSERT_NE(asset, nullptr);
  ASSERT_TRUE(asset->boundaryPositive);
  const ecs::Entity entity = addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  auto fragments = [&] {
    const auto* s = gpu::findStatistics(renderer_->lastPipelineStatistics(), "depth prepass");
    return s ? s->fragmentShaderInvocations : 0;
  };
  const bool inOrder = tolerancesFor(*context_).fragmentsShadeInPrimitiveOrder;
  using ThinBoxes = hsdf::HermiteCellFeature::ThinBoxes;
  struct Case {
    const char* label;
    ThinBoxes thin;
    bool half;
    int firstView, viewStep;
  };
  const Case cases[] = {{"attribute boxes fp32", ThinBoxes::Off, false, 0, 1},
                        {"thin boxes fp32", ThinBoxes::On, false, 1, 2},
                        {"attribute boxes fp16", ThinBoxes::Off, true, 0, 2},
                        {"thin boxes fp16", ThinBoxes::On, true, 1, 2}};
  for (const Case& c : cases) {
    feature->settings().thinBoxes = c.thin;
    registry_.get<hsdf::HermiteSdfRenderable>(entity).halfPrecision = c.half;
    std::uint64_t tested = 0, kept = 0, coneCulled = 0, allSum = 0, culledSum = 0;
    for (int view = c.firstView; view < 6; view += c.viewStep) {
      SCOPED_TRACE(std::string(c.label) + ", view " + std::to_string(view));
      const render::CameraView camera = orbitCamera(*asset, view);
      feature->settings().cullCells = false;
      const Frame all = renderWith(camera, DEBUG_VIEW_NONE);
      const std::uint64_t allFragments = fragments();
      EXPECT_EQ(feature->cullTotals().tested, 0u) << "no culling pass when it is off";
      feature->settings().cullCells = true;
      const Frame culled = renderWith(camera, DEBUG_VIEW_NONE);
      const shader::BrickCullTotals totals = feature->cullTotals();
      EXPECT_EQ(totals.tested, feature->stats().cells) << "every front-face cell is tested once";
      EXPECT_EQ(totals.kept + totals.frustumCulled + totals.coneCulled, totals.tested);
      tested += totals.tested;
      kept += totals.kept;
      coneCulled += totals.coneCulled;
      ASSERT_GT(std::count_if(culled.depth.begin(), culled.depth.end(), [](float d) { return d > 0.0f; }), 500);
      EXPECT_TRUE(all.depth == culled.depth) << "culling changed the depth";
      EXPECT_TRUE(all.rgba == culled.rgba) << "culling changed the colour";
      allSum += allFragments;
      culledSum += fragments();
      // In primitive order (lavapipe) every view's count can only fall; a GPU's early depth test
      // depends on the order its parallel fragments write depth (see the bricks' test).
      if (allFragments > 0 && inOrder) {
        EXPECT_LT(fragments(), allFragments);
      }
    }
    SCOPED_TRACE(c.label);
    EXPECT_GT(coneCulled, 0u) << "the cones removed no cell of the bunny";
    // Most of the back half goes (55 % of the cells kept here at K = 64; cells near the silhouette,
    // whose cones are wide or face sideways, stay).
    EXPECT_LT(double(kept), 0.65 * double(tested)) << "the cones kept nearly every cell of the bunny";
    if (allSum > 0) {
      EXPECT_LT(culledSum, allSum) << "culling drew no fewer prepass fragments";
    }
  }

  // Inside a cell of the torus: the near plane in the grid turns the cone test off.
  feature->settings().thinBoxes = ThinBoxes::Off;
  registry_ = ecs::Registry();
  const auto torus = bakeAsset("torus", 16);
  ASSERT_NE(torus, nullptr);
  addSdf(registry_, torus, hsdf::RenderMethod::Cells);
  const std::optional<render::CameraView> inside = insideACellCamera(*torus);
  ASSERT_TRUE(inside);
  feature->settings().cullCells = false;
  const Frame all = renderWith(*inside, DEBUG_VIEW_NONE);
  feature->settings().cullCells = true;
  const Frame culled = renderWith(*inside, DEBUG_VIEW_NONE);
  EXPECT_GT(feature->stats().nearCells, 0u);
  const shader::BrickCullTotals totals = feature->cullTotals();
  EXPECT_GT(totals.tested, 0u);
  EXPECT_EQ(totals.coneCulled, 0u) << "the near plane lies in the grid: no cone test";
  EXPECT_GT(totals.frustumCulled, 0u) << "from inside the torus most cells are off screen";
  EXPECT_TRUE(all.depth == culled.depth) << "culling changed the depth inside a cell";
  EXPECT_TRUE(all.rgba == culled.rgba) << "culling changed the colour inside a cell";
}

// Why: a world holds many objects, most of them out of view; one whose grid box lies outside the
// frustum must cost no commands, no culling work and no room in the kept streams, for every cell
// method, and one that only reaches into the view (its box across a frustum plane) must still be
// drawn. So: the object in view alone, then with copies beside the view, behind the camera and
// nearer than the near plane, and one across the left edge: the same pixels where the first one is
// drawn, the hidden copies counted as outside the view and never tested by the culling pass.
TEST_F(HermiteCellsTest, ObjectsOutsideTheViewAreNotDrawn) {
  createCellRenderer(kSize, kSize);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  const auto asset = bakeAsset("bunny", 16);
  ASSERT_NE(asset, nullptr);
  const glm::vec3 center(asset->surfaceBounds.center());
  const float extent = float(glm::length(asset->surfaceBounds.size()));
  const render::CameraView camera =
      render::CameraView::lookAt(center + glm::vec3(0.0f, 0.0f, 2.0f * extent), center, 0.8f, 0.5f * extent, 1.0f);
  // The asset moved by `offset` and scaled by `scale` about its centre.
  const auto at = [&](const glm::vec3& offset, float scale = 1.0f) {
    return glm::translate(glm::mat4(1.0f), center + offset) * glm::scale(glm::mat4(1.0f), glm::vec3(scale)) *
           glm::translate(glm::mat4(1.0f), -center);
  };
  for (const hsdf::RenderMethod method : {hsdf::RenderMethod::Cells, hsdf::RenderMethod::CellRuns, hsdf::RenderMethod::CellBricks}) {
    SCOPED_TRACE(hsdf::renderMethodName(method));
    registry_ = ecs::Registry();
    addSdf(registry_, asset, method);
    const Frame alone = renderWith(camera, DEBUG_VIEW_NONE);
    EXPECT_EQ(feature->stats().culledObjects, 0u);
    const std::uint64_t tested = feature->cullTotals().tested;
    ASSERT_GT(std::count_if(alone.depth.begin(), alone.depth.end(), [](float d) { return d > 0.0f; }), 1000);
    addSdf(registry_, asset, method, at({8.0f * extent, 0.0f, 0.0f}));    // far to the right
    addSdf(registry_, asset, method, at({0.0f, 0.0f, 5.0f * extent}));    // behind the camera
    addSdf(registry_, asset, method, at({0.0f, 0.0f, 1.75f * extent}, 0.1f));  // between the eye and the near plane
    const Frame hidden = renderWith(camera, DEBUG_VIEW_NONE);
    EXPECT_EQ(feature->stats().culledObjects, 3u);
    EXPECT_EQ(feature->stats().objects, 1u);
    EXPECT_EQ(feature->cullTotals().tested, tested) << "the culling pass tested cells of objects out of view";
    EXPECT_TRUE(alone.depth == hidden.depth) << "objects out of view changed the image";
    // A copy whose box crosses the left edge of the view is drawn.
    const float halfWidth = 2.0f * extent * std::tan(0.4f);
    addSdf(registry_, asset, method, at({-halfWidth - 0.1f * extent, 0.0f, 0.0f}));
    const Frame edge = renderWith(camera, DEBUG_VIEW_NONE);
    EXPECT_EQ(feature->stats().culledObjects, 3u);
    EXPECT_EQ(feature->stats().objects, 2u);
    int leftColumn = 0;
    for (std::uint32_t y = 0; y < kSize; ++y) leftColumn += edge.depthAt(0, y) > 0.0f;
    EXPECT_GT(leftColumn, 0) << "the copy across the left edge was not drawn";
  }
}

// The kept streams' tests: a cell renderer with instances of the bunny at K = 32 in rows of three
// facing the camera, 0.6 of the object's extent apart (three to start with), and that camera.
class KeptStreamsTest : public HermiteCellsTest {
 protected:
  void startBunnies() {
    registry_ = ecs::Registry{};
    renderer_.reset();
    instances_ = 0;
    bunnies_.clear();
    createCellRenderer(kSize, kSize);
    feature_ = renderer_->feature<hsdf::HermiteCellFeature>();
    asset_ = bakeAsset("bunny", 32);
    ASSERT_NE(asset_, nullptr);
    addBunnies(3);
    camera_ = orbitCamera(*asset_, 1, 3.0f);
  }
  void addBunnies(int more) {
    for (int i = 0; i < more; ++i, ++instances_) bunnies_.push_back(addBunnyAt(instances_));
  }
  // The i-th place of the rows (another bunny there overlaps the one placed first).
  ecs::Entity addBunnyAt(int i) {
    const float extent = float(glm::length(asset_->surfaceBounds.size()));
    return addSdf(registry_, asset_, hsdf::RenderMethod::Cells,
                  glm::translate(glm::mat4(1.0f), glm::vec3(float(i % 3 - 1) * 0.6f * extent,
                                                            float(i / 3) * 0.6f * extent, 0.0f)));
  }
  std::vector<ecs::Entity> bunnies_;
  hsdf::HermiteCellFeature* feature_ = nullptr;
  std::shared_ptr<const hsdf::SdfAsset> asset_;
  render::CameraView camera_;
  int instances_ = 0;
};

// Why: the kept-cell streams hold every cell of every culled object only up to
// Settings::keptStreamBytes; past it (scenes of many instances: 10,000 bunnies at K = 32 would need
// 5.9 GB per frame slot) they are sized by the share of its culled cells the slot's last frame
// kept, so a frame can keep more than they hold: a view that keeps a larger share than the last
// one (here: the camera pulls back from close to one bunny, where the frustum culled most cells), or
// a frame whose streams the allocator's budget stops from growing. Such a frame must not lose a
// cell: each row whose kept cells do not fit is drawn whole and unculled (its fallback command),
// the image of culling off, and the next frames' streams grow to what the frame wanted. With
// boxes, with occlusion culling (whose second phase appends to the same streams and draws the
// fallbacks again) and with tiles (which must skip the holes that a row that did not fit leaves in
// the streams). A mutant that drops the fallback draw loses the rows; one that grows nothing keeps
// falling back; one that sizes by the last frame's count instead of its share falls back on the
// first frame of three times the instances.
TEST_F(KeptStreamsTest, KeptCellsPastTheStreamsDrawTheirRowsUnculled) {
  using Tiles = hsdf::HermiteCellFeature::Tiles;
  struct Mode {
    const char* name;
    Tiles tiles;
    bool occlusion;
  };
  for (const Mode mode : {Mode{"boxes", Tiles::Off, false}, Mode{"occlusion culling", Tiles::Off, true},
                          Mode{"tiles", Tiles::On, false}}) {
    SCOPED_TRACE(mode.name);
    startBunnies();
    auto* feature = feature_;
    const render::CameraView camera = camera_;
    hsdf::HermiteCellFeature::Settings& settings = feature->settings();
    settings.tiles = mode.tiles;
    settings.cullOcclusion = mode.occlusion;
    settings.cullCells = true;
    settings.keptStreamBytes = 64 << 10;  // 450 fp32 slots: less than one bunny keeps
    // The same frame with every cell in the streams, rendered after the frames under test (its
    // streams would hold everything later frames keep): the image each fallback must reproduce
    // (tiles and boxes differ where roots tie, so tiles with fallback rows are compared with tiles).
    const auto reference = [&] {
      settings.cullCells = mode.tiles == Tiles::On;
      settings.keptStreamBytes = std::uint64_t(1) << 30;
      const Frame frame = renderWith(camera, DEBUG_VIEW_NONE);
      EXPECT_FALSE(feature->stats().keptMayFallBack);
      settings.cullCells = true;
      settings.keptStreamBytes = 64 << 10;
      return frame;
    };
    const auto expectSame = [&](const Frame& want, const Frame& got, const char* what) {
      ASSERT_GT(std::count_if(want.depth.begin(), want.depth.end(), [](float d) { return d > 0.0f; }), 1000);
      if (mode.tiles == Tiles::On) {
        const TileComparison c = compareTilesWithBoxes(want, got);
        EXPECT_EQ(c.coverageDiffers, 0) << what;
        EXPECT_LE(c.colourDiffers, c.hitsBoxes / 500 + 2) << what;
        EXPECT_LT(c.depthRelativeMax, 1e-4) << what;
      } else {
        EXPECT_TRUE(want.depth == got.depth) << what << " changed the depth";
        EXPECT_TRUE(want.rgba == got.rgba) << what << " changed the colour";
      }
    };
    // Two frames (one per frame slot) close to the middle bunny with a narrow field of view: one
    // object in view, most of its cells outside the frustum, so the slots learn a small kept share
    // and make streams for one bunny.
    const glm::vec3 centre = glm::vec3(asset_->surfaceBounds.center());
    const render::CameraView close = render::CameraView::lookAt(orbitCamera(*asset_, 0, 0.3f).position, centre,
                                                                0.3f, camera.znear, 1.0f);
    for (int slot = 0; slot < 2; ++slot) (void)renderWith(close, DEBUG_VIEW_NONE);
    ASSERT_EQ(feature->stats().objects, 1u);
    const shader::BrickCullTotals closeTotals = feature->cullTotals();
    ASSERT_LT(closeTotals.keptSlots[0] * 4, feature->stats().cells) << "the close view keeps a large share";
    // Pulled back, every bunny in view keeps a larger share than the streams were sized for.
    const Frame first = renderWith(camera, DEBUG_VIEW_NONE);
    EXPECT_TRUE(feature->stats().keptMayFallBack);
    EXPECT_EQ(feature->stats().tiles, mode.tiles == Tiles::On);
    EXPECT_FALSE(feature->stats().cullingRefused);
    const shader::BrickCullTotals firstTotals = feature->cullTotals();
    EXPECT_GT(firstTotals.fallbackCells, 0u) << "the pulled-back frame's kept cells fit in the streams sized from "
                                             << closeTotals.keptSlots[0] << " kept cells close to one bunny";
    EXPECT_GT(firstTotals.keptSlots[0] + firstTotals.keptSlots[1], feature->stats().keptSlots);
    // The streams grow to what the frames want (each frame slot learns from its own last frame).
    Frame steady;
    int frames = 0;
    for (; frames < 4; ++frames) {
      steady = renderWith(camera, DEBUG_VIEW_NONE);
      if (feature->cullTotals().fallbackCells == 0) break;
    }
    EXPECT_LT(frames, 4) << "the streams never grew to what the frames kept";
    EXPECT_GE(feature->stats().keptSlots, feature->cullTotals().keptSlots[0]);
    Frame want = reference();
    expectSame(want, first, "the pulled-back frame's fallback rows");
    expectSame(want, steady, "culling with streams sized by the demand");
    for (int slot = 0; slot < 2; ++slot) (void)renderWith(camera, DEBUG_VIEW_NONE);  // both slots sized again

    // Three times the instances: the streams are sized by the share kept, so the first frame of
    // the larger scene fits (not with occlusion culling: its share falls as the instances hide
    // each other, and is not what this checks).
    addBunnies(6);
    if (!mode.occlusion) {
      (void)renderWith(camera, DEBUG_VIEW_NONE);
      EXPECT_EQ(feature->cullTotals().fallbackCells, 0u)
          << "streams of " << feature->stats().keptSlots << " slots, " << feature->cullTotals().keptSlots[0]
          << " wanted: sized by the last frame's count rather than its share";
    }
    // A second bunny at each of the nine places (twice the kept cells in the same view, the same
    // image), but the budget stops the streams from growing (room for the frame's other buffers,
    // not for streams larger than those held): the frame culls into the streams it has and draws
    // the rows past them unculled, rather than turning culling off. (Not with occlusion culling:
    // it keeps only the visible cells, and the instances hide each other, so its demand stays
    // within the streams the first frames made.)
    if (mode.occlusion) continue;
    for (int slot = 0; slot < 2; ++slot) (void)renderWith(camera, DEBUG_VIEW_NONE);
    for (int i = 0; i < 9; ++i) addBunnyAt(i);
    gpu::Allocator& allocator = context_->allocator();
    allocator.setBudget(allocator.stats().usedBytes + feature->stats().keptStreamBytesHeld / 8);
    renderer_->renderFrame(registry_, camera, render::FrameSettings{});
    allocator.setBudget(gpu::Allocator::kUnlimited);  // before the read-back's staging buffers
    Frame budgeted = first;
    budgeted.rgba = renderer_->readbackColor();
    budgeted.depth = renderer_->readbackDepth();
    EXPECT_FALSE(feature->stats().cullingRefused) << "culling was turned off, the streams held a few rows";
    EXPECT_TRUE(feature->stats().keptMayFallBack);
    EXPECT_GT(feature->cullTotals().fallbackCells, 0u)
        << "streams of " << feature->stats().keptSlots << " slots, " << feature->cullTotals().keptSlots[0] << " wanted";
    want = reference();
    expectSame(want, budgeted, "the budget's fallback rows");
  }
}

// Why: where not even a few thousand kept cells fit in GPU memory, the allocator's budget or one
// buffer, the frame must not fail: it draws every cell unculled, the image of culling off, says so
// in its stats, and culls again once the streams fit (before the kept streams were sized by the
// demand, every frame of 10,000 bunnies failed this way).
TEST_F(KeptStreamsTest, CullingThatDoesNotFitDrawsEveryCellInstead) {
  startBunnies();
  auto* feature = feature_;
  const render::CameraView camera = camera_;
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;
  feature->settings().cullCells = false;
  const Frame all = renderWith(camera, DEBUG_VIEW_NONE);
  ASSERT_GT(std::count_if(all.depth.begin(), all.depth.end(), [](float d) { return d > 0.0f; }), 1000);
  EXPECT_FALSE(feature->stats().cullingRefused) << "culling was off, not refused";
  feature->settings().cullCells = true;
  // Room for the asset's cell cones (uploaded by the first culled frame) and 64 KiB more: the
  // least streams need 4,096 slots of 144 bytes.
  const std::uint64_t cones = asset_->cells.records.size() * sizeof(shader::CellBrickCone);
  gpu::Allocator& allocator = context_->allocator();
  allocator.setBudget(allocator.stats().usedBytes + cones + 65536);
  renderer_->renderFrame(registry_, camera, render::FrameSettings{});
  allocator.setBudget(gpu::Allocator::kUnlimited);
  EXPECT_TRUE(feature->stats().cullingRefused);
  EXPECT_EQ(feature->cullTotals().tested, 0u) << "no culling pass ran";
  EXPECT_TRUE(all.depth == renderer_->readbackDepth()) << "the unculled frame is not culling off's";
  EXPECT_TRUE(all.rgba == renderer_->readbackColor()) << "the unculled frame is not culling off's";
  // With room again, the next frame culls.
  const Frame culled = renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_FALSE(feature->stats().cullingRefused);
  EXPECT_GT(feature->cullTotals().tested, 0u);
  EXPECT_TRUE(all.depth == culled.depth) << "culling changed the depth";
}

// Why: streams sized by the demand grow with the scene; were that all, one look at a large scene
// (the whole 10,000-bunny grid holds 9 GB of streams) would keep its memory for the rest of the run.
// Streams far larger than their frames want, or held while nothing is culled, must be released
// after Settings::releaseAfterFrames of the slot's frames in a row, and not before (a camera
// swinging back and forth must not reallocate them every frame); the frames after the release
// must draw the same image. A mutant that never releases keeps the nine bunnies' streams.
TEST_F(KeptStreamsTest, StreamsFarLargerThanTheFramesWantAreReleased) {
  startBunnies();
  auto* feature = feature_;
  hsdf::HermiteCellFeature::Settings& settings = feature->settings();
  settings.tiles = hsdf::HermiteCellFeature::Tiles::Off;
  settings.cullCells = true;
  settings.keptStreamBytes = 64 << 10;  // 450 fp32 slots: the streams are sized by the demand
  addBunnies(6);
  const auto render = [&] { return renderWith(camera_, DEBUG_VIEW_NONE); };
  // Until both frame slots' streams hold what their frames keep.
  for (int frame = 0; frame < 6; ++frame) (void)render();
  ASSERT_EQ(feature->cullTotals().fallbackCells, 0u);
  const std::uint64_t nine = feature->stats().keptStreamBytesHeld;
  ASSERT_GT(nine, 2 * settings.keptStreamBytes);
  // One bunny left (the middle one of the first row, in the camera's centre).
  for (std::size_t i = 0; i < bunnies_.size(); ++i) {
    if (i == 1) continue;
    ASSERT_TRUE(registry_.destroy(bunnies_[i]));
  }
  for (int frame = 0; frame < 10; ++frame) (void)render();
  EXPECT_EQ(feature->stats().keptStreamBytesHeld, nine) << "released before releaseAfterFrames (120) frames";
  settings.releaseAfterFrames = 3;
  Frame shrunk;
  for (int frame = 0; frame < 10 && feature->stats().keptStreamBytesHeld >= nine / 2; ++frame) shrunk = render();
  const std::uint64_t one = feature->stats().keptStreamBytesHeld;
  EXPECT_LT(one, nine / 2) << "the nine bunnies' streams were kept for one bunny";
  EXPECT_GT(one, 0u);
  shrunk = render();  // a frame drawn into the streams made at one bunny's size
  EXPECT_EQ(feature->cullTotals().fallbackCells, 0u);
  // Culling off: nothing is culled, so nothing is kept.
  settings.cullCells = false;
  Frame unculled;
  for (int frame = 0; frame < 10 && feature->stats().keptStreamBytesHeld > 0; ++frame) unculled = render();
  EXPECT_EQ(feature->stats().keptStreamBytesHeld, 0u) << "streams held while nothing is culled";
  ASSERT_GT(std::count_if(unculled.depth.begin(), unculled.depth.end(), [](float d) { return d > 0.0f; }), 1000);
  EXPECT_TRUE(unculled.depth == shrunk.depth) << "culling into the released and remade streams changed the depth";
  EXPECT_TRUE(unculled.rgba == shrunk.rgba) << "culling into the released and remade streams changed the colour";
}

// Why: each view region has frame slots of its own, prepared only while it is drawn: a slot's own
// frames release what it no longer wants, but a region that is no longer drawn (the split screen
// turned off) has no frames, and its kept streams and tile lists would be held for the rest of the
// run. They must go once no frame has prepared the slot for Settings::releaseAfterFrames frames,
// not before, and the region drawn again must show the same image.
TEST_F(KeptStreamsTest, BuffersOfAViewRegionNoLongerDrawnAreReleased) {
  startBunnies();
  auto* feature = feature_;
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::On;
  render::FrameSettings split;
  const std::uint32_t half = kSize / 2;
  split.regions = {{VkRect2D{{0, 0}, {half, kSize}}, {}}, {VkRect2D{{int(half), 0}, {kSize - half, kSize}}, {}}};
  // The first region alone, at the same place: its slots' lists keep their size, so what changes is
  // the second region's.
  render::FrameSettings firstOnly;
  firstOnly.regions = {split.regions[0]};
  const auto held = [&] { return feature->stats().keptStreamBytesHeld + feature->stats().tileListBytesHeld; };
  // Every slot of both regions prepared, twice: the tile lists that a slot's first frame made by
  // the upper bound are remade at what its second frame measured (TileListsFollowWhatTheFramesNeed).
  for (int frame = 0; frame < 3; ++frame) (void)renderWith(camera_, split);
  const Frame before = renderWith(camera_, split);
  const std::uint64_t bothRegions = held();
  ASSERT_GT(bothRegions, 0u);
  for (int frame = 0; frame < 10; ++frame) (void)renderWith(camera_, firstOnly);
  EXPECT_EQ(held(), bothRegions) << "released before releaseAfterFrames (120) frames";
  feature->settings().releaseAfterFrames = 3;
  (void)renderWith(camera_, firstOnly);
  const std::uint64_t oneRegion = held();
  EXPECT_LT(oneRegion, bothRegions) << "the second region's buffers were kept while it was not drawn";
  EXPECT_GT(oneRegion, 0u) << "the drawn region's buffers were released";
  (void)renderWith(camera_, split);
  const Frame after = renderWith(camera_, split);
  EXPECT_EQ(held(), bothRegions) << "the second region's buffers were not made again as they were";
  ASSERT_GT(std::count_if(after.depth.begin(), after.depth.end(), [](float d) { return d > 0.0f; }), 1000);
  EXPECT_TRUE(before.depth == after.depth) << "the region drawn again changed the depth";
  EXPECT_TRUE(before.rgba == after.rgba) << "the region drawn again changed the colour";
}

// Why: occlusion culling's history (a uint per cell of every culled object: 174 MB for the
// 10,000-bunny grid) would be held for the rest of the run once occlusion culling is turned off.
// After Settings::releaseAfterFrames frames without it, it must go, and not before; turning it
// on again must start a fresh history that draws the same image.
TEST_F(HermiteCellsTest, OcclusionHistoryIsReleasedWhenOcclusionCullingStops) {
  createCellRenderer(kSize, kSize);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  hsdf::HermiteCellFeature::Settings& settings = feature->settings();
  settings.tiles = hsdf::HermiteCellFeature::Tiles::Off;  // occlusion culls boxes; tiles turn it off
  settings.earlyDepth = hsdf::HermiteCellFeature::EarlyDepth::Off;
  const auto asset = bakeAsset("bunny", 32);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  const render::CameraView camera = orbitCamera(*asset, 2);
  settings.cullOcclusion = true;
  const Frame culled = renderWith(camera, DEBUG_VIEW_NONE);
  const std::uint64_t held = feature->stats().historyBytesHeld;
  ASSERT_GE(held, asset->cells.records.size() * sizeof(std::uint32_t));
  settings.cullOcclusion = false;
  for (int frame = 0; frame < 10; ++frame) (void)renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_EQ(feature->stats().historyBytesHeld, held) << "released before releaseAfterFrames (120) frames";
  settings.releaseAfterFrames = 3;
  for (int frame = 0; frame < 3; ++frame) (void)renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_EQ(feature->stats().historyBytesHeld, 0u) << "the history was kept while nothing culled by occlusion";
  settings.cullOcclusion = true;
  for (int frame = 0; frame < 3; ++frame) {
    const Frame again = renderWith(camera, DEBUG_VIEW_NONE);
    EXPECT_GT(feature->stats().historyBytesHeld, 0u);
    EXPECT_TRUE(culled.depth == again.depth) << "a fresh history changed the depth (frame " << frame << ")";
    EXPECT_TRUE(culled.rgba == again.rgba) << "a fresh history changed the colour (frame " << frame << ")";
  }
}

// Why: occlusion culling draws in two phases what one pass drew: a cell missing from both (a wrong
// history index, an occlusion test that is not conservative at the box's edges or depth, a pyramid
// texel that misses pixels) is a hole, a cell drawn twice or out of its row's order a different
// winner where hits tie. The history must never decide what is drawn, only when: so depth and
// colour identical with occlusion on and off on the concave bunny from several sides, on the first
// frame (empty history), after a frame that looked from the opposite side (stale history) and in
// steady state (the previous frames from the same camera); and the prepass rasterizes fewer
// fragments in steady state (the bunny's surface hides cells behind it).
TEST_F(HermiteCellsTest, OcclusionCullingKeepsTheImageAndDrawsFewerFragments) {
  createCellRenderer(kSize, kSize);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;  // occlusion culls boxes; tiles turn it off
  const auto asset = bakeAsset("bunny", 64);
  ASSERT_NE(asset, nullptr);
  const ecs::Entity entity = addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  const bool inOrder = tolerancesFor(*context_).fragmentsShadeInPrimitiveOrder;
  using ThinBoxes = hsdf::HermiteCellFeature::ThinBoxes;
  struct Case {
    const char* label;
    ThinBoxes thin;
    bool half;
    int firstView, viewStep;
  };
  const Case cases[] = {{"attribute boxes fp32", ThinBoxes::Off, false, 0, 1},
                        {"thin boxes fp16", ThinBoxes::On, true, 1, 3}};
  // Occlusion culling turns the early depth stage off (HermiteCellFeature::Settings::cullOcclusion):
  // the frames without it keep it off too, so that only the culling differs.
  feature->settings().earlyDepth = hsdf::HermiteCellFeature::EarlyDepth::Off;
  {
    feature->settings().cullOcclusion = false;
    const Frame without = renderWith(orbitCamera(*asset, 0), DEBUG_VIEW_NONE);
    feature->settings().cullOcclusion = true;
    const Frame first = renderWith(orbitCamera(*asset, 0), DEBUG_VIEW_NONE);  // empty history
    EXPECT_TRUE(without.depth == first.depth) << "occlusion culling changed the depth (empty history)";
    EXPECT_TRUE(without.rgba == first.rgba) << "occlusion culling changed the colour (empty history)";
  }
  for (const Case& c : cases) {
    feature->settings().thinBoxes = c.thin;
    registry_.get<hsdf::HermiteSdfRenderable>(entity).halfPrecision = c.half;
    std::uint64_t withoutSum = 0, withSum = 0;
    for (int view = c.firstView; view < 6; view += c.viewStep) {
      SCOPED_TRACE(std::string(c.label) + ", view " + std::to_string(view));
      const render::CameraView camera = orbitCamera(*asset, view);
      feature->settings().cullOcclusion = false;
      const Frame without = renderWith(camera, DEBUG_VIEW_NONE);
      const std::uint64_t withoutFragments = prepassFragments(*renderer_);
      ASSERT_GT(std::count_if(without.depth.begin(), without.depth.end(), [](float d) { return d > 0.0f; }), 500);
      feature->settings().cullOcclusion = true;
      renderWith(orbitCamera(*asset, view + 3), DEBUG_VIEW_NONE);  // the history of the other side
      const Frame stale = renderWith(camera, DEBUG_VIEW_NONE);
      EXPECT_TRUE(without.depth == stale.depth) << "occlusion culling with a stale history changed the depth";
      EXPECT_TRUE(without.rgba == stale.rgba) << "occlusion culling with a stale history changed the colour";
      // After a stale history phase 1 draws little, so its pyramid hides little and phase 2
      // marks nearly every cell visible: the next frame draws them all in phase 1 and finds
      // which are hidden; from the one after on, those are not drawn.
      const Frame settling = renderWith(camera, DEBUG_VIEW_NONE);
      EXPECT_TRUE(without.depth == settling.depth) << "occlusion culling changed the depth (settling)";
      EXPECT_TRUE(without.rgba == settling.rgba) << "occlusion culling changed the colour (settling)";
      const Frame steady = renderWith(camera, DEBUG_VIEW_NONE);
      EXPECT_TRUE(without.depth == steady.depth) << "occlusion culling changed the depth";
      EXPECT_TRUE(without.rgba == steady.rgba) << "occlusion culling changed the colour";
      EXPECT_TRUE(feature->usesOcclusionCulling());
      EXPECT_FALSE(feature->stats().earlyDepth) << "the early depth stage is off with occlusion culling";
      withoutSum += withoutFragments;
      withSum += prepassFragments(*renderer_);
      if (withoutFragments > 0 && inOrder) {
        EXPECT_LT(prepassFragments(*renderer_), withoutFragments);
      }
    }
    SCOPED_TRACE(c.label);
    if (withoutSum > 0) {
      EXPECT_LT(withSum, withoutSum) << "occlusion culling drew no fewer prepass fragments";
    }
  }
}

// Why: an object hidden behind another must cost nothing once the history holds the occluder: in
// steady state its cells are neither drawn in phase 1 (not visible last frame) nor in phase 2
// (behind the pyramid). A sphere in front of a small torus: with the torus the frame draws exactly
// the boxes and prepass fragments it draws without it, and the image is the one drawn without
// occlusion culling. The torus alone, from the same camera, draws boxes (it is in view).
TEST_F(HermiteCellsTest, OcclusionCullingDrawsNothingOfAHiddenObject) {
  auto* feature = createOcclusionCullingRenderer(kSize, kSize);
  const auto sphere = bakeAsset("sphere", 16);
  const auto torus = bakeAsset("torus", 16);
  ASSERT_NE(sphere, nullptr);
  ASSERT_NE(torus, nullptr);
  const render::CameraView camera = render::CameraView::lookAt({0.0f, 0.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, 0.9f, 0.05f, 1.0f);
  const glm::mat4 behind = glm::scale(glm::translate(glm::mat4(1.0f), {0.0f, 0.0f, -3.0f}), glm::vec3(0.2f));
  struct Drawn {
    std::uint64_t boxes = 0, tested = 0, fragments = 0;
    Frame frame;
  };
  // Four frames from the camera (the history settles), the last one measured.
  auto draw = [&](bool withSphere, bool withTorus) {
    registry_ = ecs::Registry();
    if (withSphere) addSdf(registry_, sphere, hsdf::RenderMethod::Cells);
    if (withTorus) addSdf(registry_, torus, hsdf::RenderMethod::Cells, behind);
    Drawn d;
    for (int frame = 0; frame < 4; ++frame) d.frame = renderWith(camera, DEBUG_VIEW_NONE);
    d.boxes = feature->cullTotals().kept;
    d.tested = feature->cullTotals().tested;
    d.fragments = prepassFragments(*renderer_);
    return d;
  };
  const Drawn torusAlone = draw(false, true);
  EXPECT_GT(torusAlone.boxes, 0u) << "the torus is in view";
  const Drawn sphereAlone = draw(true, false);
  const Drawn both = draw(true, true);
  EXPECT_EQ(both.tested, sphereAlone.tested + torusAlone.tested) << "the torus's cells are tested";
  EXPECT_EQ(both.boxes, sphereAlone.boxes) << "the hidden torus drew boxes";
  EXPECT_EQ(both.fragments, sphereAlone.fragments) << "the hidden torus drew prepass fragments";
  EXPECT_TRUE(both.frame.depth == sphereAlone.frame.depth);
  feature->settings().cullOcclusion = false;
  const Drawn unculled = draw(true, true);
  EXPECT_GT(unculled.boxes, both.boxes);
  EXPECT_TRUE(unculled.frame.depth == both.frame.depth) << "occlusion culling changed the depth";
  EXPECT_TRUE(unculled.frame.rgba == both.frame.rgba) << "occlusion culling changed the colour";
}

// Why: each view region keeps its own history, and the sides of a split screen may draw other
// assets for one entity (the Viewer's compared side at another K swaps the asset in for its
// region). The history placed each entity once for all regions, so the two sides took each
// other's places every frame: every frame each side started from a fresh history, phase 1 drew
// nothing and occlusion culled nothing (the image stayed right: only the work grew). So: the
// sphere in front of the small torus on both sides of a split, the right side drawing the sphere
// from another asset; in steady state the right side draws exactly the boxes it draws without the
// torus (cullTotals: the last region's pass).
TEST_F(HermiteCellsTest, OcclusionHistoryOfEachSideOfASplitScreenSurvivesTheOtherSidesAssets) {
  auto* feature = createOcclusionCullingRenderer(kSize, kSize);
  const auto sphere = bakeAsset("sphere", 16);
  const auto otherSphere = bakeAsset("sphere", 20);
  const auto torus = bakeAsset("torus", 16);
  ASSERT_TRUE(sphere && otherSphere && torus);
  const render::CameraView camera = render::CameraView::lookAt({0.0f, 0.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, 0.9f, 0.05f, 1.0f);
  const glm::mat4 behind = glm::scale(glm::translate(glm::mat4(1.0f), {0.0f, 0.0f, -3.0f}), glm::vec3(0.2f));
  // Four frames of the split (the history settles); the right side's boxes of the last one.
  auto rightBoxes = [&](bool withTorus) {
    registry_ = ecs::Registry();
    const ecs::Entity front = addSdf(registry_, sphere, hsdf::RenderMethod::Cells);
    if (withTorus) addSdf(registry_, torus, hsdf::RenderMethod::Cells, behind);
    const auto drawing = [&, front](std::shared_ptr<const hsdf::SdfAsset> asset) {
      return [&, front, asset] { registry_.get<hsdf::HermiteSdfRenderable>(front).asset = asset; };
    };
    render::FrameSettings settings;
    settings.regions = {{VkRect2D{{0, 0}, {kSize / 2, kSize}}, drawing(sphere)},
                        {VkRect2D{{std::int32_t(kSize / 2), 0}, {kSize / 2, kSize}}, drawing(otherSphere)}};
    for (int frame = 0; frame < 4; ++frame) (void)renderWith(camera, settings);
    EXPECT_TRUE(feature->usesOcclusionCulling());
    return feature->cullTotals().kept;
  };
  const std::uint64_t sphereAlone = rightBoxes(false);
  const std::uint64_t both = rightBoxes(true);
  std::printf("[ split occlusion ] right side's boxes in steady state: %llu with the torus behind, %llu without\n",
              static_cast<unsigned long long>(both), static_cast<unsigned long long>(sphereAlone));
  EXPECT_GT(sphereAlone, 0u);
  EXPECT_EQ(both, sphereAlone) << "the hidden torus drew boxes: the side's history restarted";
}

}  // namespace
}  // namespace gputest
