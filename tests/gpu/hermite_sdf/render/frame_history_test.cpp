// Every frame of a moving scene against the same frame drawn by a fresh renderer. The cell feature
// keeps state from frame to frame (occlusion culling's visibility history, kept-cell streams and
// tile lists sized by earlier frames, pipelines per variant, uploaded assets); none of it may change
// what a frame shows. The settled-frame checks (ViewerWalk, the culling tests) compare a frame
// after the history caught up; here each frame is compared as it is drawn: the frame in which the
// camera jumps or turns fast, an object comes out from behind another (occlusion culling's phase 2
// must draw it in that very frame), objects cross each other or a mesh wall (the shared depth
// prepass), objects appear, disappear or change method, and the eye enters an object.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "engine/core/image_io.h"
#include "engine/render/components.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/render/sphere_trace_feature.h"
#include "hermite_test_support.h"
#include "shared/host_device.h"

namespace gputest {
namespace {

using namespace engine;
using CellSettings = hsdf::HermiteCellFeature::Settings;

constexpr std::uint32_t kWidth = 160, kHeight = 120;
constexpr float kAspect = float(kWidth) / float(kHeight);

glm::mat4 placed(const glm::vec3& at, float scale, float turn = 0.0f) {
  return glm::scale(glm::rotate(glm::translate(glm::mat4(1.0f), at), turn, glm::vec3(0.0f, 1.0f, 0.0f)),
                    glm::vec3(scale));
}

// One frame of a walk: its camera and what happened in it (for the log).
struct Shot {
  render::CameraView camera;
  std::string what;
};

class FrameHistoryTest : public GpuTest {
 protected:
  // The long-lived renderer (renderer_) with `settings`. The fresh renderers use them too, but
  // without occlusion culling (no history at all, the same image: the early depth stage is off in
  // frames that cull by occlusion, so off there too).
  void start(const CellSettings& settings) {
    freshSettings_ = settings;
    if (settings.cullOcclusion) {
      freshSettings_.cullOcclusion = false;
      freshSettings_.earlyDepth = hsdf::HermiteCellFeature::EarlyDepth::Off;
    }
    createRenderer(kWidth, kHeight);
    ASSERT_TRUE(renderer_->addFeature(std::make_unique<hsdf::HermiteCellFeature>()).ok());
    renderer_->feature<hsdf::HermiteCellFeature>()->settings() = settings;
    if (tracers_) {
      ASSERT_TRUE(renderer_->addFeature(std::make_unique<hsdf::SphereTraceFeature>()).ok());
    }
  }

  // The frame a renderer with no history draws of the registry as it stands.
  Frame freshFrame(const render::CameraView& camera, int i) {
    render::Renderer fresh(*context_, render::RendererDesc{}, VkExtent2D{kWidth, kHeight});
    EXPECT_TRUE(fresh.addFeature(std::make_unique<render::MeshFeature>(*pool_)).ok());
    EXPECT_TRUE(fresh.addFeature(std::make_unique<hsdf::HermiteCellFeature>()).ok());
    fresh.feature<hsdf::HermiteCellFeature>()->settings() = freshSettings_;
    if (tracers_) {
      EXPECT_TRUE(fresh.addFeature(std::make_unique<hsdf::SphereTraceFeature>()).ok());
    }
    fresh.renderFrame(registry_, camera, frameSettings(i));
    Frame frame;
    frame.width = kWidth;
    frame.height = kHeight;
    frame.rgba = fresh.readbackColor();
    frame.depth = fresh.readbackDepth();
    return frame;
  }

  // Moves an entity (its local transform: world transforms are resolved before each frame).
  void place(ecs::Entity entity, const glm::mat4& matrix) {
    registry_.get<scene::Transform>(entity) = scene::fromMatrix(matrix);
  }

  ecs::Entity addObject(std::shared_ptr<const hsdf::SdfAsset> asset, hsdf::RenderMethod method,
                        const glm::mat4& matrix) {
    const ecs::Entity entity = addSdf(registry_, std::move(asset), method, matrix);
    place(entity, matrix);
    return entity;
  }

  // The walks' assets: a sphere, a torus, a box and the bunny (null where a bake failed: the test
  // has failed).
  static std::array<std::shared_ptr<const hsdf::SdfAsset>, 4> walkAssets() {
    return {bakeAsset("sphere", 16), bakeAsset("torus", 16), bakeAsset("box", 12), bakeAsset("bunny", 16)};
  }

  // Two-phase occlusion culling of boxes (tiles turn it off).
  static CellSettings occlusionCulling() {
    CellSettings settings;
    settings.cullOcclusion = true;
    settings.tiles = hsdf::HermiteCellFeature::Tiles::Off;
    return settings;
  }

  int runScene(const char* label, int frames, hsdf::RenderMethod method);
  int runMethodSwitches(const char* label, int frames);

  // Runs `frames` steps of `script` (which moves the scene for frame i and returns its shot),
  // comparing every frame of the long-lived renderer with a fresh renderer's. Returns the
  // differing pixels of all frames; each frame that differs fails the test, named.
  int walk(const char* label, int frames, const std::function<Shot(int)>& script) {
    int total = 0, covered = 0;
    double keptSeconds = 0.0, freshSeconds = 0.0;
    occludedFrames_ = 0;
    for (int i = 0; i < frames; ++i) {
      const Shot shot = script(i);
      scene::updateWorldTransforms(registry_);
      const auto start = std::chrono::steady_clock::now();
      const Frame kept = renderWith(shot.camera, frameSettings(i));
      const auto drawn = std::chrono::steady_clock::now();
      const Frame fresh = freshFrame(shot.camera, i);
      keptSeconds += std::chrono::duration<double>(drawn - start).count();
      freshSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - drawn).count();
      const int diff = int(differingPixels(kept, fresh));
      occludedFrames_ += renderer_->feature<hsdf::HermiteCellFeature>()->usesOcclusionCulling();
      logFrame(label, i, shot, kept, fresh, diff);
      covered += int(std::count_if(fresh.depth.begin(), fresh.depth.end(), [](float d) { return d > 0.0f; }));
      EXPECT_EQ(diff, 0) << label << ", frame " << i << " (" << shot.what << "): pixels unlike a fresh renderer's";
      total += diff;
    }
    std::printf("[ %s ] %d frames (%d culled by occlusion), %d pixels drawn, %d differing (%.1f s kept, %.1f s fresh)\n",
                label, frames, occludedFrames_, covered, total, keptSeconds, freshSeconds);
    return total;
  }

  // With HSDF_TEST_VERBOSE the cell feature's counts of the frame; with HSDF_TEST_DUMP=folder both
  // images as PNGs.
  void logFrame(const char* label, int i, const Shot& shot, const Frame& kept, const Frame& fresh, int diff) {
    if (const char* dump = std::getenv("HSDF_TEST_DUMP")) {
      const std::string prefix = std::string(dump) + "/" + label + "_" + std::to_string(i);
      (void)writePng(prefix + "_kept.png", kept.rgba, kWidth, kHeight, 4);
      (void)writePng(prefix + "_fresh.png", fresh.rgba, kWidth, kHeight, 4);
    }
    if (!std::getenv("HSDF_TEST_VERBOSE")) return;
    const auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
    std::printf("[ %s ] frame %2d %-40s objects %u, cells tested %llu kept %llu fallback %u, tiles' boxes %u, "
                "occlusion %d, differing %d\n",
                label, i, shot.what.c_str(), feature->stats().objects,
                static_cast<unsigned long long>(feature->cullTotals().tested),
                static_cast<unsigned long long>(feature->cullTotals().kept), feature->cullTotals().fallbackCells,
                feature->tileTotals().boxDrawCount, int(feature->usesOcclusionCulling()), diff);
  }

  // Frame i's settings: with split_, two view regions split at a column that moves 4 pixels a
  // frame, the right one drawing every SDF from fp16 records (the compared side of a split screen:
  // each region keeps its own history and streams).
  render::FrameSettings frameSettings(int i) {
    render::FrameSettings settings;
    if (!split_) return settings;
    const auto halfPrecision = [this](bool half) {
      return [this, half] {
        registry_.view<hsdf::HermiteSdfRenderable>().each(
            [half](ecs::Entity, hsdf::HermiteSdfRenderable& renderable) { renderable.halfPrecision = half; });
      };
    };
    const std::uint32_t column = 40 + 4 * std::uint32_t(i);
    settings.regions = {{VkRect2D{{0, 0}, {column, kHeight}}, halfPrecision(false)},
                        {VkRect2D{{std::int32_t(column), 0}, {kWidth - column, kHeight}}, halfPrecision(true)}};
    return settings;
  }

  CellSettings freshSettings_;
  bool split_ = false;
  bool tracers_ = false;  // the sphere tracers' feature too (start)
  int occludedFrames_ = 0;  // of the last walk: frames the long-lived renderer culled by occlusion
};

// The scene: a sphere in front (drawn by `method`), a torus behind it (by `method`) that slides out
// and back, a box (runs) that passes through the sphere, a mesh wall that slides across through
// the sphere, a bunny that comes, turns into bricks and runs and goes, the sphere removed and put
// back; the camera orbits slowly, jumps to the other side, turns fast, enters the sphere and comes
// back. Returns the differing pixels of all frames.
int FrameHistoryTest::runScene(const char* label, int frames, hsdf::RenderMethod method) {
  const auto [sphere, torus, box, bunny] = walkAssets();
  if (!sphere || !torus || !box || !bunny) return -1;
  const ecs::Entity front = addObject(sphere, method, placed({0.0f, 0.0f, 0.0f}, 1.0f));
  const ecs::Entity behind = addObject(torus, method, placed({0.0f, 0.0f, -3.0f}, 0.6f));
  const ecs::Entity crossing = addObject(box, hsdf::RenderMethod::CellRuns, placed({-2.0f, 0.3f, 0.0f}, 0.5f));
  const ecs::Entity wall = addQuad({3.0f, 0.0f, 0.3f}, 2.2f, glm::vec4(0.2f, 0.6f, 0.9f, 1.0f));
  const glm::mat4 bunnyPlace = glm::translate(
      placed({0.9f, 0.6f, -0.8f}, 1.5f / float(glm::length(bunny->surfaceBounds.size()))),
      -glm::vec3(bunny->surfaceBounds.center()));
  ecs::Entity visitor{};
  const glm::vec3 target(0.0f, 0.0f, -1.0f);
  const auto orbit = [&](float yaw, float pitch, float distance) {
    const glm::vec3 eye = target + distance * glm::vec3(std::sin(yaw) * std::cos(pitch), std::sin(pitch),
                                                        std::cos(yaw) * std::cos(pitch));
    return render::CameraView::lookAt(eye, target, 0.9f, 0.02f, kAspect);
  };
  return walk(label, frames, [&](int i) -> Shot {
    // The torus slides out from behind the sphere (frames 0-7), then back (8-13).
    const float slide = i < 8 ? 0.35f * float(i) : std::max(0.0f, 2.45f - 0.45f * float(i - 7));
    place(behind, placed({slide, 0.0f, -3.0f}, 0.6f, 0.2f * float(i)));
    place(crossing, placed({-2.0f + 0.4f * float(i % 12), 0.3f, 0.1f * float(i % 5)}, 0.5f, 0.3f * float(i)));
    registry_.get<scene::Transform>(wall).translation = {3.0f - 0.5f * float(i), 0.0f, 0.3f};
    Shot shot{{}, "orbit"};
    switch (i) {
      case 4:
        visitor = addObject(bunny, hsdf::RenderMethod::Cells, bunnyPlace);
        shot.what = "bunny appears";
        break;
      case 7:
        registry_.get<hsdf::HermiteSdfRenderable>(visitor).method = hsdf::RenderMethod::CellBricks;
        shot.what = "bunny as bricks";
        break;
      case 9:
        registry_.get<hsdf::HermiteSdfRenderable>(visitor).method = hsdf::RenderMethod::CellRuns;
        shot.what = "bunny as runs";
        break;
      case 12:
        registry_.destroy(visitor);
        shot.what = "bunny removed";
        break;
      case 15:
        registry_.remove<hsdf::HermiteSdfRenderable>(front);
        shot.what = "sphere removed";
        break;
      case 17:
        registry_.emplace<hsdf::HermiteSdfRenderable>(front, hsdf::HermiteSdfRenderable{sphere, method});
        shot.what = "sphere back";
        break;
      default:
        break;
    }
    // The camera: a slow orbit, a jump to the other side (frame 10), fast turns (11-13), the eye
    // inside the sphere (14 and 18), in front otherwise.
    if (i < 10) {
      shot.camera = orbit(0.05f * float(i), 0.1f, 5.0f);
    } else if (i == 10) {
      shot.camera = orbit(3.1f, -0.2f, 5.0f);
      shot.what += ", jump behind";
    } else if (i < 14) {
      shot.camera = orbit(3.1f + 0.9f * float(i - 10), 0.4f * float(i - 11), 4.0f);
      shot.what += ", fast turn";
    } else if (i == 14 || i == 18) {
      shot.camera = render::CameraView::lookAt({0.1f, 0.05f, 0.2f}, {0.0f, 0.0f, -3.0f}, 1.2f, 0.02f, kAspect);
      shot.what += ", eye inside the sphere";
    } else {
      shot.camera = orbit(0.2f - 0.05f * float(i - 15), 0.05f, 4.0f);
      shot.what += ", in front";
    }
    return shot;
  });
}

// Four objects through each other that change how they are drawn while the others keep drawing:
// the sphere and the torus take the next of the five methods every frame (cells, runs, bricks,
// trilinear, Hermite: an entity leaves the cell feature for a tracer and comes back), the box
// turns into the torus's asset and back every other frame, the bunny is hidden (its renderable
// removed), shown again as a tracer, destroyed, and made again as cells (on the freed index); the
// camera orbits. Returns the differing pixels of all frames.
int FrameHistoryTest::runMethodSwitches(const char* label, int frames) {
  const auto [sphere, torus, box, bunny] = walkAssets();
  if (!sphere || !torus || !box || !bunny) return -1;
  const hsdf::RenderMethod kinds[] = {hsdf::RenderMethod::Cells, hsdf::RenderMethod::CellRuns,
                                      hsdf::RenderMethod::CellBricks, hsdf::RenderMethod::TrilinearSphereTrace,
                                      hsdf::RenderMethod::HermiteSphereTrace};
  const ecs::Entity first = addObject(sphere, kinds[0], placed({0.0f, 0.0f, 0.0f}, 1.0f));
  const ecs::Entity second = addObject(torus, kinds[3], placed({0.6f, 0.2f, -0.8f}, 0.8f, 0.5f));
  const ecs::Entity third = addObject(box, hsdf::RenderMethod::Cells, placed({-0.7f, -0.2f, 0.3f}, 0.5f));
  const glm::mat4 bunnyPlace = glm::translate(placed({0.3f, 0.5f, 0.6f}, 1.5f / float(glm::length(bunny->surfaceBounds.size()))),
                                              -glm::vec3(bunny->surfaceBounds.center()));
  ecs::Entity visitor = addObject(bunny, hsdf::RenderMethod::Cells, bunnyPlace);
  const glm::vec3 target(0.0f, 0.0f, -0.2f);
  return walk(label, frames, [&](int i) -> Shot {
    registry_.get<hsdf::HermiteSdfRenderable>(first).method = kinds[i % 5];
    registry_.get<hsdf::HermiteSdfRenderable>(second).method = kinds[(i + 3) % 5];
    registry_.get<hsdf::HermiteSdfRenderable>(third).asset = i % 4 < 2 ? box : torus;
    Shot shot{{}, fmt::format("sphere {}, torus {}", hsdf::renderMethodName(kinds[i % 5]),
                              hsdf::renderMethodName(kinds[(i + 3) % 5]))};
    switch (i) {
      case 3:
        registry_.remove<hsdf::HermiteSdfRenderable>(visitor);
        shot.what += ", bunny hidden";
        break;
      case 5:
        registry_.emplace<hsdf::HermiteSdfRenderable>(visitor,
                                                      hsdf::HermiteSdfRenderable{bunny, hsdf::RenderMethod::HermiteSphereTrace});
        shot.what += ", bunny traced";
        break;
      case 7:
        registry_.destroy(visitor);
        shot.what += ", bunny destroyed";
        break;
      case 8:
        visitor = addObject(bunny, hsdf::RenderMethod::CellRuns, bunnyPlace);
        shot.what += ", bunny made again as runs";
        break;
      default:
        break;
    }
    const float yaw = 0.25f * float(i);
    const glm::vec3 eye = target + 3.5f * glm::vec3(std::sin(yaw), 0.3f, std::cos(yaw));
    shot.camera = render::CameraView::lookAt(eye, target, 0.9f, 0.02f, kAspect);
    return shot;
  });
}

// Why: the renderers keep per-entity state across features: the cell feature's uploaded assets,
// the entity's last drawn asset (drawn while a replacement uploads), its occlusion history place,
// the tracers' textures; an entity that leaves the cells for a tracer, changes asset, is hidden
// or destroyed and made again on its index must be drawn in that very frame as a fresh renderer
// draws it, and so must the objects around it. Occlusion culling (a history per entity).
TEST_F(FrameHistoryTest, ObjectsThatChangeMethodAssetOrVisibilityDrawEachFrameAsAFreshRenderer) {
  tracers_ = true;
  start(occlusionCulling());
  EXPECT_EQ(runMethodSwitches("method switches, occlusion", 10), 0);
}

// Boxes with two-phase occlusion culling: the torus comes out from behind the sphere and must be
// drawn in that very frame (phase 2), not the next; kept-cell streams sized by the share of cells
// the slot's previous frame kept (keptStreamBytes below the scene's cells), so a frame that keeps
// more than the one before draws the rows that do not fit whole, in either phase.
TEST_F(FrameHistoryTest, EveryFrameOfAMovingSceneIsTheFreshRenderersWithOcclusionCulling) {
  CellSettings settings = occlusionCulling();
  settings.keptStreamBytes = 1;
  start(settings);
  EXPECT_EQ(runScene("boxes, occlusion", 20, hsdf::RenderMethod::Cells), 0);
  EXPECT_EQ(occludedFrames_, 20) << "a frame drew without occlusion culling";
}

// A split screen with occlusion culling: each view region keeps its own history, and the split
// moves, so a region's cells visible last frame may lie in the other region now.
TEST_F(FrameHistoryTest, EveryFrameOfAMovingSplitScreenIsTheFreshRenderersWithOcclusionCulling) {
  split_ = true;
  start(occlusionCulling());
  EXPECT_EQ(runScene("split, occlusion", 20, hsdf::RenderMethod::Cells), 0);
  EXPECT_EQ(occludedFrames_, 20) << "a frame drew without occlusion culling";
}

// Tiles: lists sized by the slot's earlier frames (a jump nearer or into the sphere wants more
// entries than the frame before), boxes for the cells the near plane may cut.
TEST_F(FrameHistoryTest, EveryFrameOfAMovingSceneIsTheFreshRenderersWithTiles) {
  CellSettings settings;
  settings.tiles = hsdf::HermiteCellFeature::Tiles::On;
  start(settings);
  EXPECT_EQ(runScene("tiles", 20, hsdf::RenderMethod::Cells), 0);
}

}  // namespace
}  // namespace gputest
