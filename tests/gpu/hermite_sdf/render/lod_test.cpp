// Levels of detail (hermite_sdf/render/lod.h) on the device: a far object draws a coarser level, the
// frame shows the same objects as without levels (coverage within a level's difference), and the
// cells' prepass does less work. Lavapipe, validation layers on.
#include <algorithm>

#include <gtest/gtest.h>

#include "engine/gpu/pipeline_statistics.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/render/lod.h"
#include "hermite_test_support.h"

namespace gputest {
namespace {

using namespace engine;

constexpr std::uint32_t kSize = 256;
constexpr float kFov = 0.8f;

class LodGpuTest : public GpuTest {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    render::RendererDesc desc;
    renderer_ = std::make_unique<render::Renderer>(*context_, desc, VkExtent2D{kSize, kSize});
    ASSERT_TRUE(renderer_->addFeature(std::make_unique<render::MeshFeature>(*pool_)).ok());
    // The cells alone beside the meshes: levels of detail are drawn by the cell renderers only.
    ASSERT_TRUE(renderer_->addFeature(std::make_unique<hsdf::HermiteCellFeature>()).ok());
  }

  // A sphere with levels K = 64, 32, 16 at `position`, drawing level 0 until selected.
  ecs::Entity addSphere(const std::vector<std::shared_ptr<const hsdf::SdfAsset>>& levels, const glm::vec3& position) {
    const ecs::Entity e = addSdf(registry_, levels.front(), hsdf::RenderMethod::Cells);
    registry_.get<scene::Transform>(e).translation = position;
    hsdf::HermiteSdfLod lod;
    lod.levels = levels;
    registry_.emplace<hsdf::HermiteSdfLod>(e, std::move(lod));
    return e;
  }

  // Covered pixels in columns [x0, x1).
  static int coverage(const Frame& frame, std::uint32_t x0, std::uint32_t x1) {
    int n = 0;
    for (std::uint32_t y = 0; y < frame.height; ++y)
      for (std::uint32_t x = x0; x < x1; ++x) n += frame.depthAt(x, y) > 0.0f;
    return n;
  }

  std::uint64_t prepassVertices() const {
    const auto* s = gpu::findStatistics(renderer_->lastPipelineStatistics(), "depth prepass");
    return s ? s->vertexShaderInvocations : 0;
  }
};

// Tricky: the near sphere (cells ~3 px) must keep K = 64 and the far one (cells under a pixel even
// at K = 16) must draw the coarsest level, in the same frame; the images with and without levels
// must agree where the same asset is drawn (near: identical depth) and nearly where it is not
// (far: coverage within a rim of pixels), and the cells drawn must drop by exactly the far
// object's K = 64 minus K = 16 cells.
TEST_F(LodGpuTest, FarObjectDrawsACoarserLevel) {
  hsdf::BakeSettings settings;
  settings.resolution = 64;
  const auto levels = hsdf::bakeLodLevels(hsdf::BakeSource::fromShape("sphere"), settings, 16);
  ASSERT_TRUE(levels.ok()) << levels.error().message;
  ASSERT_EQ(levels->size(), 3u);
  const ecs::Entity near = addSphere(*levels, {-1.0f, 0.0f, -5.0f});
  const ecs::Entity far = addSphere(*levels, {15.0f, 0.0f, -60.0f});
  const auto camera = render::CameraView::lookAt({0, 0, 0}, {0, 0, -1}, kFov, 0.05f, 1.0f);

  scene::updateWorldTransforms(registry_);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  // Boxes: their vertices count the cells drawn (tiles draw one point per screen tile).
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;
  const Frame full = renderWith(camera, 0);  // both at K = 64: the levels not selected yet
  const std::uint64_t fullCells = feature->stats().cells;
  const std::uint64_t fullVertices = prepassVertices();

  hsdf::selectSdfLevels(registry_, camera, kSize);
  EXPECT_EQ(registry_.get<hsdf::HermiteSdfRenderable>(near).asset, levels->front());
  EXPECT_EQ(registry_.get<hsdf::HermiteSdfRenderable>(far).asset, levels->back());
  const Frame lod = renderWith(camera, 0);
  const std::uint64_t lodCells = feature->stats().cells;
  EXPECT_EQ(fullCells - lodCells, levels->front()->cells.records.size() - levels->back()->cells.records.size());
  if (context_->capabilities().pipelineStatistics) {
    EXPECT_LT(prepassVertices(), fullVertices);
  }

  // Near sphere: left of x = 170 (its disc spans about 5..130), the same asset, the same depth.
  for (std::uint32_t y = 0; y < kSize; ++y) {
    for (std::uint32_t x = 0; x < 170; ++x) {
      ASSERT_EQ(lod.depthAt(x, y), full.depthAt(x, y)) << x << "," << y;
    }
  }
  // Far sphere: a disc of about 5 px radius around x = 204; K = 16 moves its rim by under a pixel.
  const int farFull = coverage(full, 170, kSize), farLod = coverage(lod, 170, kSize);
  EXPECT_GT(farFull, 40);
  EXPECT_NEAR(farLod, farFull, 0.2 * farFull) << "far sphere: " << farFull << " px at K = 64, " << farLod << " at K = 16";
}

// Tricky: the hysteresis is per entity and survives frames: moving the far sphere to where its
// K = 32 cells sit just inside the band must not switch it, moving it well past must.
TEST_F(LodGpuTest, LevelStaysWithinTheHysteresisBand) {
  hsdf::BakeSettings settings;
  settings.resolution = 64;
  const auto levels = hsdf::bakeLodLevels(hsdf::BakeSource::fromShape("sphere"), settings, 16);
  ASSERT_TRUE(levels.ok()) << levels.error().message;
  const ecs::Entity e = addSphere(*levels, {0.0f, 0.0f, -5.0f});
  const auto camera = render::CameraView::lookAt({0, 0, 0}, {0, 0, -1}, kFov, 0.05f, 1.0f);
  auto drawnAt = [&](float z) {
    registry_.get<scene::Transform>(e).translation = {0.0f, 0.0f, z};
    scene::updateWorldTransforms(registry_);
    hsdf::selectSdfLevels(registry_, camera, kSize);
    renderWith(camera, 0);
    EXPECT_EQ(renderer_->feature<hsdf::HermiteCellFeature>()->stats().cells,
              registry_.get<hsdf::HermiteSdfRenderable>(e).asset->cells.records.size());
    return registry_.get<hsdf::HermiteSdfRenderable>(e).asset->cells.grid.resolution;
  };
  EXPECT_EQ(drawnAt(-5.0f), 64);
  // Walk away until the level changes, then step back by less than the band: it must hold
  // (without the hysteresis, K = 32 is drawn from 2 px, 1.7 units nearer: 0.5 back would switch).
  // The walk starts where K = 64 is still drawn (K = 32's cells 2.27 px) to keep the frames few.
  float z = -11.0f;
  while (drawnAt(z) == 64 && z > -200.0f) z -= 0.25f;
  ASSERT_LT(z, -11.0f);
  const int coarser = drawnAt(z);
  EXPECT_EQ(coarser, 32);
  EXPECT_EQ(drawnAt(z + 0.5f), 32) << "switched back within the hysteresis band";
  EXPECT_EQ(drawnAt(-5.0f), 64);
}

}  // namespace
}  // namespace gputest
