// Levels of detail (hermite_sdf/render/lod.h): the level chosen from the projected size, its hysteresis,
// objects near and far in one registry, the camera turned away, and levels equal to direct bakes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/scene/transform.h"
#include "hermite_sdf/render/lod.h"

namespace hsdf {
namespace {

constexpr float kFov = 0.8f;
constexpr std::uint32_t kHeight = 720;

// The projection written out independently: a length L at distance d spans L / (2 d tan(fov/2)) of
// the image height.
TEST(Lod, ProjectedPixelsFollowsThePinholeModel) {
  EXPECT_NEAR(projectedPixels(1.0f, 10.0f, kFov, kHeight), 720.0f / (20.0f * std::tan(0.4f)), 1e-3f);
  EXPECT_NEAR(projectedPixels(2.0f, 10.0f, kFov, kHeight), 2.0f * projectedPixels(1.0f, 10.0f, kFov, kHeight), 1e-3f);
  EXPECT_TRUE(std::isinf(projectedPixels(1.0f, 0.0f, kFov, kHeight))) << "the eye inside the object: finest level";
  EXPECT_TRUE(std::isinf(projectedPixels(1.0f, -3.0f, kFov, kHeight)));
}

// Tricky: an orthographic camera shows a length at the same size at every distance, L / (2 ymag)
// of the image height, even with the camera's point inside the object (distance <= 0), where the
// perspective rule's "finest level" would make an orthographic view of a large object draw its
// finest level however small it is on screen. A perspective camera still follows the pinhole.
TEST(Lod, ProjectedPixelsOfAnOrthographicCameraIgnoreDistance) {
  engine::render::Camera ortho;
  ortho.projection = engine::render::Projection::kOrthographic;
  ortho.ymag = 4.0f;
  ortho.znear = 0.0f;
  ortho.zfar = 100.0f;
  const auto camera = engine::render::CameraView::fromWorld(glm::mat4(1.0f), ortho, 1.5f);
  ASSERT_TRUE(camera.ok()) << camera.error().message;
  for (const float distance : {-3.0f, 0.0f, 10.0f, 90.0f})
    EXPECT_NEAR(projectedPixels(2.0f, distance, *camera, kHeight), 2.0f * 720.0f / 8.0f, 1e-3f) << distance;
  const auto perspective = engine::render::CameraView::fromWorld(glm::mat4(1.0f), kFov, 0.1f, 1.5f);
  ASSERT_TRUE(perspective.ok());
  EXPECT_NEAR(projectedPixels(1.0f, 10.0f, *perspective, kHeight), projectedPixels(1.0f, 10.0f, kFov, kHeight), 1e-3f);
}

// Cell sizes in pixels of levels K, K/2, K/4, K/8: each level doubles the cell.
std::vector<float> levelsAt(float finestPixels) { return {finestPixels, 2 * finestPixels, 4 * finestPixels, 8 * finestPixels}; }

TEST(Lod, ChoosesTheCoarsestLevelWithinTarget) {
  EXPECT_EQ(chooseLodLevel(levelsAt(4.0f), 2.0f, 0), 0u) << "finest already over target: finest";
  EXPECT_EQ(chooseLodLevel(levelsAt(1.0f), 2.0f, 0), 0u) << "K/2's 2 px is not under 2 / 1.15";
  EXPECT_EQ(chooseLodLevel(levelsAt(0.5f), 2.0f, 0), 1u);
  EXPECT_EQ(chooseLodLevel(levelsAt(0.2f), 2.0f, 0), 3u);
  EXPECT_EQ(chooseLodLevel(levelsAt(0.01f), 2.0f, 0), 3u) << "no level coarser than the last";
  EXPECT_EQ(chooseLodLevel({}, 2.0f, 0), 0u);
}

// Tricky: at the threshold (the K/2 level's cells exactly at target) a choice without hysteresis
// flips with every rounding of the camera; the drawn level must stay on both sides of it within 15%.
TEST(Lod, HysteresisKeepsTheLevelAroundTheThreshold) {
  for (float finest : {0.9f, 1.0f, 1.1f}) {  // K/2 at 1.8, 2.0, 2.2 px against a target of 2
    EXPECT_EQ(chooseLodLevel(levelsAt(finest), 2.0f, 0), 0u) << finest;
    EXPECT_EQ(chooseLodLevel(levelsAt(finest), 2.0f, 1), 1u) << finest;
  }
  // Past the band it switches: coarser under 2 / 1.15, finer over 2 * 1.15.
  EXPECT_EQ(chooseLodLevel(levelsAt(0.85f), 2.0f, 0), 1u);
  EXPECT_EQ(chooseLodLevel(levelsAt(1.2f), 2.0f, 1), 0u);
  // A camera jump moves several levels at once.
  EXPECT_EQ(chooseLodLevel(levelsAt(0.1f), 2.0f, 0), 3u);
  EXPECT_EQ(chooseLodLevel(levelsAt(5.0f), 2.0f, 3), 0u);
}

// An asset whose cells have grid spacing h, grid box [-1, 1]^3-ish: only the grid matters here.
std::shared_ptr<const SdfAsset> fakeLevel(int resolution, double spacing) {
  auto asset = std::make_shared<SdfAsset>();
  asset->cells.grid.resolution = resolution;
  asset->cells.grid.spacing = spacing;
  asset->cells.grid.origin = glm::dvec3(-0.5 * spacing * (resolution - 1));
  return asset;
}

HermiteSdfLod fakeLod() {
  HermiteSdfLod lod;
  for (int k = 256; k >= 16; k /= 2) lod.levels.push_back(fakeLevel(k, 2.0 / (k - 1)));
  return lod;
}

engine::ecs::Entity addObject(engine::ecs::Registry& registry, const glm::vec3& position, float scale = 1.0f) {
  const engine::ecs::Entity e = registry.create();
  HermiteSdfLod lod = fakeLod();
  HermiteSdfRenderable renderable;
  renderable.asset = lod.levels.front();
  registry.emplace<HermiteSdfLod>(e, std::move(lod));
  registry.emplace<HermiteSdfRenderable>(e, std::move(renderable));
  glm::mat4 world = glm::translate(glm::mat4(1.0f), position) * glm::scale(glm::mat4(1.0f), glm::vec3(scale));
  registry.emplace<engine::scene::WorldTransform>(e, engine::scene::WorldTransform{world});
  return e;
}

int drawnResolution(engine::ecs::Registry& registry, engine::ecs::Entity e) {
  return registry.get<HermiteSdfRenderable>(e).asset->cells.grid.resolution;
}

// Objects near and far in one frame: the near one keeps K, the far ones draw coarser levels, each
// the one the projection predicts (written out here from the geometry, not from the code).
TEST(Lod, SystemPicksPerObjectLevelsNearAndFar) {
  engine::ecs::Registry registry;
  const auto near = addObject(registry, {0, 0, -3});
  const auto middle = addObject(registry, {0, 0, -40});
  const auto far = addObject(registry, {0, 0, -400});
  const auto camera = engine::render::CameraView::lookAt({0, 0, 0}, {0, 0, -1}, kFov, 0.05f, 16.0f / 9.0f);
  selectSdfLevels(registry, camera, kHeight);
  EXPECT_EQ(drawnResolution(registry, near), 256);
  // Middle: bounding radius sqrt(3), distance 40 - 1.73; a K cell (2/255) is 0.18 px: K/8 = 32
  // (1.5 px) is the coarsest under 2 / 1.15 px; K/16 = 16 would be 3.1 px.
  // (851.5 px per unit at distance 1: K = 32's cell 2/31 spans 1.44 px at 38.3, K = 16's 2.97 px.)
  EXPECT_EQ(drawnResolution(registry, middle), 32);
  EXPECT_EQ(drawnResolution(registry, far), 16);
  // Scaling the middle object up 8x makes its cells 8x larger on screen: a finer level.
  registry.get<engine::scene::WorldTransform>(middle).matrix =
      glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, -40)) * glm::scale(glm::mat4(1.0f), glm::vec3(8.0f));
  selectSdfLevels(registry, camera, kHeight);
  EXPECT_GT(drawnResolution(registry, middle), 32);
}

// Tricky: turning the camera away (the object behind it) must not change the level: only the
// distance counts, so turning back shows no switch. The eye inside the bounds draws the finest.
TEST(Lod, CameraBehindAndInsideKeepDistanceBasedLevels) {
  engine::ecs::Registry registry;
  const auto object = addObject(registry, {0, 0, -40});
  const auto front = engine::render::CameraView::lookAt({0, 0, 0}, {0, 0, -1}, kFov, 0.05f, 1.0f);
  const auto back = engine::render::CameraView::lookAt({0, 0, 0}, {0, 0, 1}, kFov, 0.05f, 1.0f);
  selectSdfLevels(registry, front, kHeight);
  const int seen = drawnResolution(registry, object);
  selectSdfLevels(registry, back, kHeight);
  EXPECT_EQ(drawnResolution(registry, object), seen);
  EXPECT_LT(seen, 256);
  const auto inside = engine::render::CameraView::lookAt({0, 0, -40}, {0, 0, -41}, kFov, 0.05f, 1.0f);
  selectSdfLevels(registry, inside, kHeight);
  EXPECT_EQ(drawnResolution(registry, object), 256);
}

// An entity without levels (or with an empty list) keeps the asset it has.
TEST(Lod, EmptyLevelsLeaveTheRenderableAlone) {
  engine::ecs::Registry registry;
  const auto object = addObject(registry, {0, 0, -400});
  registry.get<HermiteSdfLod>(object).levels.clear();
  selectSdfLevels(registry, engine::render::CameraView::lookAt({0, 0, 0}, {0, 0, -1}, kFov, 0.05f, 1.0f), kHeight);
  EXPECT_EQ(drawnResolution(registry, object), 256);
}

bool sameCells(const CellStream& a, const CellStream& b) {
  return a.grid.resolution == b.grid.resolution && a.grid.spacing == b.grid.spacing && a.grid.origin == b.grid.origin &&
         a.records.size() == b.records.size() &&
         std::memcmp(a.records.data(), b.records.data(), a.records.size() * sizeof(CellRecord)) == 0;
}

// Each level equals a bake made directly at its K, through another path: the levels are dense
// bakes, the references sparse ones (sparse_bake.h: the same cells, bit for bit, for analytic
// shapes). Catches a level baked at the wrong K, padding or from another source.
TEST(Lod, LevelsEqualDirectBakesAtTheirResolution) {
  BakeSettings settings;
  settings.resolution = 64;
  settings.padding = 2;
  const BakeSource torus = BakeSource::fromShape("torus");
  const auto levels = bakeLodLevels(torus, settings, 16);
  ASSERT_TRUE(levels.ok()) << levels.error().message;
  ASSERT_EQ(levels->size(), 3u);
  int k = 64;
  for (const auto& level : *levels) {
    BakeSettings direct = settings;
    direct.resolution = k;
    direct.band = BakeBand::Sparse;
    const auto reference = bakeAsset(torus, direct);
    ASSERT_TRUE(reference.ok()) << reference.error().message;
    EXPECT_EQ(level->cells.grid.resolution, k);
    EXPECT_TRUE(sameCells(level->cells, (*reference)->cells)) << "level K = " << k;
    EXPECT_FALSE(level->field.samples.empty()) << "a dense level keeps its field for the sphere tracers";
    k /= 2;
  }
}

// The finest asset, when given, is reused (not baked again) and the floor is honoured.
TEST(Lod, FinestAssetIsReusedAndFloorRespected) {
  BakeSettings settings;
  settings.resolution = 48;
  const BakeSource sphere = BakeSource::fromShape("sphere");
  const auto finest = bakeAsset(sphere, settings);
  ASSERT_TRUE(finest.ok());
  const auto levels = bakeLodLevels(sphere, settings, 12, *finest);
  ASSERT_TRUE(levels.ok()) << levels.error().message;
  ASSERT_EQ(levels->size(), 3u);  // 48, 24, 12
  EXPECT_EQ((*levels)[0].get(), finest->get());
  EXPECT_EQ((*levels)[2]->cells.grid.resolution, 12);
  const auto refused = bakeLodLevels(sphere, settings, 1);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("at least 2"), std::string::npos) << refused.error().message;
}

}  // namespace
}  // namespace hsdf
