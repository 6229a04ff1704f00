// The Viewer playing a glTF animation (SceneDesc::animation, samples/common/animation_player.h),
// headless on the test device with validation on: the frame at time t is compared pixel by pixel
// with the frame of the same scene made still, its door node's transform set to the pose at t
// worked by hand. tests/data/gltf/swinging_door.gltf (tools/gltf_testdata/make_animated.py): the
// door slides 0 -> 1 along x and turns 0 -> 170 degrees about y, both LINEAR over 2 s.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "test_viewer.h"

namespace samples {
namespace {

const std::filesystem::path kDoor = hsdftest::testData("gltf/swinging_door.gltf");
constexpr float kTime = 0.5f;  // a quarter of the way: slerp and a normalized lerp differ by ~7 degrees
constexpr int kSteps = 31;     // frames from t = 0 at 1/60 s each: the last shows t = 0.5

// The door file with no animation and the door node at the pose of t = 0.5, by hand: translation
// (0.25, 0, 0); a quarter of 170 degrees about y, 42.5 degrees (slerp turns at a constant rate).
std::filesystem::path stillDoorAtQuarter() {
  std::ifstream in(kDoor);
  nlohmann::json doc = nlohmann::json::parse(in);
  doc.erase("animations");
  const double half = 0.5 * 42.5 * M_PI / 180.0;
  doc["nodes"][1]["translation"] = {0.25, 0.0, 0.0};
  doc["nodes"][1]["rotation"] = {0.0, std::sin(half), 0.0, std::cos(half)};
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "hsdf_viewer_animation_still_door.gltf";
  std::ofstream(path) << doc.dump();
  return path;
}

// The colour of the last of `steps` frames of `gltf` drawn by `method` (objects: one SDF per node).
std::vector<std::uint8_t> lastFrame(const std::filesystem::path& gltf, Method method, const std::string& animation,
                                    int steps) {
  auto viewer = makeTestViewer(128, 96);
  if (!viewer) return {};
  SceneDesc scene;
  scene.gltf = gltf;
  scene.groundPlane = false;
  scene.objects = true;
  scene.animation = animation;
  TuningState tuning;
  tuning.method = method;
  tuning.resolution = 32;
  const engine::Status loaded = viewer->loadScene(scene, tuning);
  EXPECT_TRUE(loaded.ok()) << loaded.error().message;
  if (!loaded.ok()) return {};
  viewer->setCamera(glm::dvec3(2.0, 4.0, 6.0), glm::dvec3(0.8, 0.3, 0.0));
  for (int s = 0; s < steps; ++s) EXPECT_TRUE(viewer->step().ok());
  viewer->renderer().finish();
  return viewer->renderer().readbackColor();
}

// Pixels whose colour differs by more than a few levels in a channel.
int differingPixels(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  int differ = 0;
  for (std::size_t i = 0; i + 3 < a.size() && i + 3 < b.size(); i += 4)
    for (int c = 0; c < 3; ++c)
      if (std::abs(int(a[i + c]) - int(b[i + c])) > 8) {
        ++differ;
        break;
      }
  return differ;
}

// Played for 30 frames from t = 0, the door stands where the still file puts it by hand; the rest
// pose (the animation not played) stands elsewhere, so the comparison can tell the two apart.
void expectPlayedFrameMatchesHandPose(Method method, const char* name) {
  const std::vector<std::uint8_t> played = lastFrame(kDoor, method, "", kSteps);
  const std::vector<std::uint8_t> still = lastFrame(stillDoorAtQuarter(), method, "none", 1);
  const std::vector<std::uint8_t> rest = lastFrame(kDoor, method, "none", kSteps);
  ASSERT_FALSE(played.empty());
  ASSERT_EQ(played.size(), still.size());
  const int pixels = int(played.size() / 4);
  const int playedVsStill = differingPixels(played, still);
  const int restVsStill = differingPixels(rest, still);
  std::printf("[ %s ] of %d px: played vs hand pose %d differ; rest pose vs hand pose %d differ\n", name, pixels,
              playedVsStill, restVsStill);
  EXPECT_LE(playedVsStill, pixels / 400) << name;  // 0 on lavapipe; a lerp for the slerp: 88 and 107
  EXPECT_GE(restVsStill, pixels / 50) << name << ": the test cannot see the door move";
}

TEST(ViewerAnimation, MeshFramePlayedToTimeTMatchesTheHandComputedPose) {
  expectPlayedFrameMatchesHandPose(Method::Mesh, "mesh");
}

TEST(ViewerAnimation, SdfObjectsFramePlayedToTimeTMatchesTheHandComputedPose) {
  expectPlayedFrameMatchesHandPose(hsdf::RenderMethod::Cells, "cells, objects");
}

// Without --objects the one SDF bakes the scene: the animation is drawn still, posed at the start
// time (the pose the bake would see), and later frames do not move it.
TEST(ViewerAnimation, OneSdfSceneIsDrawnStillAtTheStartTime) {
  auto viewer = makeTestViewer(128, 96);
  ASSERT_NE(viewer, nullptr);
  SceneDesc scene;
  scene.gltf = kDoor;
  scene.groundPlane = false;
  scene.animationTime = kTime;
  TuningState tuning;
  tuning.method = Method::Mesh;
  ASSERT_TRUE(viewer->loadScene(scene, tuning).ok());
  viewer->setCamera(glm::dvec3(2.0, 4.0, 6.0), glm::dvec3(0.8, 0.3, 0.0));
  ASSERT_TRUE(viewer->step().ok());
  viewer->renderer().finish();
  const std::vector<std::uint8_t> first = viewer->renderer().readbackColor();
  for (int s = 0; s < 10; ++s) ASSERT_TRUE(viewer->step().ok());
  viewer->renderer().finish();
  EXPECT_EQ(differingPixels(first, viewer->renderer().readbackColor()), 0) << "nothing moves without --objects";
  const std::vector<std::uint8_t> still = lastFrame(stillDoorAtQuarter(), Method::Mesh, "none", 1);
  EXPECT_LE(differingPixels(first, still), int(still.size() / 4 / 200)) << "posed at --animation-time";
}

TEST(ViewerAnimation, AnUnknownAnimationIsAnErrorNamingTheFilesAnimations) {
  auto viewer = makeTestViewer(64, 48);
  ASSERT_NE(viewer, nullptr);
  SceneDesc scene;
  scene.gltf = kDoor;
  scene.animation = "open";
  const engine::Status loaded = viewer->loadScene(scene, TuningState{});
  ASSERT_FALSE(loaded.ok());
  EXPECT_NE(loaded.error().message.find("--animation 'open': no such animation (the file has: 0 'swing')"),
            std::string::npos)
      << loaded.error().message;
}

}  // namespace
}  // namespace samples
