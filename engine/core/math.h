#pragma once
// Camera maths shared by the GPU renderer and the CPU reference ray caster, which must agree exactly.
//
// Conventions (fixed project-wide):
//  - World space is right-handed; +Y is up. View space: the camera sits at the origin looking down -Z.
//  - Vulkan clip space: NDC x runs left -> right and y runs top -> bottom; the projection flips y so
//    that world-up appears up in the image. Pixel (0,0) is the top-left one, its centre at (0.5,0.5).
//  - Reverse-Z infinite perspective: depth = znear / viewDistance, where viewDistance is measured along
//    the view axis (-Z), not along the ray. Depth is 1 at the near plane and tends to 0 at infinity:
//    clear depth to 0 and test with GREATER (or GREATER_OR_EQUAL).
//  - Reverse-Z orthographic: depth = (zfar - viewDistance) / (zfar - znear), 1 at the near plane and 0
//    at the (finite) far plane; the same clear and test. Its clip w is 1 (isOrthographic).
// Functions throw std::invalid_argument for parameters that cannot describe a camera (e.g. znear <= 0).
#include <array>

#include <glm/glm.hpp>

namespace engine::math {

// Reverse-Z infinite projection in Vulkan clip space (see above). fovy in (0, pi), aspect = width / height.
glm::mat4 perspectiveReverseZInfinite(float fovyRadians, float aspect, float znear);

// Reverse-Z orthographic projection in Vulkan clip space: view-space x in [-halfWidth, halfWidth]
// and y in [-halfHeight, halfHeight] fill the image, 0 <= znear < zfar. Throws std::invalid_argument
// for a half extent that is not positive and finite, or planes that are not 0 <= znear < zfar.
glm::mat4 orthographicReverseZ(float halfWidth, float halfHeight, float znear, float zfar);
// True for a projection whose clip w does not depend on the point (an orthographic one).
bool isOrthographic(const glm::mat4& proj);

// Right-handed view matrix. If `up` is parallel to the viewing direction another up is chosen
// (world Z, or X if that is parallel too) instead of producing NaNs; eye == target throws.
glm::mat4 lookAt(const glm::vec3& eye, const glm::vec3& target, const glm::vec3& up);

// Eye position on a sphere around target. yaw 0 / pitch 0 puts the eye on +Z of the target (looking
// down -Z); positive yaw turns the eye towards +X, positive pitch raises it towards +Y.
glm::vec3 orbitEye(const glm::vec3& target, float radius, float yawRadians, float pitchRadians);

struct Ray {
  glm::dvec3 origin;
  glm::dvec3 direction;  // unit length
};

// The ray from the camera eye through a point of the image, in world space: the same ray along which
// Vulkan rasterizes the fragment whose framebuffer coordinate is pixelCenter (e.g. (x + 0.5, y + 0.5)).
// Computed in double from the inverse of the given matrices. An orthographic projection has no eye
// point: its rays are parallel to the view axis and start on the camera's plane (view z = 0).
Ray pixelRay(const glm::mat4& view, const glm::mat4& proj, glm::vec2 pixelCenter, glm::ivec2 imageSize);
// The same ray starting where it crosses the near plane (reverse-Z depth 1) instead of at the eye:
// a rasterizer clips everything nearer, so what the pixel shows is the first surface after it.
Ray pixelRayFromNearPlane(const glm::mat4& view, const glm::mat4& proj, glm::vec2 pixelCenter, glm::ivec2 imageSize);

// Reverse-Z depth <-> distance along the view axis. Depth 0 (or less) maps to +infinity and back.
double depthToViewDistance(double depth, double znear);
double viewDistanceToDepth(double viewDistance, double znear);
// The same for any reverse-Z projection `proj` (perspective or orthographic), from its z and w rows.
double depthToViewDistance(const glm::mat4& proj, double depth);

// Side planes (and near plane) of a view frustum, each (normal, d) with normal pointing inwards:
// a point p is inside a plane when dot(normal, p) + d >= 0. kTop/kBottom bound the top/bottom rows of
// the image. kFar is an orthographic projection's far plane; a perspective one's lies at infinity and
// its kFar is (0, 0, 0, 1), which holds every point.
struct Frustum {
  enum Plane { kLeft, kRight, kBottom, kTop, kNear, kFar, kPlaneCount };
  std::array<glm::vec4, kPlaneCount> planes;
};

// Planes of viewProj = proj * view (reverse-Z: the near plane is clip z <= w). Normals are unit length.
Frustum extractFrustum(const glm::mat4& viewProj);

// World-space bounds of the box [lo, hi] under an affine transform (tight for the box's image).
void transformBounds(const glm::mat4& m, const glm::vec3& lo, const glm::vec3& hi, glm::vec3& outLo, glm::vec3& outHi);

// False only if the box lies entirely outside one plane. Conservative: a box near a frustum corner
// may be reported as intersecting although it is outside.
bool intersects(const Frustum& frustum, const glm::vec3& aabbMin, const glm::vec3& aabbMax);
// The same for an object's box [lo, hi] placed by the affine `model` (its world bounds tested).
bool intersects(const Frustum& frustum, const glm::mat4& model, const glm::vec3& lo, const glm::vec3& hi);

}  // namespace engine::math
