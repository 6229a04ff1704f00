// Random walks through the tuning (samples/common/tuning.h) on a running Viewer, headless on the
// test device with validation on: wherever a walk ends, the frame is the one a fresh Viewer started
// with that tuning draws.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "test_viewer.h"

namespace samples {
namespace {

constexpr std::uint32_t kWidth = 96, kHeight = 72;

// Every key of a settings file with values worth walking through (small K: the walk re-bakes).
struct Choice {
  const char* key;
  std::vector<const char*> values;
};
const std::vector<Choice> kChoices = {
    {"method", {"cells", "cells", "cells", "trilinear", "hermite", "cells-runs", "cell-bricks", "mesh"}},
    {"resolution", {"16", "20", "24"}},
    {"padding", {"1", "2"}},
    {"subdivisions", {"1", "2", "3", "5"}},
    {"refine", {"0", "1", "2"}},
    {"normals", {"exact", "central"}},
    {"fp16", {"true", "false"}},
    {"debug_view", {"none", "none", "normals", "depth", "cells", "evals", "wireframe"}},
    {"front_to_back", {"true", "false"}},
    {"early_depth", {"auto", "true", "false"}},
    {"certified", {"true", "false"}},
    {"cull_bricks", {"true", "false"}},
    {"cull_cells", {"true", "false"}},
    {"cull_occlusion", {"true", "false"}},
    {"proxy_boxes", {"true", "false"}},
    {"thin_boxes", {"auto", "true", "false"}},
    {"tiles", {"auto", "true", "false"}},
    {"tile_size", {"4", "8", "16"}},
    {"split", {"off", "off", "vertical", "horizontal"}},
    {"split_position", {"0.05", "0.3", "0.5", "0.95"}},
    {"compare_method", {"cells", "trilinear", "hermite", "cells-runs", "cell-bricks"}},
    {"compare_resolution", {"0", "16", "24"}},
    {"compare_normals", {"exact", "central"}},
    {"difference", {"false", "false", "true"}},
    {"node_draw", {"sdf", "triangles"}},
    {"lod", {"false", "true"}},
    {"lod_pixels_per_cell", {"0.25", "2", "16"}},
    {"trace_epsilon", {"0.0001", "0.001"}},
    {"trace_max_steps", {"64", "1024"}},
    {"central_difference_step", {"0.25", "0.5"}},
    {"max_run_length", {"1", "4", "8"}},
};

std::vector<std::uint8_t> settledImage(Viewer& viewer) {
  // A few frames for what sizes itself from earlier frames (kept-cell streams, tile lists,
  // occlusion history): the image must not depend on them, but the fresh viewer gets them too.
  for (int frame = 0; frame < 3; ++frame) {
    const engine::Status stepped = viewer.step();
    EXPECT_TRUE(stepped.ok()) << stepped.error().message;
  }
  viewer.renderer().finish();
  return viewer.renderer().readbackColor();
}

// Walks `steps` frames from `start`, 1-3 random settings changed before each (a re-bake waited for
// now and then, an orbit view now and then), then compares the settled frame with a fresh viewer's
// at the walk's last tuning and view. `path` in every message replays the walk.
void walkAndCompare(const SceneDesc& scene, const TuningState& start, std::uint32_t seed, int steps) {
  std::mt19937 rng(seed);
  const auto pick = [&rng](std::size_t n) { return std::size_t(rng() % n); };
  auto walked = makeTestViewer(kWidth, kHeight);
  ASSERT_NE(walked, nullptr);
  const engine::Status loaded = walked->loadScene(scene, start);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  TuningState tuning = start;
  int view = 0;
  std::string path = fmt::format("seed {}:", seed);
  for (int step = 0; step < steps; ++step) {
    path += fmt::format(" | {}:", step);
    for (std::size_t change = 0, changes = 1 + pick(3); change < changes; ++change) {
      const Choice& choice = kChoices[pick(kChoices.size())];
      const char* value = choice.values[pick(choice.values.size())];
      const engine::Status set = setTuningValue(tuning, choice.key, value);
      ASSERT_TRUE(set.ok()) << path << ": " << set.error().message;
      path += fmt::format(" {}={}", choice.key, value);
    }
    walked->setTuning(tuning);
    if (pick(8) == 0) {
      view = int(pick(8));
      walked->setOrbitView(view);
      path += fmt::format(" view={}", view);
    }
    if (pick(4) == 0) {
      const engine::Status baked = walked->waitForBake();
      ASSERT_TRUE(baked.ok()) << path << ": " << baked.error().message;
      path += " wait-bake";
    }
    const engine::Status stepped = walked->step();
    ASSERT_TRUE(stepped.ok()) << path << ": " << stepped.error().message;
  }
  const engine::Status baked = walked->waitForBake();
  ASSERT_TRUE(baked.ok()) << path << ": " << baked.error().message;
  // No setting of the walk is refused or undone (no bake past the budget, none cancelled).
  EXPECT_EQ(walked->tuning().resolution, tuning.resolution) << path;
  const std::vector<std::uint8_t> walkedImage = settledImage(*walked);

  auto fresh = makeTestViewer(kWidth, kHeight);
  ASSERT_NE(fresh, nullptr);
  const engine::Status freshLoaded = fresh->loadScene(scene, tuning);
  ASSERT_TRUE(freshLoaded.ok()) << path << ": " << freshLoaded.error().message;
  fresh->setOrbitView(view);
  const engine::Status freshBaked = fresh->waitForBake();
  ASSERT_TRUE(freshBaked.ok()) << path << ": " << freshBaked.error().message;
  const std::vector<std::uint8_t> freshImage = settledImage(*fresh);

  ASSERT_EQ(walkedImage.size(), freshImage.size());
  int differing = 0;
  for (std::size_t i = 0; i < walkedImage.size(); i += 4)
    differing += walkedImage[i] != freshImage[i] || walkedImage[i + 1] != freshImage[i + 1] ||
                 walkedImage[i + 2] != freshImage[i + 2];
  EXPECT_EQ(differing, 0) << "pixels of the walked viewer's frame that a fresh viewer at its tuning draws otherwise; "
                          << path;
  const engine::Status walkedClosed = walked->close();
  EXPECT_TRUE(walkedClosed.ok()) << path << ": " << walkedClosed.error().message;
  const engine::Status freshClosed = fresh->close();
  EXPECT_TRUE(freshClosed.ok()) << path << ": " << freshClosed.error().message;
}

// Why: the panel and scripts change one setting at a time over a long run, and every feature keeps
// state from frame to frame: pipelines per variant, kept-cell streams and tile lists sized by
// earlier frames, occlusion culling's history, the compared side's bake, levels of detail, SDFs
// hidden behind their meshes and back. A setting that leaves something of the previous state
// behind (a stale pipeline, a history entry, a bake of the old K, an Auto choice never made
// again) shows as a frame that differs from a fresh start at the same tuning. Each walk also runs
// every transition under the validation layers (close() fails on any message). Seeds are fixed,
// so a failure replays; the message lists the walk.
TEST(ViewerWalk, AnyWalkThroughTheTuningEndsInTheFrameOfAFreshStart) {
  SceneDesc scene;
  scene.gltf = hsdftest::sampleAsset("bunny.glb");
  TuningState start;
  start.resolution = 16;
  for (const std::uint32_t seed : {20261127u, 7u, 4242u, 11u, 12u, 13u, 14u, 15u}) walkAndCompare(scene, start, seed, 16);
}

// The same over a scene of objects (4 meshes at 120 nodes: per-node SDF or triangles, every mesh
// re-baked at a new K, levels of detail per node).
TEST(ViewerWalk, AnyWalkThroughAScenesTuningEndsInTheFrameOfAFreshStart) {
  SceneDesc scene;
  scene.gltf = hsdftest::sampleAsset("grid_scene.glb");
  scene.objects = true;
  TuningState start;
  start.resolution = 16;
  walkAndCompare(scene, start, 99u, 16);
}

}  // namespace
}  // namespace samples
