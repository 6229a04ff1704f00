#pragma once
// Analytic SDF sources with exact gradients. All are 1-Lipschitz with |gradient| <= 1 (the narrow
// band bake relies on it); sphere, box, torus and capsule are exact signed distances. Where the
// gradient is undefined (sphere centre, torus core circle, capsule axis, box medial kinks) a unit
// vector of a neighbouring region is returned, documented per shape.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/expected.h"
#include "hermite_sdf/core/source.h"

namespace hsdf {

class SphereSource final : public SdfSource {
 public:
  SphereSource(const glm::dvec3& center, double radius) : center_(center), radius_(radius) {}
  // At the centre the gradient is (0,0,1).
  SdfSample sample(const glm::dvec3& p) const override;
  Aabb bounds() const override;

 private:
  glm::dvec3 center_;
  double radius_;
};

// Axis-aligned box, exact SDF. Inside, the gradient is the normal of the nearest face; on ties
// (medial planes) the lowest axis wins, and a zero coordinate counts as positive.
class BoxSource final : public SdfSource {
 public:
  BoxSource(const glm::dvec3& center, const glm::dvec3& halfExtents) : center_(center), half_(halfExtents) {}
  SdfSample sample(const glm::dvec3& p) const override;
  Aabb bounds() const override;

 private:
  glm::dvec3 center_;
  glm::dvec3 half_;
};

// Torus around the y axis through `center`: ring radius `major`, tube radius `minor`.
// On the y axis the radial direction is taken as +x; on the core circle the gradient is +y.
class TorusSource final : public SdfSource {
 public:
  TorusSource(const glm::dvec3& center, double major, double minor) : center_(center), major_(major), minor_(minor) {}
  SdfSample sample(const glm::dvec3& p) const override;
  Aabb bounds() const override;

 private:
  glm::dvec3 center_;
  double major_;
  double minor_;
};

// Segment a-b swept by a sphere of `radius`. On the segment itself the gradient is any unit vector
// perpendicular to it (deterministic).
class CapsuleSource final : public SdfSource {
 public:
  CapsuleSource(const glm::dvec3& a, const glm::dvec3& b, double radius) : a_(a), b_(b), radius_(radius) {}
  SdfSample sample(const glm::dvec3& p) const override;
  Aabb bounds() const override;

 private:
  glm::dvec3 a_;
  glm::dvec3 b_;
  double radius_;
};

// Smooth union of any number of sources with the quadratic polynomial smooth minimum
//   smin(a,b) = mix(b, a, w) - k w (1-w),  w = clamp(1/2 + (b-a)/(2k), 0, 1),
// applied left to right. Its gradient is exactly w grad a + (1-w) grad b (the derivative of the
// -k w(1-w) term cancels the one of w inside the blend), a convex combination, so |grad| <= 1 and
// the result stays 1-Lipschitz. It is not an exact distance inside the blend (it is smaller there,
// by at most k/4), so bounds grow by k/4.
class SmoothUnionSource final : public SdfSource {
 public:
  SmoothUnionSource(std::vector<std::unique_ptr<SdfSource>> children, double blendRadius);
  SdfSample sample(const glm::dvec3& p) const override;
  Aabb bounds() const override;

 private:
  std::vector<std::unique_ptr<SdfSource>> children_;
  double k_;
};

// The quadratic polynomial smooth minimum above, value and gradient, for two samples.
SdfSample smoothMin(const SdfSample& a, const SdfSample& b, double k);

// Named analytic shapes, each about 2 units across, centred near the origin:
//   "sphere" radius 1; "box" half extents (1, 0.7, 0.5); "torus" major 1, minor 0.35;
//   "capsule" from (-0.8,-0.3,0) to (0.8,0.3,0) radius 0.4; "blob" smooth union (k = 0.3) of a
//   sphere, a capsule and a small torus.
// Unknown names get an error listing the known ones.
engine::Expected<std::unique_ptr<SdfSource>> makeAnalyticSource(std::string_view name);
const std::vector<std::string>& analyticShapeNames();

}  // namespace hsdf
