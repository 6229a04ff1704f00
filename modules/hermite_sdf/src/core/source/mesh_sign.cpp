#include "source/mesh_sign.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace hsdf::mesh {
namespace {

std::uint64_t edgeKey(std::uint32_t u, std::uint32_t v) {
  return (std::uint64_t(std::min(u, v)) << 32) | std::max(u, v);
}

double angleBetween(const glm::dvec3& u, const glm::dvec3& v) {
  return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
}

// Orientation of d relative to the plane (a, b, c): the sign of the signed volume.
double orient(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  return glm::dot(glm::cross(b - a, c - a), d - a);
}

// Segment [p, q] touches or crosses triangle (a, b, c); false when it lies in the triangle's plane.
bool segmentHitsTriangle(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& a, const glm::dvec3& b,
                         const glm::dvec3& c) {
  const double sp = orient(a, b, c, p);
  const double sq = orient(a, b, c, q);
  if ((sp > 0.0 && sq > 0.0) || (sp < 0.0 && sq < 0.0) || (sp == 0.0 && sq == 0.0)) return false;
  const double e0 = orient(p, q, a, b);
  const double e1 = orient(p, q, b, c);
  const double e2 = orient(p, q, c, a);
  return (e0 >= 0.0 && e1 >= 0.0 && e2 >= 0.0) || (e0 <= 0.0 && e1 <= 0.0 && e2 <= 0.0);
}

bool trianglesIntersect(const glm::dvec3 (&s)[3], const glm::dvec3 (&t)[3]) {
  for (int e = 0; e < 3; ++e) {
    if (segmentHitsTriangle(s[e], s[(e + 1) % 3], t[0], t[1], t[2])) return true;
    if (segmentHitsTriangle(t[e], t[(e + 1) % 3], s[0], s[1], s[2])) return true;
  }
  return false;
}

struct Bounds {
  glm::dvec3 lo;
  glm::dvec3 hi;
};

// Axis-aligned bounds of an oriented box.
Bounds alignedBounds(const OrientedBox& box) {
  glm::dvec3 reach(0.0);
  for (int a = 0; a < 3; ++a) reach += glm::abs(box.axes[a]) * box.halfExtent[a];
  return {box.centre - reach, box.centre + reach};
}

bool overlap(const Bounds& x, const Bounds& y) {
  return glm::all(glm::lessThanEqual(x.lo, y.hi)) && glm::all(glm::lessThanEqual(y.lo, x.hi));
}

}  // namespace

PseudoNormals::PseudoNormals(const TriangleBvh& bvh, const std::vector<std::uint32_t>& vertexOf) {
  const std::size_t count = bvh.triangleCount();
  std::unordered_map<std::uint32_t, glm::dvec3> vertexSum;
  std::unordered_map<std::uint64_t, glm::dvec3> edgeSum;
  for (std::uint32_t t = 0; t < count; ++t) {
    const glm::dvec3& n = bvh.unitNormal(t);
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3& here = bvh.corner(t, k);
      const double angle = angleBetween(bvh.corner(t, (k + 1) % 3) - here, bvh.corner(t, (k + 2) % 3) - here);
      vertexSum[vertexOf[3 * t + std::size_t(k)]] += angle * n;
      edgeSum[edgeKey(vertexOf[3 * t + std::size_t(k)], vertexOf[3 * t + std::size_t(k + 1) % 3])] += n;
    }
  }
  normals_.resize(count);
  for (std::uint32_t t = 0; t < count; ++t) {
    const std::uint32_t* v = &vertexOf[3 * std::size_t(t)];
    auto& n = normals_[t];
    n[std::size_t(Feature::Face)] = bvh.unitNormal(t);
    n[std::size_t(Feature::VertexA)] = vertexSum[v[0]];
    n[std::size_t(Feature::VertexB)] = vertexSum[v[1]];
    n[std::size_t(Feature::VertexC)] = vertexSum[v[2]];
    n[std::size_t(Feature::EdgeAB)] = edgeSum[edgeKey(v[0], v[1])];
    n[std::size_t(Feature::EdgeBC)] = edgeSum[edgeKey(v[1], v[2])];
    n[std::size_t(Feature::EdgeCA)] = edgeSum[edgeKey(v[2], v[0])];
  }
}

bool hasSelfIntersections(const TriangleBvh& bvh, const std::vector<std::uint32_t>& vertexOf) {
  const std::vector<BvhNode>& nodes = bvh.nodes();
  std::vector<Bounds> nodeBounds(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) nodeBounds[i] = alignedBounds(nodes[i].box);
  std::vector<std::uint32_t> stack;
  for (std::uint32_t t = 0; t < bvh.triangleCount(); ++t) {
    const glm::dvec3 s[3] = {bvh.corner(t, 0), bvh.corner(t, 1), bvh.corner(t, 2)};
    const Bounds box{glm::min(s[0], glm::min(s[1], s[2])), glm::max(s[0], glm::max(s[1], s[2]))};
    const std::uint32_t* sv = &vertexOf[3 * std::size_t(t)];
    stack.assign(1, 0);
    while (!stack.empty()) {
      const std::uint32_t index = stack.back();
      stack.pop_back();
      if (!overlap(box, nodeBounds[index])) continue;
      const BvhNode& node = nodes[index];
      if (!node.isLeaf()) {
        stack.push_back(index + 1);
        stack.push_back(node.rightOrFirst);
        continue;
      }
      for (std::uint32_t u = node.rightOrFirst; u < node.rightOrFirst + node.count; ++u) {
        if (u <= t) continue;  // each pair once
        const std::uint32_t* uv = &vertexOf[3 * std::size_t(u)];
        const bool shareVertex = std::find(uv, uv + 3, sv[0]) != uv + 3 || std::find(uv, uv + 3, sv[1]) != uv + 3 ||
                                 std::find(uv, uv + 3, sv[2]) != uv + 3;
        if (shareVertex) continue;
        const glm::dvec3 other[3] = {bvh.corner(u, 0), bvh.corner(u, 1), bvh.corner(u, 2)};
        if (trianglesIntersect(s, other)) return true;
      }
    }
  }
  return false;
}

namespace {

// Twice the area of BVH triangle t.
double doubleArea(const TriangleBvh& bvh, std::uint32_t t) {
  return glm::length(glm::cross(bvh.corner(t, 1) - bvh.corner(t, 0), bvh.corner(t, 2) - bvh.corner(t, 0)));
}

// Connected parts: triangles joined by welded vertices (union-find over the vertices).
struct Parts {
  std::vector<std::uint32_t> of;  // part of each BVH triangle, 0..count-1
  std::uint32_t count = 0;
};

Parts connectedParts(const TriangleBvh& bvh, const std::vector<std::uint32_t>& vertexOf) {
  std::vector<std::uint32_t> parent(vertexOf.empty() ? 0 : *std::max_element(vertexOf.begin(), vertexOf.end()) + 1);
  for (std::uint32_t v = 0; v < parent.size(); ++v) parent[v] = v;
  const auto find = [&parent](std::uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  const auto triangles = static_cast<std::uint32_t>(bvh.triangleCount());
  for (std::uint32_t t = 0; t < triangles; ++t)
    for (int k = 1; k < 3; ++k) parent[find(vertexOf[3 * std::size_t(t) + std::size_t(k)])] = find(vertexOf[3 * std::size_t(t)]);
  Parts parts;
  std::vector<std::uint32_t> number(parent.size(), UINT32_MAX);
  parts.of.resize(triangles);
  for (std::uint32_t t = 0; t < triangles; ++t) {
    std::uint32_t& n = number[find(vertexOf[3 * std::size_t(t)])];
    if (n == UINT32_MAX) n = parts.count++;
    parts.of[t] = n;
  }
  return parts;
}

// The winding numbers just in front of and just behind triangle t at its centroid. The step is a
// millionth of the triangle's smallest altitude (a sliver's length says nothing of how thin the
// part is): far less than the part's thickness or its distance to another part, far enough that
// the triangle's own solid angle is ~2 pi, and above the coordinates' rounding.
std::pair<double, double> windingBothSides(const TriangleBvh& bvh, std::uint32_t t, double windingBeta) {
  const glm::dvec3 a = bvh.corner(t, 0), b = bvh.corner(t, 1), c = bvh.corner(t, 2);
  const glm::dvec3 centroid = (a + b + c) / 3.0;
  const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
  const glm::dvec3 magnitude = glm::abs(centroid);
  const double offset =
      std::max(1e-6 * doubleArea(bvh, t) / longest, 1e-13 * std::max({magnitude.x, magnitude.y, magnitude.z}));
  const glm::dvec3 step = offset * bvh.unitNormal(t);
  return {bvh.windingNumber(centroid + step, windingBeta), bvh.windingNumber(centroid - step, windingBeta)};
}

// A winding number this far from 1/2 says inside or outside of an open mesh for sure.
constexpr double kSeparatingMargin = 0.1;
// Points sampled over the whole mesh, by area (at least one per part, at most kMaxPartSamples).
constexpr double kOpenSamples = 4096.0;
constexpr std::size_t kMaxPartSamples = 64;

}  // namespace

PartSides partSides(const TriangleBvh& bvh, const std::vector<std::uint32_t>& vertexOf, double windingBeta) {
  const Parts parts = connectedParts(bvh, vertexOf);
  // Each part's largest triangle: the points off it are farthest from its edges.
  std::vector<std::uint32_t> largest(parts.count, UINT32_MAX);
  std::vector<double> largestArea(parts.count, -1.0);
  for (std::uint32_t t = 0; t < parts.of.size(); ++t) {
    const std::uint32_t part = parts.of[t];
    if (const double area = doubleArea(bvh, t); area > largestArea[part]) {
      largestArea[part] = area;
      largest[part] = t;
    }
  }
  PartSides sides;
  std::vector<bool> interiorPart(parts.count, false);
  for (std::uint32_t part = 0; part < parts.count; ++part) {
    const auto [front, back] = windingBothSides(bvh, largest[part], windingBeta);
    sides.faceOutside = sides.faceOutside && std::abs(front) < 0.5;
    interiorPart[part] = std::abs(front) >= 0.5 && std::abs(back) >= 0.5;
  }
  for (std::uint32_t t = 0; t < parts.of.size(); ++t)
    if (interiorPart[parts.of[t]]) sides.interior.push_back(t);
  return sides;
}

std::vector<std::uint32_t> partsBoundingNothing(const TriangleBvh& bvh, const std::vector<std::uint32_t>& vertexOf,
                                                double windingBeta) {
  const Parts parts = connectedParts(bvh, vertexOf);
  std::vector<std::vector<std::uint32_t>> members(parts.count);
  std::vector<double> partArea(parts.count, 0.0);
  double total = 0.0;
  for (std::uint32_t t = 0; t < parts.of.size(); ++t) {
    members[parts.of[t]].push_back(t);
    partArea[parts.of[t]] += doubleArea(bvh, t);
    total += doubleArea(bvh, t);
  }
  std::vector<bool> nothing(parts.count, false);
  for (std::uint32_t part = 0; part < parts.count; ++part) {
    // Stratified by area: sample i at the triangle holding area (i + 1/2) / n of the part.
    const auto n = std::size_t(std::clamp(std::ceil(kOpenSamples * partArea[part] / total), 1.0, double(kMaxPartSamples)));
    std::size_t separating = 0, sample = 0;
    double before = 0.0;
    for (const std::uint32_t t : members[part]) {
      before += doubleArea(bvh, t);
      for (; sample < n && (double(sample) + 0.5) / double(n) * partArea[part] <= before; ++sample) {
        const auto [front, back] = windingBothSides(bvh, t, windingBeta);
        const bool decisive = std::abs(front - 0.5) >= kSeparatingMargin && std::abs(back - 0.5) >= kSeparatingMargin;
        separating += decisive && (front >= 0.5) != (back >= 0.5);
      }
    }
    nothing[part] = 2 * separating < n;
  }
  std::vector<std::uint32_t> triangles;
  for (std::uint32_t t = 0; t < parts.of.size(); ++t)
    if (nothing[parts.of[t]]) triangles.push_back(t);
  return triangles;
}

}  // namespace hsdf::mesh
