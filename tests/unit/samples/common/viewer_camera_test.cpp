// The Viewer's camera (samples/common/viewer_camera.cpp): looking through a glTF scene's camera
// nodes, and orbit and fly taking over from them. The scene, tests/data/gltf/camera_cube.gltf, is a
// unit cube at the origin and camera nodes placed as a graphics tool writes them: "front" under a
// parent rotated 90 degrees about Y and scaled by (2, 1, 2) (its world eye is (4, 0, 0), looking
// down -X),
// "away" at (0, 0, 4) turned to look along +Z, "tilted" at (0, 0, 4) pitched up by 0.2 rad with a
// yfov of 0.3 and znear 0.5, "flat" with a zero scale, an unnamed one and "ortho" at (0, 0, 4), an
// orthographic camera ("plan": xmag = ymag = 1, znear 0.1, zfar 10) looking down -Z.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/scene/transform.h"
#include "test_viewer.h"

namespace samples {
namespace {

constexpr std::uint32_t kWidth = 96, kHeight = 64;
const std::filesystem::path kScene = hsdftest::testData("gltf/camera_cube.gltf");

std::unique_ptr<Viewer> viewCameraCube() {
  auto viewer = makeTestViewer(kWidth, kHeight);
  if (!viewer) return nullptr;
  SceneDesc scene;
  scene.gltf = kScene;
  scene.groundPlane = false;
  TuningState tuning;
  tuning.method = hsdf::RenderMethod::Cells;
  tuning.resolution = 16;
  const engine::Status loaded = viewer->loadScene(scene, tuning);
  EXPECT_TRUE(loaded.ok()) << loaded.error().message;
  return loaded.ok() ? std::move(viewer) : nullptr;
}

std::vector<std::uint8_t> frame(Viewer& viewer) {
  EXPECT_TRUE(viewer.step().ok());
  viewer.renderer().finish();
  return viewer.renderer().readbackColor();
}

// Pixels that differ from the top-left one (the background: no ground plane).
std::size_t covered(const std::vector<std::uint8_t>& rgba) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < rgba.size(); i += 4)
    if (rgba[i] != rgba[0] || rgba[i + 1] != rgba[1] || rgba[i + 2] != rgba[2]) ++count;
  return count;
}

glm::vec3 forwardOf(const engine::render::CameraView& view) {
  return -glm::normalize(glm::vec3(glm::inverse(view.view)[2]));
}

void expectSameCamera(const engine::render::CameraView& a, const engine::render::CameraView& b, const char* what) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) {
      EXPECT_NEAR(a.view[c][r], b.view[c][r], 1e-5f) << what << ": view[" << c << "][" << r << "]";
      EXPECT_NEAR(a.proj[c][r], b.proj[c][r], 1e-5f) << what << ": proj[" << c << "][" << r << "]";
    }
  EXPECT_NEAR(glm::length(a.position - b.position), 0.0f, 1e-5f) << what;
  EXPECT_FLOAT_EQ(a.znear, b.znear) << what;
  EXPECT_FLOAT_EQ(a.fovY, b.fovY) << what;
}

engine::ecs::Entity named(Viewer& viewer, const std::string& name) {
  engine::ecs::Entity found{};
  viewer.registry().view<engine::scene::Name>().each([&](engine::ecs::Entity e, const engine::scene::Name& n) {
    if (n.value == name) found = e;
  });
  return found;
}

// Tricky: the orthographic camera is listed with the perspective ones, in node order, and a node
// without a name still needs one the panel and --scene-camera can use.
TEST(SceneCameras, AreListedInNodeOrderByName) {
  auto viewer = viewCameraCube();
  ASSERT_TRUE(viewer);
  EXPECT_EQ(viewer->sceneCameraNames(),
            (std::vector<std::string>{"front", "away", "tilted", "flat", "camera 4", "ortho"}));
  EXPECT_EQ(viewer->cameraMode(), CameraMode::Orbit) << "a scene's cameras are offered, not taken";
}

// Tricky: "front"'s pose comes through a rotated parent with a non-uniform scale. The view must be
// the camera's own, built independently here by lookAt from the eye and target the file's numbers
// give: a scale left in the view matrix would squash the image (and change its depths).
TEST(SceneCameras, LookThroughTheNodesPoseWithoutItsScale) {
  auto viewer = viewCameraCube();
  ASSERT_TRUE(viewer);
  const float aspect = float(kWidth) / float(kHeight);
  ASSERT_TRUE(viewer->lookThroughSceneCamera("front").ok());
  EXPECT_EQ(viewer->cameraMode(), CameraMode::Scene);
  EXPECT_EQ(viewer->sceneCamera(), 0u);
  expectSameCamera(viewer->cameraView(),
                   engine::render::CameraView::lookAt({4.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0.8f, 0.05f, aspect),
                   "front");
  // By index; the node's own yfov and znear; pitched up by 0.2 rad about x.
  ASSERT_TRUE(viewer->lookThroughSceneCamera("2").ok());
  const glm::vec3 eye(0.0f, 0.0f, 4.0f);
  const glm::vec3 ahead(0.0f, std::sin(0.2f), -std::cos(0.2f));
  expectSameCamera(viewer->cameraView(), engine::render::CameraView::lookAt(eye, eye + ahead, 0.3f, 0.5f, aspect),
                   "tilted");
}

// Tricky: exporters name a camera's node and its camera data apart (Blender: node "Camera", camera
// "Camera.001"); a user reading the file may give either. The camera's own name picks the first
// node showing it ("lens" is shown by four nodes), a node's name wins over a camera's, and the
// orthographic camera is found by its own name too.
TEST(SceneCameras, ACamerasOwnNamePicksTheFirstNodeShowingIt) {
  auto viewer = viewCameraCube();
  ASSERT_TRUE(viewer);
  ASSERT_TRUE(viewer->lookThroughSceneCamera("tele").ok());
  EXPECT_EQ(viewer->sceneCamera(), 2u) << "tele is tilted's camera";
  ASSERT_TRUE(viewer->lookThroughSceneCamera("lens").ok());
  EXPECT_EQ(viewer->sceneCamera(), 0u) << "lens is shown by front first";
  ASSERT_TRUE(viewer->lookThroughSceneCamera("plan").ok());
  EXPECT_EQ(viewer->sceneCamera(), 5u) << "plan is ortho's camera";
  EXPECT_TRUE(viewer->cameraView().orthographic());
}

// Tricky: --scene-camera must select an orthographic camera and the frame must be drawn through
// it: the unit cube seen straight down -Z through a view 2 units tall (ymag 1) covers half the
// image's height at any distance, and the projection is the file's (depth linear between its
// znear and zfar), not the viewer's perspective.
TEST(SceneCameras, AnOrthographicCameraDrawsThroughItsProjection) {
  auto viewer = viewCameraCube();
  ASSERT_TRUE(viewer);
  ASSERT_TRUE(viewer->lookThroughSceneCamera("ortho").ok());
  const engine::render::CameraView view = viewer->cameraView();
  ASSERT_TRUE(view.orthographic());
  EXPECT_FLOAT_EQ(view.ymag, 1.0f);
  EXPECT_FLOAT_EQ(view.znear, 0.1f);
  EXPECT_FLOAT_EQ(view.zfar, 10.0f);
  // The cube's front face (z = 0.5) is 3.5 in front of the camera: depth (10 - 3.5) / 9.9.
  const glm::vec4 clip = view.proj * view.view * glm::vec4(0.0f, 0.0f, 0.5f, 1.0f);
  EXPECT_NEAR(clip.z / clip.w, 6.5f / 9.9f, 1e-5f);
  // The face spans y in [-0.5, 0.5] of the view's [-1, 1]: rows kHeight / 4 .. 3 kHeight / 4.
  const std::vector<std::uint8_t> pixels = frame(*viewer);
  const auto coveredRow = [&](std::uint32_t y) {  // pixels unlike the background (the top-left one)
    std::uint32_t count = 0;
    for (std::uint32_t x = 0; x < kWidth; ++x)
      for (std::size_t c = 0; c < 3; ++c)
        if (pixels[(y * kWidth + x) * 4 + c] != pixels[c]) {
          ++count;
          break;
        }
    return count;
  };
  EXPECT_EQ(coveredRow(kHeight / 4 - 2), 0u) << "above the cube";
  EXPECT_EQ(coveredRow(kHeight / 2), kHeight / 2) << "the face is as wide as it is tall: kHeight / 2 pixels";
  EXPECT_EQ(coveredRow(3 * kHeight / 4 + 1), 0u) << "below the cube";
}

// Tricky: the cells' and tiles' culling, the depth prepass and the resolve all take the frame's
// camera; the frame through "front" must show the cube as an orbit camera placed at the same eye
// does (the same yfov; only the near plane differs: the file's 0.05 against the viewer's), and
// "away" must show nothing of it.
TEST(SceneCameras, FramesShowWhatTheCameraSees) {
  auto viewer = viewCameraCube();
  ASSERT_TRUE(viewer);
  ASSERT_TRUE(viewer->lookThroughSceneCamera("front").ok());
  const std::vector<std::uint8_t> front = frame(*viewer);
  viewer->setCamera({4.0, 0.0, 0.0}, {0.0, 0.0, 0.0});
  const std::vector<std::uint8_t> orbit = frame(*viewer);
  ASSERT_EQ(front.size(), orbit.size());
  EXPECT_GT(covered(front), kWidth * kHeight / 20) << "the cube fills the middle of the frame";
  std::size_t differing = 0;
  for (std::size_t i = 0; i < front.size(); i += 4)
    for (std::size_t c = 0; c < 3; ++c)
      if (std::abs(int(front[i + c]) - int(orbit[i + c])) > 8) {
        ++differing;
        break;
      }
  EXPECT_LE(differing, kWidth * kHeight / 200) << "the scene camera's frame and the orbit's at its eye differ";
  ASSERT_TRUE(viewer->lookThroughSceneCamera("away").ok());
  EXPECT_EQ(covered(frame(*viewer)), 0u) << "a camera looking away from the cube sees none of it";
}

// Tricky: a bad choice must say why and leave the camera where it was, not half-switch to a
// camera that cannot draw (a zero scale has no view direction).
TEST(SceneCameras, BadChoicesAreRefusedNamingTheCamera) {
  auto viewer = viewCameraCube();
  ASSERT_TRUE(viewer);
  const engine::render::CameraView before = viewer->cameraView();
  const engine::Status flat = viewer->lookThroughSceneCamera("flat");
  ASSERT_FALSE(flat.ok());
  EXPECT_NE(flat.error().message.find("scene camera 'flat': the camera's Z axis has zero length"), std::string::npos)
      << flat.error().message;
  for (const char* missing : {"planar", "6", "-1", "1x", ""}) {
    const engine::Status refused = viewer->lookThroughSceneCamera(std::string_view(missing));
    ASSERT_FALSE(refused.ok()) << missing;
    EXPECT_NE(refused.error().message.find("the scene's cameras: front, away, tilted, flat, camera 4, ortho"),
              std::string::npos)
        << refused.error().message;
  }
  EXPECT_FALSE(viewer->lookThroughSceneCamera(std::size_t(6)).ok());
  EXPECT_EQ(viewer->cameraMode(), CameraMode::Orbit);
  expectSameCamera(viewer->cameraView(), before, "after the refusals");
}

// Tricky: orbit and fly take over from the scene camera's eye and direction (F2, the panel, the
// first gesture), not from where they were before it; setCameraMode(Scene) has no camera to pick.
TEST(SceneCameras, OrbitAndFlyTakeOverFromTheCamerasEye) {
  auto viewer = viewCameraCube();
  ASSERT_TRUE(viewer);
  for (CameraMode mode : {CameraMode::Fly, CameraMode::Orbit}) {
    ASSERT_TRUE(viewer->lookThroughSceneCamera("front").ok());
    viewer->setCameraMode(mode);
    EXPECT_EQ(viewer->cameraMode(), mode);
    const engine::render::CameraView view = viewer->cameraView();
    EXPECT_NEAR(glm::length(view.position - glm::vec3(4.0f, 0.0f, 0.0f)), 0.0f, 1e-4f) << int(mode);
    EXPECT_NEAR(glm::dot(forwardOf(view), glm::vec3(-1.0f, 0.0f, 0.0f)), 1.0f, 1e-5f) << int(mode);
  }
  viewer->setCameraMode(CameraMode::Scene);
  EXPECT_EQ(viewer->cameraMode(), CameraMode::Orbit);
  ASSERT_TRUE(viewer->lookThroughSceneCamera("front").ok());
  viewer->setOrbitView(3);
  EXPECT_EQ(viewer->cameraMode(), CameraMode::Orbit) << "a fixed orbit view leaves the scene camera";
}

// Tricky: the camera is read from its node every frame, so a scene that moves the node (here its
// parent) is followed; a node destroyed under it falls back to the orbit camera instead of
// reading a dead entity.
TEST(SceneCameras, FollowTheirNodeAndSurviveItsRemoval) {
  auto viewer = viewCameraCube();
  ASSERT_TRUE(viewer);
  ASSERT_TRUE(viewer->lookThroughSceneCamera("front").ok());
  const engine::ecs::Entity rig = named(*viewer, "rig");
  ASSERT_TRUE(viewer->registry().valid(rig));
  viewer->registry().get<engine::scene::Transform>(rig).rotation =
      glm::angleAxis(3.14159265f, glm::vec3(0.0f, 1.0f, 0.0f));
  (void)frame(*viewer);
  const engine::render::CameraView moved = viewer->cameraView();
  EXPECT_NEAR(glm::length(moved.position - glm::vec3(0.0f, 0.0f, -4.0f)), 0.0f, 1e-4f);
  EXPECT_NEAR(glm::dot(forwardOf(moved), glm::vec3(0.0f, 0.0f, 1.0f)), 1.0f, 1e-5f);
  EXPECT_GT(covered(frame(*viewer)), kWidth * kHeight / 20) << "the moved camera still looks at the cube";

  viewer->setCamera({0.0, 3.0, 3.0}, {0.0, 0.0, 0.0});
  const engine::render::CameraView orbit = viewer->cameraView();
  ASSERT_TRUE(viewer->lookThroughSceneCamera("front").ok());
  ASSERT_TRUE(viewer->registry().destroy(named(*viewer, "front")));
  expectSameCamera(viewer->cameraView(), orbit, "the camera's node destroyed");
  EXPECT_GT(covered(frame(*viewer)), 0u);
}

}  // namespace
}  // namespace samples
