// What the render features derive from an object's world matrix on the CPU: whether it can be
// drawn, whether it mirrors, and how far the near plane reaches in its units.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/render/camera_view.h"
#include "engine/render/gpu_scene.h"

namespace engine::render {
namespace {

const glm::mat4 kTurn = glm::rotate(glm::mat4(1.0f), 0.8f, glm::normalize(glm::vec3(1.0f, 0.4f, -0.3f)));

glm::mat4 scaled(const glm::vec3& s) { return glm::scale(glm::mat4(1.0f), s); }

// Tricky: the sign of the determinant, not of any single scale, decides mirroring (two negative
// scales are a rotation by 180 degrees), and rotations or translations never mirror.
TEST(ObjectTransform, MirrorsExactlyWhenTheDeterminantIsNegative) {
  EXPECT_TRUE(mirrors(scaled({-1.0f, 1.0f, 1.0f})));
  EXPECT_TRUE(mirrors(kTurn * scaled({1.0f, 2.5f, -0.4f})));
  EXPECT_TRUE(mirrors(scaled({-1.0f, -1.0f, -1.0f})));
  EXPECT_FALSE(mirrors(scaled({-1.0f, -1.0f, 1.0f})));
  EXPECT_FALSE(mirrors(glm::translate(kTurn, glm::vec3(-5.0f))));
  EXPECT_FALSE(mirrors(glm::mat4(1.0f)));
}

// Tricky: a zero scale (a common way to hide an animated node), a NaN from a broken animation and
// a projective matrix must be refused before their inverse reaches a shader; small but valid
// scales must still be drawn.
TEST(ObjectTransform, DrawableOnlyWhenFiniteAffineAndInvertible) {
  EXPECT_TRUE(drawableTransform(glm::mat4(1.0f)));
  EXPECT_TRUE(drawableTransform(kTurn * scaled({1e-3f, 2.5f, -0.4f})));
  EXPECT_FALSE(drawableTransform(scaled({1.0f, 0.0f, 1.0f})));
  EXPECT_FALSE(drawableTransform(scaled(glm::vec3(0.0f))));
  EXPECT_FALSE(drawableTransform(scaled({1e-20f, 1e-20f, 1e-20f})));  // the float inverse overflows
  glm::mat4 nan(1.0f);
  nan[3][1] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(drawableTransform(nan));
  glm::mat4 projective(1.0f);
  projective[2][3] = -1.0f;
  EXPECT_FALSE(drawableTransform(projective));
}

// Tricky: for a scale applied after a rotation (a parent scaled non-uniformly, a rotated child)
// the columns of the matrix are not its singular values, so the shortest column overestimates how
// much the object shrinks a world length; the bound must hold for every point of the near plane's
// rectangle whatever the model (mirroring, shear) and the camera (10 and 150 degrees, thin images).
TEST(ObjectTransform, NearPlaneReachInObjectBoundsEveryNearPlanePoint) {
  const std::vector<glm::mat4> models = {
      glm::mat4(1.0f),
      scaled(glm::vec3(0.25f)),
      glm::translate(glm::mat4(1.0f), glm::vec3(3.0f, -1.0f, 2.0f)) * kTurn * scaled({1.0f, 2.5f, 0.4f}),
      scaled({0.5f, -1.6f, 1.0f}) * kTurn,
      scaled({0.1f, 1.0f, 1.0f}) * kTurn * scaled({1.0f, 10.0f, 1.0f}) * glm::inverse(kTurn),
  };
  const float kDegree = 3.14159265f / 180.0f;
  const std::vector<CameraView> cameras = {
      CameraView::lookAt({1.0f, 2.0f, 3.0f}, glm::vec3(0.0f), 10.0f * kDegree, 0.05f, 1.0f),
      CameraView::lookAt({1.0f, 2.0f, 3.0f}, glm::vec3(0.0f), 150.0f * kDegree, 0.05f, 1.0f),
      CameraView::lookAt({-2.0f, 0.5f, 1.0f}, glm::vec3(0.0f), 0.9f, 0.3f, 7.0f / 300.0f),
      CameraView::lookAt({-2.0f, 0.5f, 1.0f}, glm::vec3(0.0f), 0.02f, 0.3f, 300.0f / 7.0f),
  };
  for (std::size_t m = 0; m < models.size(); ++m) {
    const glm::dmat4 inverseModel = glm::inverse(glm::dmat4(models[m]));
    for (std::size_t c = 0; c < cameras.size(); ++c) {
      SCOPED_TRACE("model " + std::to_string(m) + ", camera " + std::to_string(c));
      const CameraView& camera = cameras[c];
      const double reach = camera.nearPlaneReachInObject(glm::inverse(models[m]));
      const glm::dmat4 clipToWorld = glm::inverse(glm::dmat4(camera.proj) * glm::dmat4(camera.view));
      const glm::dvec3 eye = glm::dvec3(inverseModel * glm::dvec4(glm::dvec3(camera.position), 1.0));
      double farthest = 0.0;
      for (int i = 0; i <= 8; ++i)
        for (int j = 0; j <= 8; ++j) {
          const glm::dvec4 clip(-1.0 + 0.25 * i, -1.0 + 0.25 * j, 1.0, 1.0);  // depth 1: the near plane
          const glm::dvec4 world = clipToWorld * clip;
          const glm::dvec3 object = glm::dvec3(inverseModel * (world / world.w));
          farthest = std::max(farthest, glm::length(object - eye));
        }
      EXPECT_LE(farthest, reach);
    }
  }
}

}  // namespace
}  // namespace engine::render
