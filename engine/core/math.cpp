#include "engine/core/math.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

namespace engine::math {

glm::mat4 perspectiveReverseZInfinite(float fovyRadians, float aspect, float znear) {
  constexpr float kPi = 3.14159265358979f;
  if (!(fovyRadians > 0.0f && fovyRadians < kPi)) {
    throw std::invalid_argument(fmt::format("perspective: fovy {} rad is outside (0, pi)", fovyRadians));
  }
  if (!(aspect > 0.0f) || !std::isfinite(aspect)) {
    throw std::invalid_argument(fmt::format("perspective: aspect ratio {} is not positive", aspect));
  }
  if (!(znear > 0.0f) || !std::isfinite(znear)) {
    throw std::invalid_argument(fmt::format("perspective: znear {} is not positive", znear));
  }
  const float focal = 1.0f / std::tan(0.5f * fovyRadians);
  // Column-major: clip = (focal/aspect * x, -focal * y, znear, -z), so depth = znear / -z and the
  // negated y puts view-space +Y at the top of the Vulkan image.
  glm::mat4 m(0.0f);
  m[0][0] = focal / aspect;
  m[1][1] = -focal;
  m[2][3] = -1.0f;
  m[3][2] = znear;
  return m;
}

glm::mat4 orthographicReverseZ(float halfWidth, float halfHeight, float znear, float zfar) {
  for (const float half : {halfWidth, halfHeight})
    if (!(half > 0.0f) || !std::isfinite(half))
      throw std::invalid_argument(fmt::format("orthographic: half extent {} is not positive", half));
  if (!(znear >= 0.0f && zfar > znear) || !std::isfinite(zfar))
    throw std::invalid_argument(fmt::format("orthographic: planes znear {} zfar {} are not 0 <= znear < zfar", znear, zfar));
  // Column-major: clip = (x / halfWidth, -y / halfHeight, (zfar + z) / (zfar - znear), 1): depth 1 at
  // view z = -znear, 0 at -zfar, and y negated as in the perspective projection.
  glm::mat4 m(0.0f);
  m[0][0] = 1.0f / halfWidth;
  m[1][1] = -1.0f / halfHeight;
  m[2][2] = 1.0f / (zfar - znear);
  m[3][2] = zfar / (zfar - znear);
  m[3][3] = 1.0f;
  return m;
}

bool isOrthographic(const glm::mat4& proj) { return proj[0][3] == 0.0f && proj[1][3] == 0.0f && proj[2][3] == 0.0f; }

glm::mat4 lookAt(const glm::vec3& eye, const glm::vec3& target, const glm::vec3& up) {
  const glm::vec3 forward = target - eye;
  if (!(glm::length(forward) > 0.0f)) {
    throw std::invalid_argument(fmt::format("lookAt: eye and target are the same point ({}, {}, {})", eye.x, eye.y, eye.z));
  }
  const auto usable = [&](const glm::vec3& candidate) {
    return glm::length(glm::cross(glm::normalize(forward), candidate)) > 1e-4f * glm::length(candidate);
  };
  glm::vec3 chosenUp = up;
  if (!usable(chosenUp)) chosenUp = glm::vec3(0.0f, 0.0f, 1.0f);
  if (!usable(chosenUp)) chosenUp = glm::vec3(1.0f, 0.0f, 0.0f);
  return glm::lookAtRH(eye, target, chosenUp);
}

glm::vec3 orbitEye(const glm::vec3& target, float radius, float yawRadians, float pitchRadians) {
  const float horizontal = std::cos(pitchRadians);
  const glm::vec3 direction(horizontal * std::sin(yawRadians), std::sin(pitchRadians), horizontal * std::cos(yawRadians));
  return target + radius * direction;
}

namespace {
// The pixel's ray and its point on the near plane (depth 1), both in world space, in double.
struct PixelRayPoints {
  Ray ray;
  glm::dvec3 nearPoint;
};

PixelRayPoints pixelRayPoints(const glm::mat4& view, const glm::mat4& proj, glm::vec2 pixelCenter, glm::ivec2 imageSize) {
  if (imageSize.x <= 0 || imageSize.y <= 0) {
    throw std::invalid_argument(fmt::format("pixelRay: image size {}x{} is empty", imageSize.x, imageSize.y));
  }
  // Vulkan viewport transform inverted: framebuffer (0,0) is NDC (-1,-1), the top-left corner.
  const glm::dvec2 ndc = 2.0 * glm::dvec2(pixelCenter) / glm::dvec2(imageSize) - 1.0;
  const glm::dmat4 inverseView = glm::inverse(glm::dmat4(view));
  const glm::dmat4 inverseProj = glm::inverse(glm::dmat4(proj));
  // The point of this pixel on the near plane (depth 1).
  const glm::dvec4 nearPoint = inverseProj * glm::dvec4(ndc, 1.0, 1.0);
  const glm::dvec3 nearView = glm::dvec3(nearPoint) / nearPoint.w;
  PixelRayPoints points;
  points.nearPoint = glm::dvec3(inverseView * glm::dvec4(nearView, 1.0));
  if (isOrthographic(proj)) {
    // Parallel rays down -Z, each starting on the camera's plane beside the near point.
    points.ray.origin = glm::dvec3(inverseView * glm::dvec4(nearView.x, nearView.y, 0.0, 1.0));
    points.ray.direction = glm::normalize(glm::dvec3(inverseView * glm::dvec4(0.0, 0.0, -1.0, 0.0)));
    return points;
  }
  // Perspective: the eye is the view-space origin.
  points.ray.origin = glm::dvec3(inverseView * glm::dvec4(0.0, 0.0, 0.0, 1.0));
  points.ray.direction = glm::normalize(glm::dvec3(inverseView * glm::dvec4(nearView, 0.0)));
  return points;
}
}  // namespace

Ray pixelRay(const glm::mat4& view, const glm::mat4& proj, glm::vec2 pixelCenter, glm::ivec2 imageSize) {
  return pixelRayPoints(view, proj, pixelCenter, imageSize).ray;
}

Ray pixelRayFromNearPlane(const glm::mat4& view, const glm::mat4& proj, glm::vec2 pixelCenter, glm::ivec2 imageSize) {
  const PixelRayPoints points = pixelRayPoints(view, proj, pixelCenter, imageSize);
  return {points.nearPoint, points.ray.direction};
}

namespace {
void requirePositiveZnear(double znear, const char* function) {
  if (!(znear > 0.0)) throw std::invalid_argument(fmt::format("{}: znear {} is not positive", function, znear));
}
}  // namespace

double depthToViewDistance(double depth, double znear) {
  requirePositiveZnear(znear, "depthToViewDistance");
  if (!(depth > 0.0)) return std::numeric_limits<double>::infinity();
  return znear / depth;
}

double depthToViewDistance(const glm::mat4& proj, double depth) {
  // depth = (m22 z + m32) / (m23 z + m33) at view z = -distance, solved for z.
  const double m22 = proj[2][2], m32 = proj[3][2], m23 = proj[2][3], m33 = proj[3][3];
  const double denominator = m22 - depth * m23;
  if (!(denominator > 0.0)) return std::numeric_limits<double>::infinity();  // depth <= 0 of an infinite one
  return -(depth * m33 - m32) / denominator;
}

double viewDistanceToDepth(double viewDistance, double znear) {
  requirePositiveZnear(znear, "viewDistanceToDepth");
  if (!(viewDistance > 0.0)) {
    throw std::invalid_argument(fmt::format("viewDistanceToDepth: view distance {} is not in front of the eye", viewDistance));
  }
  return znear / viewDistance;  // +infinity gives 0
}

namespace {
glm::vec4 row(const glm::mat4& m, int i) { return glm::vec4(m[0][i], m[1][i], m[2][i], m[3][i]); }

glm::vec4 normalizedPlane(const glm::vec4& plane) {
  const float length = glm::length(glm::vec3(plane));
  // A degenerate plane (e.g. a singular matrix) culls nothing rather than producing NaNs.
  if (!(length > 1e-20f)) return glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  return plane / length;
}
}  // namespace

Frustum extractFrustum(const glm::mat4& viewProj) {
  // Clip-space inside conditions -w <= x <= w, -w <= y <= w, z <= w (reverse-Z near) as planes.
  const glm::vec4 x = row(viewProj, 0);
  const glm::vec4 y = row(viewProj, 1);
  const glm::vec4 z = row(viewProj, 2);
  const glm::vec4 w = row(viewProj, 3);
  Frustum frustum{};
  frustum.planes[Frustum::kLeft] = normalizedPlane(w + x);
  frustum.planes[Frustum::kRight] = normalizedPlane(w - x);
  frustum.planes[Frustum::kTop] = normalizedPlane(w + y);  // NDC y = -1 is the top row of the image
  frustum.planes[Frustum::kBottom] = normalizedPlane(w - y);
  frustum.planes[Frustum::kNear] = normalizedPlane(w - z);
  // Reverse-Z far plane z >= 0; an infinite perspective's z row has no normal (a plane holding all).
  frustum.planes[Frustum::kFar] = normalizedPlane(z);
  return frustum;
}

bool intersects(const Frustum& frustum, const glm::vec3& aabbMin, const glm::vec3& aabbMax) {
  for (const glm::vec4& plane : frustum.planes) {
    // The box corner furthest along the plane normal: if even it is outside, the whole box is.
    const glm::vec3 farthest(plane.x >= 0.0f ? aabbMax.x : aabbMin.x, plane.y >= 0.0f ? aabbMax.y : aabbMin.y,
                             plane.z >= 0.0f ? aabbMax.z : aabbMin.z);
    if (glm::dot(glm::vec3(plane), farthest) + plane.w < 0.0f) return false;
  }
  return true;
}

bool intersects(const Frustum& frustum, const glm::mat4& model, const glm::vec3& lo, const glm::vec3& hi) {
  glm::vec3 worldLo, worldHi;
  transformBounds(model, lo, hi, worldLo, worldHi);
  return intersects(frustum, worldLo, worldHi);
}

void transformBounds(const glm::mat4& m, const glm::vec3& lo, const glm::vec3& hi, glm::vec3& outLo, glm::vec3& outHi) {
  const glm::vec3 center = glm::vec3(m * glm::vec4(0.5f * (lo + hi), 1.0f));
  const glm::vec3 half = 0.5f * (hi - lo);
  const glm::mat3 a(m);
  const glm::vec3 extent = glm::abs(a[0]) * half.x + glm::abs(a[1]) * half.y + glm::abs(a[2]) * half.z;
  outLo = center - extent;
  outHi = center + extent;
}

}  // namespace engine::math
