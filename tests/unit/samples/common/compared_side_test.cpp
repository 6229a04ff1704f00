// The compared side of the split screen and difference view (samples/common/compared_side.h) on the
// CPU: which field it draws (the main one shared, its own bake, never a failed K again) and the two
// view regions of a split frame. No GPU (viewer_compare_test.cpp draws real split frames).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "compared_side.h"

namespace samples {
namespace {

using Asset = std::shared_ptr<const hsdf::SdfAsset>;

const hsdf::BakeSource kSphere = hsdf::BakeSource::fromShape("sphere");

Asset bake(int resolution, int padding, hsdf::BakeBand band = hsdf::BakeBand::Dense) {
  hsdf::BakeSettings settings;
  settings.resolution = resolution;
  settings.padding = padding;
  settings.band = band;
  hsdf::BakeJob job(kSphere, settings);
  hsdf::BakeJob::Result result = job.wait();
  EXPECT_TRUE(result.ok()) << result.error().message;
  return result ? *result : nullptr;
}

// A split comparing trilinear at `compareK` with the main tuning at K 16, padding 1.
TuningState splitTuning(int compareK) {
  TuningState tuning;
  tuning.method = hsdf::RenderMethod::HermiteSphereTrace;
  tuning.resolution = 16;
  tuning.padding = 1;
  tuning.split = SplitMode::Vertical;
  tuning.compareMethod = hsdf::RenderMethod::TrilinearSphereTrace;
  tuning.compareResolution = compareK;
  return tuning;
}

constexpr int kNotDrawn = -1;  // resolutionDrawn's answer when the side draws the main asset

TEST(ComparedSide, SharesTheMainFieldAtTheSameResolution) {
  const TuningState tuning = splitTuning(16);
  ComparedSide side{nullptr};
  side.updateBake(tuning, &kSphere, {bake(16, 1), 16, 1}, {});
  EXPECT_EQ(side.bakeJob(), nullptr);  // not baked twice
  EXPECT_EQ(side.resolutionDrawn(tuning, kNotDrawn), 16);
}

TEST(ComparedSide, BakesItsOwnFieldForAnotherResolutionOrASparseMain) {
  ComparedSide side{nullptr};
  const TuningState tuning = splitTuning(24);
  side.updateBake(tuning, &kSphere, {bake(16, 1), 16, 1}, {});
  ASSERT_NE(side.bakeJob(), nullptr);
  EXPECT_EQ(side.bakeJob()->settings().resolution, 24);
  EXPECT_EQ(side.resolutionDrawn(tuning, kNotDrawn), kNotDrawn);  // the main asset stands in meanwhile
  side.finishBake();
  EXPECT_EQ(side.bakeJob(), nullptr);
  EXPECT_EQ(side.resolutionDrawn(tuning, kNotDrawn), 24);
  EXPECT_TRUE(side.bakeError().empty());

  // A sparse main field has no dense samples for the compared tracer: baked, not shared.
  ComparedSide sparse{nullptr};
  const TuningState same = splitTuning(16);
  sparse.updateBake(same, &kSphere, {bake(16, 1, hsdf::BakeBand::Sparse), 16, 1}, {});
  ASSERT_NE(sparse.bakeJob(), nullptr);
  EXPECT_EQ(sparse.bakeJob()->settings().resolution, 16);
}

TEST(ComparedSide, AFailedResolutionIsNotBakedAgain) {
  ComparedSide side{nullptr};
  hsdf::BakeBudget budget;
  budget.maxResolution = 20;
  const TuningState refused = splitTuning(24);
  side.updateBake(refused, &kSphere, {bake(16, 1), 16, 1}, budget);
  ASSERT_NE(side.bakeJob(), nullptr);
  side.finishBake();
  EXPECT_NE(side.bakeError().find("baking the compared side at resolution 24"), std::string::npos) << side.bakeError();
  side.updateBake(refused, &kSphere, {bake(16, 1), 16, 1}, budget);
  EXPECT_EQ(side.bakeJob(), nullptr);
  EXPECT_EQ(side.resolutionDrawn(refused, kNotDrawn), kNotDrawn);
  // Another K is tried.
  side.updateBake(splitTuning(18), &kSphere, {bake(16, 1), 16, 1}, budget);
  ASSERT_NE(side.bakeJob(), nullptr);
  EXPECT_EQ(side.bakeJob()->settings().resolution, 18);
}

TEST(ComparedSide, NoBakeWithoutComparisonSourceOrForCells) {
  ComparedSide side{nullptr};
  TuningState off = splitTuning(24);
  off.split = SplitMode::Off;
  side.updateBake(off, &kSphere, {}, {});
  EXPECT_EQ(side.bakeJob(), nullptr);
  side.updateBake(splitTuning(24), nullptr, {}, {});  // a .hsdf file: nothing to bake from
  EXPECT_EQ(side.bakeJob(), nullptr);
  TuningState cells = splitTuning(24);
  cells.compareMethod = hsdf::RenderMethod::Cells;  // draws the main asset
  side.updateBake(cells, &kSphere, {}, {});
  EXPECT_EQ(side.bakeJob(), nullptr);
  EXPECT_EQ(side.resolutionDrawn(cells, kNotDrawn), kNotDrawn);
}

// Each region shows its side: the main tuning and asset left of the divider, the compared tuning
// and its own bake right of it; the divider at the rounded fraction of the width (or height).
TEST(ComparedSide, SplitRegionsShowEachSideOnItsSideOfTheDivider) {
  struct Shown {
    Method method;
    int resolution;
    Asset asset;
  };
  std::vector<Shown> shown;
  ComparedSide side{[&shown](const TuningState& tuning, const Asset& asset) {
    shown.push_back({tuning.method, tuning.resolution, asset});
  }};
  TuningState tuning = splitTuning(24);
  tuning.splitPosition = 0.3f;
  const Asset main = bake(16, 1);
  side.updateBake(tuning, &kSphere, {main, 16, 1}, {});
  side.finishBake();
  const VkExtent2D extent{101, 50};

  const std::vector<engine::render::ViewRegion> vertical = side.splitRegions(tuning, extent, main, main);
  ASSERT_EQ(vertical.size(), 2u);
  const std::uint32_t divider = 30;  // 0.3 * 101 = 30.3
  EXPECT_EQ(vertical[0].rect.offset.x, 0);
  EXPECT_EQ(vertical[0].rect.extent.width, divider);
  EXPECT_EQ(vertical[0].rect.extent.height, 50u);
  EXPECT_EQ(vertical[1].rect.offset.x, std::int32_t(divider));
  EXPECT_EQ(vertical[1].rect.extent.width, 101u - divider);
  EXPECT_EQ(vertical[1].rect.extent.height, 50u);
  for (const auto& region : vertical) region.apply();
  ASSERT_EQ(shown.size(), 2u);
  EXPECT_EQ(shown[0].method, hsdf::RenderMethod::HermiteSphereTrace);
  EXPECT_EQ(shown[0].resolution, 16);
  EXPECT_EQ(shown[0].asset, main);
  EXPECT_EQ(shown[1].method, hsdf::RenderMethod::TrilinearSphereTrace);
  EXPECT_EQ(shown[1].resolution, 24);
  ASSERT_NE(shown[1].asset, nullptr);
  EXPECT_NE(shown[1].asset, main);  // its own bake
  EXPECT_EQ(int(shown[1].asset->cells.grid.resolution), 24);

  tuning.split = SplitMode::Horizontal;
  const std::vector<engine::render::ViewRegion> horizontal = side.splitRegions(tuning, extent, main, main);
  ASSERT_EQ(horizontal.size(), 2u);
  EXPECT_EQ(horizontal[0].rect.extent.width, 101u);
  EXPECT_EQ(horizontal[0].rect.extent.height, 15u);  // 0.3 * 50
  EXPECT_EQ(horizontal[1].rect.offset.y, 15);
  EXPECT_EQ(horizontal[1].rect.extent.height, 35u);
}

}  // namespace
}  // namespace samples
