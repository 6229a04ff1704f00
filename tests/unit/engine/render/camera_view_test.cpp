// CameraView::fromWorld (engine/render/camera_view.h): a camera placed by a node's world matrix, as
// glTF camera nodes are. Each case says what a mistake would break.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/render/camera_view.h"

namespace engine::render {
namespace {

const glm::mat4 kTurn = glm::rotate(glm::mat4(1.0f), 0.8f, glm::normalize(glm::vec3(1.0f, 0.4f, -0.3f)));
const glm::vec3 kEye(1.0f, -2.0f, 3.0f);

glm::mat4 placed(const glm::mat4& linear) { return glm::translate(glm::mat4(1.0f), kEye) * linear; }

// Where a world point lands in normalized device coordinates.
glm::vec3 project(const CameraView& camera, const glm::vec3& p) {
  const glm::vec4 clip = camera.proj * camera.view * glm::vec4(p, 1.0f);
  return glm::vec3(clip) / clip.w;
}

// Tricky: a camera under a scaled parent (non-uniform, or a Y axis sheared along Z) must see the
// scene as the unscaled camera does: a scale left in the view would squash the image. Points ahead
// of the camera must project to the same place in both.
TEST(CameraFromWorld, DropsScaleAndShear) {
  const Expected<CameraView> plain = CameraView::fromWorld(placed(kTurn), 0.9f, 0.1f, 1.5f);
  ASSERT_TRUE(plain.ok()) << plain.error().message;
  glm::mat4 shear(1.0f);
  shear[1][2] = 0.3f;  // the Y axis leans along Z: no longer perpendicular to the view direction
  for (const glm::mat4& distort : {glm::scale(glm::mat4(1.0f), glm::vec3(3.0f, 0.5f, 2.0f)), shear}) {
    const Expected<CameraView> scaled = CameraView::fromWorld(placed(kTurn * distort), 0.9f, 0.1f, 1.5f);
    ASSERT_TRUE(scaled.ok()) << scaled.error().message;
    EXPECT_NEAR(glm::length(scaled->position - kEye), 0.0f, 1e-5f);
    for (const glm::vec3& local : {glm::vec3(0.0f, 0.0f, -4.0f), glm::vec3(1.0f, 0.5f, -3.0f), glm::vec3(-2.0f, 1.0f, -7.0f)}) {
      const glm::vec3 world = kEye + glm::vec3(kTurn * glm::vec4(local, 0.0f));
      EXPECT_NEAR(glm::length(project(*scaled, world) - project(*plain, world)), 0.0f, 1e-5f);
    }
  }
  // The unscaled camera looks down its -Z: a point ahead lands in the middle of the image.
  const glm::vec3 ahead = kEye + glm::vec3(kTurn * glm::vec4(0.0f, 0.0f, -5.0f, 0.0f));
  EXPECT_NEAR(project(*plain, ahead).x, 0.0f, 1e-5f);
  EXPECT_NEAR(project(*plain, ahead).y, 0.0f, 1e-5f);
}

// Tricky: glTF 2.0 ("Cameras", "View Matrix"): "The view matrix is derived from the global transform of
// the node containing the camera with the scaling ignored", and the projection (znear, zfar, ymag)
// maps that view space, in the scene's global units, to clip space. So a camera node under a root
// scaled by 0.01 (a centimetre export) keeps its znear in global units: scaling it by the node's
// scale would move the near plane 100 times closer. Reverse-Z depth at distance d ahead is znear / d.
TEST(CameraFromWorld, ZnearIsInGlobalUnitsWhateverTheNodesScale) {
  const float znear = 0.1f;
  const Expected<CameraView> camera =
      CameraView::fromWorld(placed(kTurn * glm::scale(glm::mat4(1.0f), glm::vec3(0.01f))), 0.9f, znear, 1.0f);
  ASSERT_TRUE(camera.ok()) << camera.error().message;
  EXPECT_FLOAT_EQ(camera->znear, znear);
  for (const float distance : {0.08f, 0.2f, 5.0f}) {  // global units along the view direction
    const glm::vec3 ahead = kEye + glm::vec3(kTurn * glm::vec4(0.0f, 0.0f, -distance, 0.0f));
    EXPECT_NEAR(project(*camera, ahead).z, znear / distance, 1e-5f) << "at " << distance << " ahead";
  }
}

// Tricky: a camera under a parent scaled to micrometres is a valid camera (the axes are compared
// with their own lengths, not with an absolute epsilon).
TEST(CameraFromWorld, TinyScaleIsStillACamera) {
  EXPECT_TRUE(CameraView::fromWorld(placed(kTurn * glm::scale(glm::mat4(1.0f), glm::vec3(1e-6f))), 0.9f, 0.1f, 1.0f).ok());
}

// Tricky: each of these would make a projection of NaNs or a view that is not a camera; the error
// must say which (a glTF file's camera is checked when it is picked, not when the frame is black).
TEST(CameraFromWorld, WhatCannotMakeACameraIsNamed) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  glm::mat4 notFinite = placed(kTurn);
  notFinite[3][1] = nan;
  glm::mat4 parallel = placed(kTurn);
  parallel[1] = parallel[2];
  struct Case {
    glm::mat4 world;
    float fovY, znear, aspect;
    const char* expected;
  };
  const Case cases[] = {
      {notFinite, 0.9f, 0.1f, 1.0f, "world matrix is not finite"},
      {placed(glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 1.0f, 0.0f))), 0.9f, 0.1f, 1.0f, "Z axis has zero length"},
      {placed(glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 0.0f, 1.0f))), 0.9f, 0.1f, 1.0f, "Y axis has zero length"},
      {parallel, 0.9f, 0.1f, 1.0f, "parallel to its Z axis"},
      {placed(kTurn), 0.0f, 0.1f, 1.0f, "vertical field of view 0 rad is not between 0 and pi"},
      {placed(kTurn), 3.2f, 0.1f, 1.0f, "vertical field of view 3.2 rad"},
      {placed(kTurn), nan, 0.1f, 1.0f, "vertical field of view nan"},
      {placed(kTurn), 0.9f, 0.0f, 1.0f, "znear 0 is not positive"},
      {placed(kTurn), 0.9f, std::numeric_limits<float>::infinity(), 1.0f, "znear inf"},
      {placed(kTurn), 0.9f, 0.1f, -1.0f, "aspect ratio -1 is not positive"},
  };
  for (const Case& c : cases) {
    const Expected<CameraView> made = CameraView::fromWorld(c.world, c.fovY, c.znear, c.aspect);
    ASSERT_FALSE(made.ok()) << c.expected;
    EXPECT_NE(made.error().message.find(c.expected), std::string::npos) << made.error().message;
  }
}

Camera orthographicCamera(float ymag, float znear, float zfar) {
  Camera camera;
  camera.projection = Projection::kOrthographic;
  camera.xmag = 7.0f;  // never read: the image's aspect makes the width
  camera.ymag = ymag;
  camera.znear = znear;
  camera.zfar = zfar;
  return camera;
}

// Tricky: an orthographic camera has no eye, so points must project by their offset across the view
// alone, whatever their distance: a point ymag above the axis lands on the top edge (NDC y = -1,
// Vulkan's top) at every depth, and one ymag * aspect to the right on the right edge (the image's
// aspect wins over xmag). A perspective matrix left in place would pull them towards the centre.
TEST(CameraOrthographic, KnownPointsLandOnTheEdgesAtEveryDistance) {
  const float aspect = 1.6f;
  const Expected<CameraView> camera = CameraView::fromWorld(placed(kTurn), orthographicCamera(2.5f, 0.5f, 40.0f), aspect);
  ASSERT_TRUE(camera.ok()) << camera.error().message;
  EXPECT_TRUE(camera->orthographic());
  for (const float distance : {0.6f, 5.0f, 39.0f}) {
    const auto at = [&](const glm::vec3& local) { return kEye + glm::vec3(kTurn * glm::vec4(local, 0.0f)); };
    const glm::vec3 top = project(*camera, at({0.0f, 2.5f, -distance}));
    EXPECT_NEAR(top.x, 0.0f, 1e-5f);
    EXPECT_NEAR(top.y, -1.0f, 1e-5f) << "at distance " << distance;
    const glm::vec3 right = project(*camera, at({2.5f * aspect, 0.0f, -distance}));
    EXPECT_NEAR(right.x, 1.0f, 1e-5f) << "at distance " << distance;
    EXPECT_NEAR(right.y, 0.0f, 1e-5f);
    // A pixel spans the same world length at every distance.
    EXPECT_FLOAT_EQ(camera->worldPerPixel(distance, 500), 2.0f * 2.5f / 500.0f);
  }
}

// Tricky: reverse-Z with a finite far plane: depth must be 1 at znear, 0 at zfar and fall linearly
// between (not as 1 / distance), so that nearer points win a GREATER depth test.
TEST(CameraOrthographic, ReverseZDepthIsLinearBetweenNearAndFar) {
  const Expected<CameraView> camera = CameraView::fromWorld(placed(kTurn), orthographicCamera(1.0f, 2.0f, 12.0f), 1.0f);
  ASSERT_TRUE(camera.ok()) << camera.error().message;
  const auto depthAt = [&](float distance) {
    return project(*camera, kEye + glm::vec3(kTurn * glm::vec4(0.3f, -0.2f, -distance, 0.0f))).z;
  };
  EXPECT_NEAR(depthAt(2.0f), 1.0f, 1e-6f);
  EXPECT_NEAR(depthAt(12.0f), 0.0f, 1e-6f);
  EXPECT_NEAR(depthAt(7.0f), 0.5f, 1e-6f);
  EXPECT_GT(depthAt(3.0f), depthAt(3.5f)) << "a nearer point must have the greater depth";
  EXPECT_NEAR(camera->viewDistance(kEye + glm::vec3(kTurn * glm::vec4(1.0f, 1.0f, -4.0f, 0.0f))), 4.0f, 1e-5f);
}

// Tricky: the homogeneous eye the shaders get must be a direction (w = 0) pointing from the scene
// to the viewer for an orthographic camera, and the eye point (w = 1) for a perspective one; the
// near plane's reach must cover the orthographic view's corners at znear, which are far from the
// camera's point even for znear = 0 (a perspective formula, znear * (...), would give 0).
TEST(CameraOrthographic, HomogeneousEyeAndNearPlaneReach) {
  const Expected<CameraView> ortho = CameraView::fromWorld(placed(kTurn), orthographicCamera(3.0f, 0.0f, 10.0f), 2.0f);
  ASSERT_TRUE(ortho.ok()) << ortho.error().message;
  const glm::vec3 back = glm::vec3(kTurn * glm::vec4(0.0f, 0.0f, 1.0f, 0.0f));
  EXPECT_EQ(ortho->eye().w, 0.0f);
  EXPECT_NEAR(glm::length(glm::vec3(ortho->eye()) - back), 0.0f, 1e-5f);
  EXPECT_NEAR(ortho->nearPlaneReach(), std::sqrt(9.0f + 36.0f) * 1.01f, 1e-4f);
  const Expected<CameraView> perspective = CameraView::fromWorld(placed(kTurn), 0.9f, 0.1f, 2.0f);
  ASSERT_TRUE(perspective.ok());
  EXPECT_EQ(perspective->eye(), glm::vec4(kEye, 1.0f));
}

// Tricky: each of these would make a degenerate orthographic projection (no height, a depth range
// that is empty or reversed, a view of infinite width); the error must name the field.
TEST(CameraOrthographic, WhatCannotMakeAnOrthographicCameraIsNamed) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  struct Case {
    Camera camera;
    float aspect;
    const char* expected;
  };
  const Case cases[] = {
      {orthographicCamera(0.0f, 0.1f, 10.0f), 1.0f, "ymag 0 is not positive"},
      {orthographicCamera(-1.0f, 0.1f, 10.0f), 1.0f, "ymag -1 is not positive"},
      {orthographicCamera(nan, 0.1f, 10.0f), 1.0f, "ymag nan"},
      {orthographicCamera(1.0f, -0.1f, 10.0f), 1.0f, "znear -0.1 is negative"},
      {orthographicCamera(1.0f, 5.0f, 5.0f), 1.0f, "zfar 5 is not beyond znear 5"},
      {orthographicCamera(1.0f, 0.1f, 0.0f), 1.0f, "zfar 0 is not beyond znear"},
      {orthographicCamera(1.0f, 0.1f, std::numeric_limits<float>::infinity()), 1.0f, "zfar inf"},
      {orthographicCamera(1.0f, 0.1f, 10.0f), 0.0f, "aspect ratio 0 is not positive"},
      {orthographicCamera(3e38f, 0.1f, 10.0f), 1e3f, "width is not finite"},
  };
  for (const Case& c : cases) {
    const Expected<CameraView> made = CameraView::fromWorld(placed(kTurn), c.camera, c.aspect);
    ASSERT_FALSE(made.ok()) << c.expected;
    EXPECT_NE(made.error().message.find(c.expected), std::string::npos) << made.error().message;
  }
}

}  // namespace
}  // namespace engine::render
