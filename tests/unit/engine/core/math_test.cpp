// Camera maths: the reverse-Z infinite projection, pixel rays and frustum culling must agree with
// what Vulkan does with proj * view (viewport transform written out here, independently).
#include "engine/core/math.h"

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

namespace engine::math {
namespace {

constexpr float kFovy = 0.9f;
constexpr float kZnear = 0.1f;
const glm::ivec2 kImage(320, 180);

struct Projected {
  glm::dvec2 pixel;  // framebuffer coordinates, (0,0) = top-left corner
  double depth;
  double w;
};

// What the GPU does: clip = viewProj * p, divide by w, then the Vulkan viewport transform for a
// viewport (0, 0, width, height, minDepth 0, maxDepth 1).
Projected project(const glm::mat4& viewProj, const glm::vec3& p, glm::ivec2 image) {
  const glm::vec4 clip = viewProj * glm::vec4(p, 1.0f);
  const glm::dvec3 ndc = glm::dvec3(clip) / static_cast<double>(clip.w);
  return {glm::dvec2((ndc.x + 1.0) * 0.5 * image.x, (ndc.y + 1.0) * 0.5 * image.y), ndc.z, static_cast<double>(clip.w)};
}

glm::mat4 testProjection() { return perspectiveReverseZInfinite(kFovy, float(kImage.x) / float(kImage.y), kZnear); }

// Tricky: with reverse-Z the near plane is depth 1 (not 0), and depth must shrink towards 0 with
// distance without ever reaching the far clip (infinite projection).
TEST(Projection, NearPlaneIsDepthOneAndDepthFallsWithDistance) {
  const glm::mat4 proj = testProjection();
  EXPECT_NEAR(project(proj, glm::vec3(0.0f, 0.0f, -kZnear), kImage).depth, 1.0, 1e-6);
  double previous = 2.0;
  for (float distance : {0.2f, 1.0f, 10.0f, 1000.0f, 1e6f, 1e20f}) {
    const Projected p = project(proj, glm::vec3(0.0f, 0.0f, -distance), kImage);
    EXPECT_GT(p.w, 0.0);
    EXPECT_LT(p.depth, previous) << distance;
    EXPECT_GT(p.depth, 0.0) << "still in front of the (absent) far plane at " << distance;
    previous = p.depth;
  }
  EXPECT_LT(previous, 1e-20);
  EXPECT_GT(project(proj, glm::vec3(0.0f, 0.0f, -0.05f), kImage).depth, 1.0) << "closer than near: clipped";
}

// Tricky: depth follows the distance along the view axis, not along the ray; an off-axis point shows
// the difference.
TEST(Projection, DepthIsZnearOverAxisDistance) {
  const glm::mat4 proj = testProjection();
  const glm::vec3 offAxis(3.0f, -2.0f, -7.0f);
  const double depth = project(proj, offAxis, kImage).depth;
  EXPECT_NEAR(depth, double(kZnear) / 7.0, 1e-8);
  EXPECT_NEAR(depthToViewDistance(depth, double(kZnear)), 7.0, 1e-5);
  EXPECT_NEAR(viewDistanceToDepth(7.0, double(kZnear)), depth, 1e-8);
}

// Tricky: Vulkan's NDC y points down, so without the flip in the projection the image is upside
// down; and a right-handed camera must keep world +X on the right.
TEST(Projection, WorldUpIsAtTheTopAndRightIsRight) {
  const glm::mat4 view = lookAt(glm::vec3(0.0f, 0.0f, 5.0f), glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
  const glm::mat4 viewProj = testProjection() * view;
  const Projected centre = project(viewProj, glm::vec3(0.0f), kImage);
  EXPECT_NEAR(centre.pixel.x, kImage.x / 2.0, 1e-4);
  EXPECT_NEAR(centre.pixel.y, kImage.y / 2.0, 1e-4);
  EXPECT_LT(project(viewProj, glm::vec3(0.0f, 1.0f, 0.0f), kImage).pixel.y, kImage.y / 2.0);
  EXPECT_GT(project(viewProj, glm::vec3(1.0f, 0.0f, 0.0f), kImage).pixel.x, kImage.x / 2.0);
  // And the same from the ray side: the top-left pixel looks up and to the left.
  const Ray topLeft = pixelRay(view, testProjection(), glm::vec2(0.5f, 0.5f), kImage);
  EXPECT_LT(topLeft.direction.x, 0.0);
  EXPECT_GT(topLeft.direction.y, 0.0);
  EXPECT_LT(topLeft.direction.z, 0.0);
}

// Tricky: an independent closed form for the pixel-centre ray of a camera at the origin looking down
// -Z: catches half-pixel offsets, a swapped aspect ratio and a wrong y direction.
TEST(PixelRay, MatchesClosedFormForCanonicalCamera) {
  const glm::mat4 proj = testProjection();
  const double aspect = double(kImage.x) / double(kImage.y);
  const double tanHalf = std::tan(0.5 * double(kFovy));
  for (const glm::ivec2 pixel : {glm::ivec2(0, 0), glm::ivec2(319, 179), glm::ivec2(17, 150), glm::ivec2(160, 90)}) {
    const glm::vec2 centre = glm::vec2(pixel) + 0.5f;
    const Ray ray = pixelRay(glm::mat4(1.0f), proj, centre, kImage);
    const double ndcX = 2.0 * double(centre.x) / kImage.x - 1.0;
    const double ndcY = 2.0 * double(centre.y) / kImage.y - 1.0;
    const glm::dvec3 expected = glm::normalize(glm::dvec3(ndcX * aspect * tanHalf, -ndcY * tanHalf, -1.0));
    EXPECT_NEAR(ray.direction.x, expected.x, 1e-6) << pixel.x << "," << pixel.y;
    EXPECT_NEAR(ray.direction.y, expected.y, 1e-6) << pixel.x << "," << pixel.y;
    EXPECT_NEAR(ray.direction.z, expected.z, 1e-6) << pixel.x << "," << pixel.y;
    EXPECT_NEAR(glm::length(ray.direction), 1.0, 1e-12);
    EXPECT_NEAR(glm::length(ray.origin), 0.0, 1e-12);
  }
}

// Tricky: round trip through an arbitrary camera pose: points projected by proj * view (GPU path)
// must lie on the pixel ray of the pixel they land on (CPU path) at the distance the depth encodes.
TEST(PixelRay, RoundTripsWithProjectionForArbitraryCamera) {
  const glm::vec3 target(1.0f, -2.0f, 0.5f);
  const glm::vec3 eye = orbitEye(target, 6.0f, 0.7f, 0.4f);
  const glm::mat4 view = lookAt(eye, target, glm::vec3(0.0f, 1.0f, 0.0f));
  const glm::mat4 proj = testProjection();
  const glm::mat4 viewProj = proj * view;
  std::mt19937 random(7);
  std::uniform_real_distribution<float> coordinate(-3.0f, 3.0f);
  int checked = 0;
  for (int i = 0; i < 200; ++i) {
    const glm::vec3 point = target + glm::vec3(coordinate(random), coordinate(random), coordinate(random));
    const Projected p = project(viewProj, point, kImage);
    if (p.w <= double(kZnear)) continue;  // behind or too close to the eye
    ++checked;
    const Ray ray = pixelRay(view, proj, glm::vec2(p.pixel), kImage);
    EXPECT_NEAR(glm::distance(ray.origin, glm::dvec3(eye)), 0.0, 1e-5);
    EXPECT_NEAR(glm::distance(ray.direction, glm::normalize(glm::dvec3(point) - ray.origin)), 0.0, 1e-5);

    const double viewDistance = depthToViewDistance(p.depth, double(kZnear));
    EXPECT_NEAR(viewDistance, -static_cast<double>((view * glm::vec4(point, 1.0f)).z), 1e-4 * viewDistance);
    const glm::dvec3 forward = glm::normalize(glm::dvec3(target - eye));
    const glm::dvec3 reconstructed = ray.origin + ray.direction * (viewDistance / glm::dot(ray.direction, forward));
    EXPECT_NEAR(glm::distance(reconstructed, glm::dvec3(point)), 0.0, 1e-4) << i;
  }
  EXPECT_GT(checked, 100);
}

// Tricky: the reference images start their rays here; a point off the near plane (depth != 1), off
// the pixel's ray or at another pixel would shift every depth the GPU tests compare, or show the
// clipped front of a surface the near plane cuts.
TEST(PixelRay, FromNearPlaneStartsOnThePixelsRayAtDepthOne) {
  const glm::vec3 target(1.0f, -2.0f, 0.5f);
  const glm::vec3 eye = orbitEye(target, 6.0f, 0.7f, 0.4f);
  const glm::mat4 view = lookAt(eye, target, glm::vec3(0.0f, 1.0f, 0.0f));
  const glm::mat4 proj = testProjection();
  for (const glm::vec2 pixel : {glm::vec2(0.5f, 0.5f), glm::vec2(160.5f, 90.5f), glm::vec2(319.5f, 12.5f)}) {
    const Ray fromEye = pixelRay(view, proj, pixel, kImage);
    const Ray fromNear = pixelRayFromNearPlane(view, proj, pixel, kImage);
    EXPECT_NEAR(glm::distance(fromNear.direction, fromEye.direction), 0.0, 1e-12);
    const glm::dvec3 offset = fromNear.origin - fromEye.origin;
    EXPECT_NEAR(glm::length(glm::cross(offset, fromEye.direction)), 0.0, 1e-6) << "on the pixel's ray";
    EXPECT_GT(glm::dot(offset, fromEye.direction), 0.0) << "in front of the eye";
    const Projected p = project(proj * view, glm::vec3(fromNear.origin), kImage);
    EXPECT_NEAR(p.depth, 1.0, 1e-5);
    EXPECT_NEAR(p.pixel.x, double(pixel.x), 1e-3);
    EXPECT_NEAR(p.pixel.y, double(pixel.y), 1e-3);
  }
}

TEST(DepthConversion, EdgesAndRoundTrip) {
  EXPECT_EQ(depthToViewDistance(1.0, 0.25), 0.25);
  EXPECT_EQ(viewDistanceToDepth(0.25, 0.25), 1.0);
  EXPECT_EQ(depthToViewDistance(0.0, 0.25), std::numeric_limits<double>::infinity()) << "cleared depth = sky";
  EXPECT_EQ(viewDistanceToDepth(std::numeric_limits<double>::infinity(), 0.25), 0.0);
  for (double distance : {0.3, 1.0, 17.5, 1e5}) {
    EXPECT_NEAR(depthToViewDistance(viewDistanceToDepth(distance, 0.25), 0.25), distance, 1e-12 * distance);
  }
  EXPECT_THROW(viewDistanceToDepth(-1.0, 0.25), std::invalid_argument);
  EXPECT_THROW(depthToViewDistance(0.5, 0.0), std::invalid_argument);
}

TEST(Projection, RejectsParametersThatDescribeNoCamera) {
  EXPECT_THROW(perspectiveReverseZInfinite(0.0f, 1.0f, 0.1f), std::invalid_argument);
  EXPECT_THROW(perspectiveReverseZInfinite(3.2f, 1.0f, 0.1f), std::invalid_argument);
  EXPECT_THROW(perspectiveReverseZInfinite(1.0f, 0.0f, 0.1f), std::invalid_argument);
  EXPECT_THROW(perspectiveReverseZInfinite(1.0f, 1.0f, 0.0f), std::invalid_argument);
  EXPECT_THROW(perspectiveReverseZInfinite(1.0f, 1.0f, std::nanf("")), std::invalid_argument);
  EXPECT_THROW(pixelRay(glm::mat4(1.0f), testProjection(), glm::vec2(0.5f), glm::ivec2(0, 10)), std::invalid_argument);
  EXPECT_THROW(lookAt(glm::vec3(1.0f), glm::vec3(1.0f), glm::vec3(0.0f, 1.0f, 0.0f)), std::invalid_argument);
}

// Tricky: a camera straight above (or below) its target looks exactly along its up vector, where a
// plain lookAt divides by a zero cross product and yields NaNs.
TEST(LookAt, LookingAlongUpStillGivesAValidView) {
  for (const glm::vec3 eye : {glm::vec3(0.0f, 4.0f, 0.0f), glm::vec3(0.0f, -4.0f, 0.0f)}) {
    const glm::mat4 view = lookAt(eye, glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) ASSERT_TRUE(std::isfinite(view[c][r])) << eye.y;
    }
    const glm::vec3 targetInView = glm::vec3(view * glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    EXPECT_NEAR(targetInView.x, 0.0f, 1e-5f);
    EXPECT_NEAR(targetInView.y, 0.0f, 1e-5f);
    EXPECT_NEAR(targetInView.z, -4.0f, 1e-5f) << "the target lies straight ahead (-Z)";
  }
}

TEST(OrbitEye, FollowsTheDocumentedAngles) {
  const glm::vec3 target(1.0f, 2.0f, 3.0f);
  const auto near = [](glm::vec3 a, glm::vec3 b) { return glm::distance(a, b) < 1e-5f; };
  EXPECT_TRUE(near(orbitEye(target, 2.0f, 0.0f, 0.0f), target + glm::vec3(0.0f, 0.0f, 2.0f)));
  EXPECT_TRUE(near(orbitEye(target, 2.0f, 1.57079632679f, 0.0f), target + glm::vec3(2.0f, 0.0f, 0.0f)));
  EXPECT_TRUE(near(orbitEye(target, 2.0f, 0.0f, 1.57079632679f), target + glm::vec3(0.0f, 2.0f, 0.0f)));
  EXPECT_NEAR(glm::distance(orbitEye(target, 2.0f, 2.1f, -0.7f), target), 2.0f, 1e-5f);
}

class FrustumTest : public ::testing::Test {
 protected:
  // Camera at (0,0,5) looking at the origin.
  glm::mat4 view_ = lookAt(glm::vec3(0.0f, 0.0f, 5.0f), glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
  glm::mat4 viewProj_ = testProjection() * view_;
  Frustum frustum_ = extractFrustum(viewProj_);

  bool box(glm::vec3 centre, float halfSize) const {
    return intersects(frustum_, centre - glm::vec3(halfSize), centre + glm::vec3(halfSize));
  }
};

// Tricky: behind the camera the perspective divide mirrors points back into NDC range, so a naive
// projected-bounds test would keep these boxes; and the far plane is infinite, so a box a million
// units ahead must be kept.
TEST_F(FrustumTest, CullsBehindAndBesideKeepsAheadAndStraddling) {
  EXPECT_TRUE(box(glm::vec3(0.0f), 0.5f));
  EXPECT_TRUE(box(glm::vec3(0.0f, 0.0f, -1e6f), 1.0f)) << "no far plane";
  EXPECT_FALSE(box(glm::vec3(0.0f, 0.0f, 20.0f), 1.0f)) << "behind the eye";
  EXPECT_FALSE(box(glm::vec3(40.0f, 0.0f, 0.0f), 1.0f)) << "right of the view";
  EXPECT_FALSE(box(glm::vec3(-40.0f, 0.0f, 0.0f), 1.0f)) << "left";
  EXPECT_FALSE(box(glm::vec3(0.0f, 40.0f, 0.0f), 1.0f)) << "above";
  EXPECT_FALSE(box(glm::vec3(0.0f, -40.0f, 0.0f), 1.0f)) << "below";
  EXPECT_TRUE(box(glm::vec3(0.0f, 0.0f, 5.0f), 1.0f)) << "box around the eye straddles the near plane";
  EXPECT_TRUE(box(glm::vec3(40.0f, 0.0f, 0.0f), 39.5f)) << "big box reaching into the view";
  EXPECT_FALSE(box(glm::vec3(0.0f, 0.0f, 4.95f), 0.01f)) << "between eye and near plane";
  // Plane naming follows the image: the point above the view is outside the top plane.
  const glm::vec4 top = frustum_.planes[Frustum::kTop];
  EXPECT_LT(glm::dot(glm::vec3(top), glm::vec3(0.0f, 40.0f, 0.0f)) + top.w, 0.0f);
  EXPECT_GT(glm::dot(glm::vec3(top), glm::vec3(0.0f, -40.0f, 0.0f)) + top.w, 0.0f);
}

// Tricky: property check against the projection itself: a point is inside every plane exactly when
// it projects in front of the near plane and inside the image.
TEST_F(FrustumTest, AgreesWithProjectionOnRandomPoints) {
  std::mt19937 random(99);
  std::uniform_real_distribution<float> coordinate(-10.0f, 10.0f);
  int inside = 0;
  int outside = 0;
  for (int i = 0; i < 5000; ++i) {
    const glm::vec3 p(coordinate(random), coordinate(random), coordinate(random));
    const Projected projected = project(viewProj_, p, kImage);
    const bool visible = projected.w > 0.0 && projected.depth <= 1.0 && projected.pixel.x >= 0.0 &&
                         projected.pixel.x <= kImage.x && projected.pixel.y >= 0.0 && projected.pixel.y <= kImage.y;
    // Skip points within a hair of a boundary, where float rounding may go either way.
    float margin = std::numeric_limits<float>::max();
    for (const glm::vec4& plane : frustum_.planes) margin = std::min(margin, std::abs(glm::dot(glm::vec3(plane), p) + plane.w));
    if (margin < 1e-3f) continue;
    EXPECT_EQ(intersects(frustum_, p, p), visible) << p.x << " " << p.y << " " << p.z;
    (visible ? inside : outside)++;
  }
  EXPECT_GT(inside, 100);
  EXPECT_GT(outside, 100);
}

// An orthographic camera at (0,0,5) looking at the origin: a view 4 units tall, depth range [1, 9].
constexpr float kOrthoHalfHeight = 2.0f;
glm::mat4 orthoProjection() {
  return orthographicReverseZ(kOrthoHalfHeight * float(kImage.x) / float(kImage.y), kOrthoHalfHeight, 1.0f, 9.0f);
}
const glm::mat4 kOrthoView = lookAt(glm::vec3(0.0f, 0.0f, 5.0f), glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f));

// Tricky: orthographic rays have no common eye: each must run parallel to the view axis from the
// camera's plane (view z = 0) beside its pixel, and the near-plane start must still project back
// to its own pixel at depth 1 (the reference images compared with the GPU start there).
TEST(PixelRay, OrthographicRaysAreParallelAndStartBesideTheirPixel) {
  const glm::mat4 view = lookAt(glm::vec3(1.0f, 2.0f, 6.0f), glm::vec3(0.0f, -1.0f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
  const glm::mat4 proj = orthoProjection();
  const glm::dvec3 forward = glm::normalize(glm::dvec3(0.0, -1.0, 0.0) - glm::dvec3(1.0, 2.0, 6.0));
  for (const glm::vec2 pixel : {glm::vec2(0.5f, 0.5f), glm::vec2(160.5f, 90.5f), glm::vec2(319.5f, 12.5f)}) {
    const Ray ray = pixelRay(view, proj, pixel, kImage);
    const Ray fromNear = pixelRayFromNearPlane(view, proj, pixel, kImage);
    EXPECT_NEAR(glm::distance(ray.direction, forward), 0.0, 1e-6) << "parallel to the view axis";
    EXPECT_NEAR(glm::distance(fromNear.direction, forward), 0.0, 1e-6);
    EXPECT_NEAR((glm::dmat4(view) * glm::dvec4(ray.origin, 1.0)).z, 0.0, 1e-5) << "on the camera's plane";
    EXPECT_NEAR(glm::distance(fromNear.origin, ray.origin + 1.0 * ray.direction), 0.0, 1e-5) << "znear = 1 ahead";
    const Projected p = project(proj * view, glm::vec3(fromNear.origin), kImage);
    EXPECT_NEAR(p.depth, 1.0, 1e-5);
    EXPECT_NEAR(p.pixel.x, double(pixel.x), 1e-3);
    EXPECT_NEAR(p.pixel.y, double(pixel.y), 1e-3);
  }
  // The top-left pixel's ray starts up and to the left of the axis, by the view's half extents.
  const glm::dvec3 topLeft = glm::dvec3(kOrthoView * glm::vec4(glm::vec3(pixelRay(kOrthoView, proj, {0.0f, 0.0f}, kImage).origin), 1.0f));
  EXPECT_NEAR(topLeft.x, -double(kOrthoHalfHeight) * double(kImage.x) / double(kImage.y), 1e-5);
  EXPECT_NEAR(topLeft.y, double(kOrthoHalfHeight), 1e-5);
}

// Tricky: depth is linear in view distance for an orthographic projection and 1 / distance for a
// perspective one; the conversion read from the matrix must invert both, and the depth 0 of an
// infinite projection (the sky) is infinitely far.
TEST(DepthConversion, FromAnyProjectionMatrix) {
  const glm::mat4 ortho = orthoProjection();
  for (const double distance : {1.0, 2.5, 9.0}) {
    const glm::vec4 clip = ortho * glm::vec4(0.3f, 0.1f, -float(distance), 1.0f);
    EXPECT_NEAR(depthToViewDistance(ortho, clip.z / clip.w), distance, 1e-5);
  }
  EXPECT_NEAR(depthToViewDistance(ortho, 1.0), 1.0, 1e-6);
  EXPECT_NEAR(depthToViewDistance(ortho, 0.0), 9.0, 1e-5);
  EXPECT_NEAR(depthToViewDistance(testProjection(), 0.5), 2.0 * double(kZnear), 1e-7);
  EXPECT_EQ(depthToViewDistance(testProjection(), 0.0), std::numeric_limits<double>::infinity());
}

// Tricky: an orthographic view is a box: beside it, behind the camera, nearer than znear and beyond
// zfar (a plane a perspective frustum does not have) all cull; the same property check as the
// perspective frustum's, with the far plane in play.
TEST(FrustumOrthographic, CullsOutsideTheBoxIncludingBeyondFar) {
  const Frustum frustum = extractFrustum(orthoProjection() * kOrthoView);
  const auto box = [&](glm::vec3 centre, float half) { return intersects(frustum, centre - glm::vec3(half), centre + glm::vec3(half)); };
  EXPECT_TRUE(box(glm::vec3(0.0f), 0.5f));
  EXPECT_TRUE(box(glm::vec3(3.0f, 1.5f, 0.0f), 0.1f)) << "near the corner, wider than tall";
  EXPECT_FALSE(box(glm::vec3(0.0f, 0.0f, -20.0f), 1.0f)) << "beyond zfar";
  EXPECT_FALSE(box(glm::vec3(0.0f, 0.0f, 4.5f), 0.2f)) << "between the camera and znear";
  EXPECT_FALSE(box(glm::vec3(0.0f, 3.0f, 0.0f), 0.5f)) << "above (a perspective frustum would keep it)";
  std::mt19937 random(7);
  std::uniform_real_distribution<float> coordinate(-10.0f, 10.0f);
  int inside = 0, outside = 0;
  const glm::mat4 viewProj = orthoProjection() * kOrthoView;
  for (int i = 0; i < 5000; ++i) {
    const glm::vec3 p(coordinate(random) * 0.5f, coordinate(random) * 0.3f, coordinate(random));
    const Projected projected = project(viewProj, p, kImage);
    const bool visible = projected.depth >= 0.0 && projected.depth <= 1.0 && projected.pixel.x >= 0.0 &&
                         projected.pixel.x <= kImage.x && projected.pixel.y >= 0.0 && projected.pixel.y <= kImage.y;
    float margin = std::numeric_limits<float>::max();
    for (const glm::vec4& plane : frustum.planes) margin = std::min(margin, std::abs(glm::dot(glm::vec3(plane), p) + plane.w));
    if (margin < 1e-3f) continue;
    EXPECT_EQ(intersects(frustum, p, p), visible) << p.x << " " << p.y << " " << p.z;
    (visible ? inside : outside)++;
  }
  EXPECT_GT(inside, 100);
  EXPECT_GT(outside, 100);
}

// Tricky: a zero or infinite extent, a negative znear or an empty depth range would divide by zero
// or flip the image; each must throw, as a bad perspective does.
TEST(Projection, RejectsOrthographicParametersThatDescribeNoCamera) {
  EXPECT_THROW(orthographicReverseZ(0.0f, 1.0f, 0.1f, 10.0f), std::invalid_argument);
  EXPECT_THROW(orthographicReverseZ(1.0f, -1.0f, 0.1f, 10.0f), std::invalid_argument);
  EXPECT_THROW(orthographicReverseZ(1.0f, std::numeric_limits<float>::infinity(), 0.1f, 10.0f), std::invalid_argument);
  EXPECT_THROW(orthographicReverseZ(1.0f, 1.0f, -0.1f, 10.0f), std::invalid_argument);
  EXPECT_THROW(orthographicReverseZ(1.0f, 1.0f, 10.0f, 10.0f), std::invalid_argument);
  EXPECT_NO_THROW(orthographicReverseZ(1.0f, 1.0f, 0.0f, 10.0f)) << "glTF allows znear = 0";
  EXPECT_TRUE(isOrthographic(orthographicReverseZ(1.0f, 1.0f, 0.0f, 10.0f)));
  EXPECT_FALSE(isOrthographic(testProjection()));
}

}  // namespace
}  // namespace engine::math
