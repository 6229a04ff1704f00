#include "source/mesh_bvh.h"

#include <algorithm>
#include <array>
#include <numbers>
#include <span>

namespace hsdf::mesh {
namespace {

constexpr std::uint32_t kMaxLeafTriangles = 4;
constexpr int kSahBins = 16;
// Beyond this depth the builder splits at the median, which halves the count at every level, so
// the tree depth (and the traversal stacks below) stay bounded for any input.
constexpr int kMaxSahDepth = 40;
constexpr int kStackSize = 128;

double halfSurfaceArea(const glm::dvec3& lo, const glm::dvec3& hi) {
  const glm::dvec3 e = glm::max(hi - lo, glm::dvec3(0.0));
  return e.x * e.y + e.y * e.z + e.z * e.x;
}

struct Box {
  glm::dvec3 lo{std::numeric_limits<double>::infinity()};
  glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
  void grow(const glm::dvec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void grow(const Box& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
};

// Rounding margin for bounding shapes: they must contain their triangles after rounding too.
constexpr double kBoundSlack = 1e-12;

TriangleDisk boundingDisk(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& normal) {
  // Obtuse or right triangle: the disk on the longest edge. Acute: the circumscribed disk.
  const glm::dvec3 edges[3][2] = {{a, b}, {b, c}, {c, a}};
  const glm::dvec3 opposite[3] = {c, a, b};
  TriangleDisk disk;
  disk.normal = normal;
  bool found = false;
  for (int e = 0; e < 3 && !found; ++e) {
    const glm::dvec3 u = edges[e][0] - opposite[e];
    const glm::dvec3 v = edges[e][1] - opposite[e];
    if (glm::dot(u, v) <= 0.0) {  // the angle at `opposite` is >= 90 degrees
      disk.centre = 0.5 * (edges[e][0] + edges[e][1]);
      found = true;
    }
  }
  if (!found) {
    const glm::dvec3 ab = b - a, ac = c - a;
    const glm::dvec3 n = glm::cross(ab, ac);
    disk.centre = a + (glm::dot(ac, ac) * glm::cross(n, ab) + glm::dot(ab, ab) * glm::cross(ac, n)) /
                          (2.0 * glm::dot(n, n));
  }
  for (const glm::dvec3& p : {a, b, c}) disk.radius = std::max(disk.radius, glm::length(p - disk.centre));
  disk.radius *= 1.0 + kBoundSlack;
  return disk;
}

// Eigenvectors of a symmetric 3x3 matrix by cyclic Jacobi rotations (columns of the result).
glm::dmat3 symmetricEigenvectors(glm::dmat3 m) {
  glm::dmat3 vectors(1.0);
  for (int sweep = 0; sweep < 32; ++sweep) {
    const double offDiagonal = m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2];
    if (offDiagonal < 1e-30 * (m[0][0] * m[0][0] + m[1][1] * m[1][1] + m[2][2] * m[2][2]) || offDiagonal == 0.0) break;
    for (int p = 0; p < 2; ++p) {
      for (int q = p + 1; q < 3; ++q) {
        if (m[p][q] == 0.0) continue;
        const double theta = (m[q][q] - m[p][p]) / (2.0 * m[p][q]);
        const double t = (theta >= 0.0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0);
        const double s = t * c;
        glm::dmat3 rotation(1.0);
        rotation[p][p] = c;
        rotation[q][q] = c;
        rotation[q][p] = s;
        rotation[p][q] = -s;
        m = glm::transpose(rotation) * m * rotation;
        vectors = vectors * rotation;
      }
    }
  }
  return vectors;
}

OrientedBox boxWithAxes(std::span<const glm::dvec3> points, const glm::dvec3 (&axes)[3]) {
  glm::dvec3 lo(std::numeric_limits<double>::infinity());
  glm::dvec3 hi(-std::numeric_limits<double>::infinity());
  for (const glm::dvec3& p : points) {
    const glm::dvec3 t(glm::dot(p, axes[0]), glm::dot(p, axes[1]), glm::dot(p, axes[2]));
    lo = glm::min(lo, t);
    hi = glm::max(hi, t);
  }
  OrientedBox box;
  const glm::dvec3 mid = 0.5 * (lo + hi);
  box.centre = mid.x * axes[0] + mid.y * axes[1] + mid.z * axes[2];
  const double scale = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x), std::abs(hi.y), std::abs(hi.z)});
  box.halfExtent = 0.5 * (hi - lo) + glm::dvec3(kBoundSlack * scale);
  for (int i = 0; i < 3; ++i) box.axes[i] = axes[i];
  return box;
}

double halfArea(const OrientedBox& box) {
  const glm::dvec3& e = box.halfExtent;
  return e.x * e.y + e.y * e.z + e.z * e.x;
}

// The tighter (by surface area) of the axis-aligned box and the box along the principal axes of
// the points.
OrientedBox tightBox(std::span<const glm::dvec3> points) {
  const glm::dvec3 worldAxes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const OrientedBox aligned = boxWithAxes(points, worldAxes);
  glm::dvec3 mean(0.0);
  for (const glm::dvec3& p : points) mean += p;
  mean /= double(points.size());
  glm::dmat3 covariance(0.0);
  for (const glm::dvec3& p : points) covariance += glm::outerProduct(p - mean, p - mean);
  const glm::dmat3 vectors = symmetricEigenvectors(covariance);
  // Re-orthonormalise: Jacobi rotations keep orthogonality only up to rounding.
  glm::dvec3 principal[3];
  principal[0] = glm::normalize(vectors[0]);
  principal[1] = glm::normalize(vectors[1] - glm::dot(vectors[1], principal[0]) * principal[0]);
  principal[2] = glm::cross(principal[0], principal[1]);
  const OrientedBox oriented = boxWithAxes(points, principal);
  return halfArea(oriented) < halfArea(aligned) ? oriented : aligned;
}

}  // namespace

struct BvhBuildItem {
  Box box;
  glm::dvec3 centroid{0.0};
  std::uint32_t index = 0;
};

namespace {

// A binned surface-area-heuristic split: the items whose centroid falls in bins 0..bin along
// `axis` go left. axis -1: none found.
struct SahSplit {
  int axis = -1;
  int bin = 0;
  double cost = std::numeric_limits<double>::infinity();
};

// The cheapest split along `axis` where it is cheaper than `best`.
void improveSplitOnAxis(std::span<const BvhBuildItem> items, const Box& centroids, int axis, SahSplit& best) {
  const double extent = centroids.hi[axis] - centroids.lo[axis];
  if (!(extent > 0.0)) return;
  const double scale = kSahBins / extent;
  std::array<Box, kSahBins> binBoxes;
  std::array<std::uint32_t, kSahBins> binCounts{};
  for (const BvhBuildItem& item : items) {
    const int bin = std::min(kSahBins - 1, int((item.centroid[axis] - centroids.lo[axis]) * scale));
    binBoxes[std::size_t(bin)].grow(item.box);
    ++binCounts[std::size_t(bin)];
  }
  std::array<double, kSahBins> rightCost{};
  Box right;
  std::uint32_t rightCount = 0;
  for (int b = kSahBins - 1; b > 0; --b) {
    right.grow(binBoxes[std::size_t(b)]);
    rightCount += binCounts[std::size_t(b)];
    rightCost[std::size_t(b)] = rightCount ? halfSurfaceArea(right.lo, right.hi) * rightCount : 0.0;
  }
  Box left;
  std::uint32_t leftCount = 0;
  for (int b = 0; b < kSahBins - 1; ++b) {
    left.grow(binBoxes[std::size_t(b)]);
    leftCount += binCounts[std::size_t(b)];
    if (leftCount == 0 || leftCount == items.size()) continue;
    const double cost = halfSurfaceArea(left.lo, left.hi) * leftCount + rightCost[std::size_t(b) + 1];
    if (cost < best.cost) best = {axis, b, cost};
  }
}

// Where items [begin, end) split, reordered so that the left child's come first: the cheapest SAH
// split over the three axes while the tree is shallow enough, else (or where that leaves a side
// empty: coincident centroids) halved by count along the widest axis.
std::uint32_t splitItems(std::vector<BvhBuildItem>& items, std::uint32_t begin, std::uint32_t end, const Box& centroids,
                         int depth) {
  const auto first = items.begin() + begin, last = items.begin() + end;
  SahSplit split;
  if (depth < kMaxSahDepth)
    for (int axis = 0; axis < 3; ++axis) improveSplitOnAxis({first, last}, centroids, axis, split);
  const glm::dvec3 extent = centroids.hi - centroids.lo;
  std::uint32_t mid = begin;
  if (split.axis >= 0) {
    const double scale = kSahBins / extent[split.axis];
    const double lo = centroids.lo[split.axis];
    auto inLeft = [&](const BvhBuildItem& item) {
      return std::min(kSahBins - 1, int((item.centroid[split.axis] - lo) * scale)) <= split.bin;
    };
    mid = std::uint32_t(std::partition(first, last, inLeft) - items.begin());
  }
  if (mid != begin && mid != end) return mid;
  int axis = 0;
  if (extent.y > extent[axis]) axis = 1;
  if (extent.z > extent[axis]) axis = 2;
  mid = begin + (end - begin) / 2;
  std::nth_element(first, items.begin() + mid, last,
                   [axis](const BvhBuildItem& a, const BvhBuildItem& b) { return a.centroid[axis] < b.centroid[axis]; });
  return mid;
}

}  // namespace

TriangleBvh::TriangleBvh(const std::vector<glm::dvec3>& corners) {
  const std::size_t count = corners.size() / 3;
  std::vector<BvhBuildItem> items(count);
  for (std::size_t t = 0; t < count; ++t) {
    BvhBuildItem& item = items[t];
    for (int v = 0; v < 3; ++v) item.box.grow(corners[3 * t + std::size_t(v)]);
    item.centroid = (corners[3 * t] + corners[3 * t + 1] + corners[3 * t + 2]) / 3.0;
    item.index = std::uint32_t(t);
  }
  nodes_.reserve(2 * count);
  inputIndex_.reserve(count);
  build(items, 0, std::uint32_t(count), 0);
  nodes_.shrink_to_fit();

  // Leaves were given consecutive slots of inputIndex_; lay the triangles out in that order so a
  // leaf's triangles are adjacent in memory.
  triangles_.reserve(count);
  normals_.reserve(count);
  disks_.reserve(count);
  corners_.reserve(3 * count);
  for (std::uint32_t t = 0; t < count; ++t) {
    const std::size_t in = inputIndex_[t];
    const glm::dvec3& a = corners[3 * in];
    const glm::dvec3& b = corners[3 * in + 1];
    const glm::dvec3& c = corners[3 * in + 2];
    corners_.insert(corners_.end(), {a, b, c});
    triangles_.push_back({a, b - a, c - a});
    normals_.push_back(glm::normalize(glm::cross(b - a, c - a)));
    disks_.push_back(boundingDisk(a, b, c, normals_.back()));
  }
  // A subtree's triangles are contiguous in BVH order; find each node's range bottom-up.
  std::vector<std::uint32_t> first(nodes_.size());
  std::vector<std::uint32_t> last(nodes_.size());
  for (std::size_t i = nodes_.size(); i-- > 0;) {
    const BvhNode& node = nodes_[i];
    first[i] = node.isLeaf() ? node.rightOrFirst : first[i + 1];
    last[i] = node.isLeaf() ? node.rightOrFirst + node.count : last[node.rightOrFirst];
  }
  computeNodeBoxes(first, last);
  computeWindingData(first, last);
}

std::uint32_t TriangleBvh::build(std::vector<BvhBuildItem>& items, std::uint32_t begin, std::uint32_t end,
                                 int depth) {
  const std::uint32_t nodeIndex = std::uint32_t(nodes_.size());
  nodes_.emplace_back();
  if (end - begin <= kMaxLeafTriangles) {
    nodes_[nodeIndex].rightOrFirst = std::uint32_t(inputIndex_.size());
    nodes_[nodeIndex].count = end - begin;
    for (std::uint32_t i = begin; i < end; ++i) inputIndex_.push_back(items[i].index);
    return nodeIndex;
  }
  Box centroids;
  for (std::uint32_t i = begin; i < end; ++i) centroids.grow(items[i].centroid);
  const std::uint32_t mid = splitItems(items, begin, end, centroids, depth);
  build(items, begin, mid, depth + 1);
  const std::uint32_t right = build(items, mid, end, depth + 1);
  nodes_[nodeIndex].rightOrFirst = right;
  return nodeIndex;
}

void TriangleBvh::computeNodeBoxes(const std::vector<std::uint32_t>& first, const std::vector<std::uint32_t>& last) {
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const std::span<const glm::dvec3> points(corners_.data() + 3 * std::size_t(first[i]),
                                             3 * std::size_t(last[i] - first[i]));
    nodes_[i].box = tightBox(points);
  }
}

void TriangleBvh::computeWindingData(const std::vector<std::uint32_t>& first, const std::vector<std::uint32_t>& last) {
  const std::vector<glm::dvec3>& corners = corners_;
  winding_.resize(nodes_.size());
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    WindingNode& w = winding_[i];
    double area = 0.0;
    glm::dvec3 weighted(0.0);
    for (std::uint32_t t = first[i]; t < last[i]; ++t) {
      const glm::dvec3 areaVector = 0.5 * glm::cross(triangles_[t].ab, triangles_[t].ac);
      const double a = glm::length(areaVector);
      const glm::dvec3 centroid = (corners[3 * t] + corners[3 * t + 1] + corners[3 * t + 2]) / 3.0;
      area += a;
      weighted += a * centroid;
      w.areaNormal += areaVector;
    }
    w.centre = weighted / area;
    for (std::uint32_t t = first[i]; t < last[i]; ++t) {
      const glm::dvec3 areaVector = 0.5 * glm::cross(triangles_[t].ab, triangles_[t].ac);
      const glm::dvec3 centroid = (corners[3 * t] + corners[3 * t + 1] + corners[3 * t + 2]) / 3.0;
      // The centroid is the triangle's mean point, so this is the exact first moment of n dA.
      w.secondOrder += glm::outerProduct(areaVector, centroid - w.centre);
      for (int v = 0; v < 3; ++v) w.radius = std::max(w.radius, glm::length(corners[3 * t + std::size_t(v)] - w.centre));
    }
  }
}

double TriangleBvh::leafWinding(const glm::dvec3& q, const BvhNode& node) const {
  double angle = 0.0;
  for (std::uint32_t t = node.rightOrFirst; t < node.rightOrFirst + node.count; ++t)
    angle += solidAngle(q, corners_[3 * t], corners_[3 * t + 1], corners_[3 * t + 2]);
  return angle;
}

double TriangleBvh::windingNumber(const glm::dvec3& q, double beta) const {
  double angle = 0.0;  // 4 pi times the winding number
  std::array<std::uint32_t, kStackSize> stack;
  int top = 0;
  stack[top++] = 0;
  const double betaSquared = beta * beta;
  while (top > 0) {
    const std::uint32_t index = stack[--top];
    const WindingNode& w = winding_[index];
    const glm::dvec3 r = w.centre - q;
    const double r2 = glm::dot(r, r);
    if (r2 > betaSquared * w.radius * w.radius) {
      // Taylor expansion of the solid-angle kernel (x-q)/|x-q|^3 about the node centre.
      const double inv = 1.0 / std::sqrt(r2);
      const double inv3 = inv * inv * inv;
      const double inv5 = inv3 * inv * inv;
      const double trace = w.secondOrder[0][0] + w.secondOrder[1][1] + w.secondOrder[2][2];
      angle += glm::dot(r, w.areaNormal) * inv3 + trace * inv3 - 3.0 * glm::dot(r, w.secondOrder * r) * inv5;
      continue;
    }
    const BvhNode& node = nodes_[index];
    if (node.isLeaf()) {
      angle += leafWinding(q, node);
      continue;
    }
    stack[top++] = node.rightOrFirst;
    stack[top++] = index + 1;
  }
  return angle / (4.0 * std::numbers::pi);
}

double TriangleBvh::windingNumberExact(const glm::dvec3& q) const {
  double angle = 0.0;
  for (std::size_t t = 0; t < triangles_.size(); ++t)
    angle += solidAngle(q, corners_[3 * t], corners_[3 * t + 1], corners_[3 * t + 2]);
  return angle / (4.0 * std::numbers::pi);
}

}  // namespace hsdf::mesh
