#include "source/mesh_sign.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
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

// The BVH triangles of each part, in BVH order.
std::vector<std::vector<std::uint32_t>> membersOf(const Parts& parts) {
  std::vector<std::vector<std::uint32_t>> members(parts.count);
  for (std::uint32_t t = 0; t < parts.of.size(); ++t) members[parts.of[t]].push_back(t);
  return members;
}

// How far off triangle t the side points step. A millionth of the triangle's smallest altitude (a
// sliver's length says nothing of how thin the part is): far less than the part's thickness or its
// distance to another part, far enough that the triangle's own solid angle is ~2 pi, and above the
// coordinates' rounding at `on`.
glm::dvec3 sideStep(const TriangleBvh& bvh, std::uint32_t t, const glm::dvec3& on) {
  const glm::dvec3 a = bvh.corner(t, 0), b = bvh.corner(t, 1), c = bvh.corner(t, 2);
  const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
  const glm::dvec3 magnitude = glm::abs(on);
  const double offset =
      std::max(1e-6 * doubleArea(bvh, t) / longest, 1e-13 * std::max({magnitude.x, magnitude.y, magnitude.z}));
  return offset * bvh.unitNormal(t);
}

// A winding number this far from 1/2 says inside or outside of an open mesh for sure.
constexpr double kSeparatingMargin = 0.1;
// Points sampled over the whole mesh, by area (at least one per part, at most kMaxPartSamples).
constexpr double kOpenSamples = 4096.0;
constexpr std::size_t kMaxPartSamples = 64;
// Open parts that bound nothing alone (sheets) but close a volume together (a tube and caps that
// share no vertex with it, six loose faces of a box) separate it across nearly all their area: only
// near their seams does the winding number sit near 1/2. Sheets that cross in the open (foliage
// cards in an X) separate at most the wedge on one side of the crossing, where both add up: about
// half their area. Between the two, this share.
constexpr double kTogetherShare = 0.75;

// Sample j of the m that fall on triangle t: its centroid when alone, else the R2 low-discrepancy
// sequence folded into the triangle. Distinct points matter on large triangles (a quad card, the
// long sides of a cylinder pushed through a box): their centroids alone may all lie where the
// triangle separates nothing, or all where it does.
glm::dvec3 samplePoint(const TriangleBvh& bvh, std::uint32_t t, std::size_t j, std::size_t m) {
  const glm::dvec3 a = bvh.corner(t, 0), b = bvh.corner(t, 1), c = bvh.corner(t, 2);
  if (m == 1) return (a + b + c) / 3.0;
  double u = 0.5 + 0.7548776662466927 * double(j), v = 0.5 + 0.5698402909980532 * double(j);
  u -= std::floor(u);
  v -= std::floor(v);
  if (u + v > 1.0) {
    u = 1.0 - u;
    v = 1.0 - v;
  }
  return a + u * (b - a) + v * (c - a);
}

// The share of a part's samples (n, stratified by area: sample i on the triangle holding area
// (i + 1/2) / n of the part) across which `winding` goes decisively from one side of 1/2 to the other.
template <class Winding>
double separatingShare(const TriangleBvh& bvh, const std::vector<std::uint32_t>& members, double partArea,
                       std::size_t n, const Winding& winding) {
  std::size_t separating = 0, sample = 0;
  double before = 0.0;
  for (const std::uint32_t t : members) {
    before += doubleArea(bvh, t);
    const std::size_t first = sample;
    while (sample < n && (double(sample) + 0.5) / double(n) * partArea <= before) ++sample;
    for (std::size_t j = first; j < sample; ++j) {
      const glm::dvec3 p = samplePoint(bvh, t, j - first, sample - first);
      const glm::dvec3 step = sideStep(bvh, t, p);
      const double front = winding(p + step), back = winding(p - step);
      const bool decisive = std::abs(front - 0.5) >= kSeparatingMargin && std::abs(back - 0.5) >= kSeparatingMargin;
      separating += decisive && (front >= 0.5) != (back >= 0.5);
    }
  }
  return double(separating) / double(n);
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

std::vector<std::vector<std::uint32_t>> connectedPartTriangles(const TriangleBvh& bvh,
                                                               const std::vector<std::uint32_t>& vertexOf) {
  return membersOf(connectedParts(bvh, vertexOf));
}

std::uint32_t largestTriangle(const TriangleBvh& bvh, std::span<const std::uint32_t> triangles) {
  std::uint32_t largest = UINT32_MAX;
  double largestArea = -1.0;
  for (const std::uint32_t t : triangles)
    if (const double area = doubleArea(bvh, t); area > largestArea) {
      largestArea = area;
      largest = t;
    }
  return largest;
}

// The winding numbers just in front of and just behind triangle t at its centroid.
std::pair<double, double> windingBothSides(const TriangleBvh& bvh, std::uint32_t t, double windingBeta) {
  const glm::dvec3 centroid = (bvh.corner(t, 0) + bvh.corner(t, 1) + bvh.corner(t, 2)) / 3.0;
  const glm::dvec3 step = sideStep(bvh, t, centroid);
  return {bvh.windingNumber(centroid + step, windingBeta), bvh.windingNumber(centroid - step, windingBeta)};
}

// The corners of BVH triangles `triangles`, three per triangle: a BVH of these alone.
std::vector<glm::dvec3> cornersOf(const TriangleBvh& bvh, const std::vector<std::uint32_t>& triangles) {
  std::vector<glm::dvec3> corners;
  corners.reserve(3 * triangles.size());
  for (const std::uint32_t t : triangles) corners.insert(corners.end(), {bvh.corner(t, 0), bvh.corner(t, 1), bvh.corner(t, 2)});
  return corners;
}

PartSides partSides(const TriangleBvh& bvh, const std::vector<std::uint32_t>& vertexOf, double windingBeta) {
  const Parts parts = connectedParts(bvh, vertexOf);
  const std::vector<std::vector<std::uint32_t>> members = membersOf(parts);
  PartSides sides;
  std::vector<bool> interiorPart(parts.count, false);
  for (std::uint32_t part = 0; part < parts.count; ++part) {
    const auto [front, back] = windingBothSides(bvh, largestTriangle(bvh, members[part]), windingBeta);
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
  const std::vector<std::vector<std::uint32_t>> members = membersOf(parts);
  std::vector<double> partArea(parts.count, 0.0);
  double total = 0.0;
  for (std::uint32_t t = 0; t < parts.of.size(); ++t) {
    partArea[parts.of[t]] += doubleArea(bvh, t);
    total += doubleArea(bvh, t);
  }
  std::vector<std::size_t> samples(parts.count);
  for (std::uint32_t part = 0; part < parts.count; ++part)
    samples[part] = std::size_t(std::clamp(std::ceil(kOpenSamples * partArea[part] / total), 1.0, double(kMaxPartSamples)));
  const auto whole = [&](const glm::dvec3& p) { return bvh.windingNumber(p, windingBeta); };

  // Each part by its own winding number, its triangles alone: a closed part's is 0 on one side and
  // 1 on the other wherever it is, also where it runs inside another part (an arm pushed through a
  // torso, where the whole mesh's goes from 1 to 2) or beside a large sheet (a floor adds about
  // 1/2 to the whole mesh's near it); a sheet's is about -1/2 and 1/2, wherever it is. A part with
  // no BVH of its own is the largest: its winding number is the whole mesh's less the others'.
  std::uint32_t largest = 0;
  for (std::uint32_t part = 1; part < parts.count; ++part)
    if (members[part].size() > members[largest].size()) largest = part;
  std::vector<std::uint32_t> others;
  for (std::uint32_t t = 0; t < parts.of.size(); ++t)
    if (parts.of[t] != largest) others.push_back(t);
  std::vector<bool> boundsAlone(parts.count, false);
  {
    const std::optional<TriangleBvh> rest = others.empty() ? std::nullopt : std::optional<TriangleBvh>(cornersOf(bvh, others));
    boundsAlone[largest] =
        2.0 * separatingShare(bvh, members[largest], partArea[largest], samples[largest], [&](const glm::dvec3& p) {
          return rest ? whole(p) - rest->windingNumber(p, windingBeta) : whole(p);
        }) >= 1.0;
  }
  for (std::uint32_t part = 0; part < parts.count; ++part) {
    if (part == largest) continue;
    const TriangleBvh own(cornersOf(bvh, members[part]));
    boundsAlone[part] = 2.0 * separatingShare(bvh, members[part], partArea[part], samples[part], [&](const glm::dvec3& p) {
                          return own.windingNumber(p, windingBeta);
                        }) >= 1.0;
  }

  // The parts that bound nothing alone may close a volume together (see kTogetherShare): each is
  // kept if the winding number of all of them separates across most of its area.
  std::vector<std::uint32_t> loose;
  for (std::uint32_t t = 0; t < parts.of.size(); ++t)
    if (!boundsAlone[parts.of[t]]) loose.push_back(t);
  std::vector<bool> nothing(parts.count, false);
  for (std::uint32_t part = 0; part < parts.count; ++part) nothing[part] = !boundsAlone[part];
  if (std::count(boundsAlone.begin(), boundsAlone.end(), false) >= 2) {
    // All of the mesh: its own BVH answers.
    const std::optional<TriangleBvh> together =
        loose.size() == parts.of.size() ? std::nullopt : std::optional<TriangleBvh>(cornersOf(bvh, loose));
    for (std::uint32_t part = 0; part < parts.count; ++part)
      if (!boundsAlone[part])
        nothing[part] = separatingShare(bvh, members[part], partArea[part], samples[part], [&](const glm::dvec3& p) {
                          return together ? together->windingNumber(p, windingBeta) : whole(p);
                        }) < kTogetherShare;
  }
  std::vector<std::uint32_t> triangles;
  for (std::uint32_t t = 0; t < parts.of.size(); ++t)
    if (nothing[parts.of[t]]) triangles.push_back(t);
  return triangles;
}

}  // namespace hsdf::mesh
