#pragma once
// Per-triangle geometry in double precision: closest point and solid angle. Inline because the
// BVH queries call them millions of times per bake.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace hsdf::mesh {

// A triangle prepared for closest-point queries: vertex a and the edges to b and c.
struct PreparedTriangle {
  glm::dvec3 a{0.0};
  glm::dvec3 ab{0.0};
  glm::dvec3 ac{0.0};
};

// Which part of a triangle a closest point lies on; the sign of a closed mesh near its surface
// follows from the pseudonormal of that feature.
enum class Feature : std::uint8_t { Face, VertexA, VertexB, VertexC, EdgeAB, EdgeBC, EdgeCA };
inline constexpr int kFeatureCount = 7;

struct TrianglePoint {
  glm::dvec3 point{0.0};
  Feature feature = Feature::Face;
};

// Closest point of triangle (a, a+ab, a+ac) to p, by Voronoi region of the triangle's features
// (Ericson, Real-Time Collision Detection, 5.1.5). The triangle must have non-zero area.
inline TrianglePoint closestPointOnTriangle(const glm::dvec3& p, const PreparedTriangle& t) {
  const glm::dvec3 ap = p - t.a;
  const double d1 = glm::dot(t.ab, ap);
  const double d2 = glm::dot(t.ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {t.a, Feature::VertexA};
  const glm::dvec3 bp = ap - t.ab;
  const double d3 = glm::dot(t.ab, bp);
  const double d4 = glm::dot(t.ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return {t.a + t.ab, Feature::VertexB};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return {t.a + (d1 / (d1 - d3)) * t.ab, Feature::EdgeAB};
  const glm::dvec3 cp = ap - t.ac;
  const double d5 = glm::dot(t.ab, cp);
  const double d6 = glm::dot(t.ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return {t.a + t.ac, Feature::VertexC};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return {t.a + (d2 / (d2 - d6)) * t.ac, Feature::EdgeCA};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {t.a + t.ab + w * (t.ac - t.ab), Feature::EdgeBC};
  }
  const double denom = 1.0 / (va + vb + vc);
  return {t.a + (vb * denom) * t.ab + (vc * denom) * t.ac, Feature::Face};
}

// Signed solid angle of triangle (a, b, c) seen from q, positive when the triangle's
// counter-clockwise normal points away from q (Van Oosterom & Strackee 1983).
inline double solidAngle(const glm::dvec3& q, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 qa = a - q;
  const glm::dvec3 qb = b - q;
  const glm::dvec3 qc = c - q;
  const double la = glm::length(qa);
  const double lb = glm::length(qb);
  const double lc = glm::length(qc);
  const double numerator = glm::dot(qa, glm::cross(qb, qc));
  const double denominator =
      la * lb * lc + glm::dot(qa, qb) * lc + glm::dot(qb, qc) * la + glm::dot(qc, qa) * lb;
  return 2.0 * std::atan2(numerator, denominator);
}

// A box with orthonormal axes: points centre + sum t_i axes[i], |t_i| <= halfExtent[i].
struct OrientedBox {
  glm::dvec3 centre{0.0};
  glm::dvec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  glm::dvec3 halfExtent{0.0};
};

// The smallest disk holding a triangle, in the triangle's plane: the distance to it is a cheap and
// tight lower bound on the distance to the triangle (exact along the normal, off by at most the
// disk's slack sideways), which rejects most candidate triangles before the exact closest point.
struct TriangleDisk {
  glm::dvec3 centre{0.0};
  glm::dvec3 normal{0.0};
  double radius = 0.0;
};

}  // namespace hsdf::mesh
