#include "source/mesh_closest.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace hsdf::mesh {
namespace {

// Four float lanes (GCC/Clang vector extensions: SSE on x86-64, NEON on ARM, plain code elsewhere).
using Float4 = float __attribute__((vector_size(16)));
using Int4 = std::int32_t __attribute__((vector_size(16)));

Float4 load4(const float* p) {
  Float4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
Float4 splat4(float x) { return Float4{x, x, x, x}; }
Float4 max0(Float4 a) { return (Float4)((Int4)a & (Int4)(a > splat4(0.0f))); }
Float4 abs4(Float4 a) { return (Float4)((Int4)a & Int4{0x7fffffff, 0x7fffffff, 0x7fffffff, 0x7fffffff}); }
Float4 sqrt4(Float4 a) {
#if defined(__SSE__)
  return (Float4)_mm_sqrt_ps((__m128)a);
#else
  return Float4{std::sqrt(a[0]), std::sqrt(a[1]), std::sqrt(a[2]), std::sqrt(a[3])};
#endif
}

// Float bounds are off by a few float ulps of the coordinates involved (at most ~1e-6 of the mesh
// radius plus the query's distance from the mesh centre); a pruning margin 10x larger keeps every
// prune safe at a negligible loss of pruning power.
constexpr double kRelativeMargin = 1e-5;
// Stack bound: the wide tree is no deeper than the binary one (depth <= ~75, see mesh_bvh.cpp) and
// each visited node pushes at most 3 entries beyond the one it replaces.
constexpr int kStackSize = 256;
// Farthest float query coordinate, in mesh units: its square summed over three axes stays finite.
constexpr double kFarthest = 1e18;
constexpr float kUnusedExtent = -1e30f;  // gives an unused lane an infinite bound
constexpr float kInfinityF = std::numeric_limits<float>::infinity();
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Whether triangle t at squared distance d2 replaces `best`: closer, or as close with a lower index
// (never a bare bound, which only points strictly closer beat). The margin in the prune threshold
// keeps every triangle at the best distance in the traversal, so the order (d2, t) decides alone.
bool beats(double d2, std::uint32_t t, const ClosestHit& best) {
  return d2 < best.distanceSquared ||
         (d2 == best.distanceSquared && best.triangle != UINT32_MAX && t < best.triangle);
}

double halfArea(const OrientedBox& box) {
  const glm::dvec3& e = box.halfExtent;
  return e.x * e.y + e.y * e.z + e.z * e.x;
}

// Lanes with bounds below the threshold; nearest first when `sorted` (worth it only while the
// bound is still loose: testing the nearest candidate first is what tightens it).
int lanesBelow(const float (&bound)[4], float threshold, bool sorted, int (&order)[4]) {
  int n = 0;
  for (int lane = 0; lane < 4; ++lane) {
    if (!(bound[lane] < threshold)) continue;
    int at = n++;
    if (!sorted) {
      order[at] = lane;
      continue;
    }
    while (at > 0 && bound[order[at - 1]] > bound[lane]) {
      order[at] = order[at - 1];
      --at;
    }
    order[at] = lane;
  }
  return n;
}

}  // namespace

ClosestPointTree::ClosestPointTree(const TriangleBvh& bvh) {
  const BvhNode& root = bvh.nodes().front();
  origin_ = root.box.centre;
  triangles_.reserve(bvh.triangleCount());
  for (std::uint32_t t = 0; t < bvh.triangleCount(); ++t) {
    const PreparedTriangle& tri = bvh.triangle(t);
    triangles_.push_back(tri);
    for (const glm::dvec3& corner : {tri.a, tri.a + tri.ab, tri.a + tri.ac})
      radius_ = std::max(radius_, glm::length(corner - origin_));
  }
  // A power of two, so that scaling by it is exact; radius_ > 0 since no triangle has zero area.
  unit_ = std::ldexp(1.0, std::ilogb(radius_));
  inverseUnit_ = 1.0 / unit_;
  nodes_.reserve(bvh.nodeCount() / 2 + 1);
  leaves_.reserve(bvh.nodeCount() / 2 + 1);
  if (root.isLeaf()) {
    nodes_.emplace_back();
    for (int lane = 0; lane < kLanes; ++lane) setLane(nodes_[0], lane, nullptr);
    setLane(nodes_[0], 0, &root.box);
    nodes_[0].child[0] = addLeaf(bvh, root);
    nodes_[0].count = 1;
  } else {
    collapse(bvh, 0);
  }
}

// box == nullptr marks the lane unused.
void ClosestPointTree::setLane(Node& node, int lane, const OrientedBox* box) const {
  const OrientedBox unit;
  const OrientedBox& b = box ? *box : unit;
  const glm::dvec3 centre = box ? (b.centre - origin_) / unit_ : glm::dvec3(0.0);
  for (int c = 0; c < 3; ++c) {
    node.centre[c][lane] = float(centre[c]);
    node.halfExtent[c][lane] = box ? float(b.halfExtent[c] / unit_) : kUnusedExtent;
    for (int a = 0; a < 3; ++a) node.axis[a][c][lane] = float(b.axes[a][c]);
  }
  node.child[lane] = 0;
}

// Pulls grandchildren up until the node has four children (or only leaves are left), always
// opening the child with the largest box: the widest children are the least selective.
std::int32_t ClosestPointTree::collapse(const TriangleBvh& bvh, std::uint32_t binaryNode) {
  const std::vector<BvhNode>& binary = bvh.nodes();
  std::uint32_t slots[kLanes] = {binaryNode + 1, binary[binaryNode].rightOrFirst, 0, 0};
  int used = 2;
  while (used < kLanes) {
    int widest = -1;
    for (int s = 0; s < used; ++s) {
      if (!binary[slots[s]].isLeaf() && (widest < 0 || halfArea(binary[slots[s]].box) > halfArea(binary[slots[widest]].box)))
        widest = s;
    }
    if (widest < 0) break;
    const std::uint32_t opened = slots[widest];
    slots[widest] = opened + 1;
    slots[used++] = binary[opened].rightOrFirst;
  }
  const std::int32_t index = std::int32_t(nodes_.size());
  nodes_.emplace_back();
  for (int lane = 0; lane < kLanes; ++lane) setLane(nodes_[std::size_t(index)], lane, nullptr);
  nodes_[std::size_t(index)].count = used;
  for (int lane = 0; lane < used; ++lane) {
    const BvhNode& child = binary[slots[lane]];
    const std::int32_t ref = child.isLeaf() ? addLeaf(bvh, child) : collapse(bvh, slots[lane]);
    setLane(nodes_[std::size_t(index)], lane, &child.box);  // after the recursion: nodes_ may have moved
    nodes_[std::size_t(index)].child[lane] = ref;
  }
  return index;
}

std::int32_t ClosestPointTree::addLeaf(const TriangleBvh& bvh, const BvhNode& binaryLeaf) {
  Leaf leaf;
  leaf.first = binaryLeaf.rightOrFirst;
  leaf.count = binaryLeaf.count;
  for (std::uint32_t lane = 0; lane < std::uint32_t(kLanes); ++lane) {
    const bool used = lane < binaryLeaf.count;
    const TriangleDisk disk = used ? bvh.disk(binaryLeaf.rightOrFirst + lane) : TriangleDisk{};
    const glm::dvec3 centre = used ? (disk.centre - origin_) / unit_ : glm::dvec3(0.0);
    for (int c = 0; c < 3; ++c) {
      leaf.centre[c][lane] = float(centre[c]);
      leaf.normal[c][lane] = float(disk.normal[c]);
    }
    leaf.radius[lane] = used ? float(disk.radius / unit_) : kUnusedExtent;
  }
  leaves_.push_back(leaf);
  return ~std::int32_t(leaves_.size() - 1);
}

// Float bounds (in units of unit_, squared) below this value may hide something closer than
// sqrt(bestSquared) (world units).
float ClosestPointTree::pruneThreshold(double bestSquared, double margin) const {
  if (!std::isfinite(bestSquared)) return kInfinityF;
  const double reach = (std::sqrt(bestSquared) + margin) * inverseUnit_;
  return float(reach * reach);
}

// Undoes the unit and the margin: a true lower bound on the squared world distance from a float
// bound (an overflowed bound, +inf, stands for "at least the largest float").
double ClosestPointTree::trueBoundSquared(float boundF, double margin) const {
  const double bound = std::min(double(boundF), double(std::numeric_limits<float>::max()));
  const double reach = std::max(std::sqrt(bound) * unit_ - margin, 0.0);
  return reach * reach;
}

ClosestHit ClosestPointTree::distanceTo(const glm::dvec3& p, std::uint32_t t) const {
  ClosestHit hit;
  const TrianglePoint closest = closestPointOnTriangle(p, triangles_[t]);
  hit.point = closest.point;
  hit.feature = closest.feature;
  hit.distanceSquared = glm::dot(p - hit.point, p - hit.point);
  hit.triangle = t;
  return hit;
}

template <bool kTrackPruned>
void ClosestPointTree::visitLeaf(const Leaf& leaf, const glm::dvec3& p, const float q[3], double margin,
                                 Search& search) const {
  ClosestHit& hit = search.hit;
  const Float4 nx = load4(leaf.normal[0]), ny = load4(leaf.normal[1]), nz = load4(leaf.normal[2]);
  const Float4 vx = splat4(q[0]) - load4(leaf.centre[0]);
  const Float4 vy = splat4(q[1]) - load4(leaf.centre[1]);
  const Float4 vz = splat4(q[2]) - load4(leaf.centre[2]);
  const Float4 along = vx * nx + vy * ny + vz * nz;
  const Float4 wx = vx - along * nx, wy = vy - along * ny, wz = vz - along * nz;
  const Float4 beyond = max0(sqrt4(wx * wx + wy * wy + wz * wz) - load4(leaf.radius));
  float bound[kLanes];
  const Float4 bound4 = along * along + beyond * beyond;
  std::memcpy(bound, &bound4, sizeof bound);
  int order[kLanes];
  const int n = lanesBelow(bound, search.threshold, search.threshold == kInfinityF, order);
  for (int k = 0; k < n; ++k) {
    if (!(bound[order[k]] < search.threshold)) continue;  // an earlier lane tightened the threshold
    const std::uint32_t t = leaf.first + std::uint32_t(order[k]);
    const TrianglePoint c = closestPointOnTriangle(p, triangles_[t]);
    const double d2 = glm::dot(p - c.point, p - c.point);
    if (beats(d2, t, hit)) {
      hit.distanceSquared = d2;
      hit.point = c.point;
      hit.feature = c.feature;
      hit.triangle = t;
      search.threshold = pruneThreshold(d2, margin);
    } else if constexpr (kTrackPruned) {
      search.prunedExact = std::min(search.prunedExact, d2);
    }
  }
  if constexpr (kTrackPruned) {
    for (std::uint32_t lane = 0; lane < leaf.count; ++lane) {
      if (!(bound[lane] < search.threshold)) search.prunedFloat = std::min(search.prunedFloat, bound[lane]);
    }
  }
}

template <bool kTrackPruned>
ClosestHit ClosestPointTree::find(const glm::dvec3& p, const ClosestHit& seed) const {
  const double boundSquared = seed.distanceSquared;
  Search search;
  ClosestHit& hit = search.hit;
  hit = seed;
  hit.prunedBoundSquared = std::numeric_limits<double>::infinity();
  const glm::dvec3 local = p - origin_;
  glm::dvec3 scaled = local * inverseUnit_;
  // A query more than ~1e38 mesh sizes away (a shell far thicker than a tiny mesh) overflowed the
  // float coordinates, and the bounds became inf and NaN. Moved toward the mesh along the same line,
  // to kFarthest units, it is nearer every box than p is (the boxes lie within 2 units of origin_),
  // so the bounds stay lower bounds and nothing is pruned wrongly; distances are taken from p.
  if (const double far = glm::length(scaled); far > kFarthest) scaled *= kFarthest / far;
  const float q[3] = {float(scaled.x), float(scaled.y), float(scaled.z)};
  const double margin = kRelativeMargin * (radius_ + glm::length(local));
  search.threshold = pruneThreshold(boundSquared, margin);

  struct Entry {
    std::int32_t child;
    float bound;
  };
  Entry stack[kStackSize];
  int top = 0;
  stack[top++] = {0, 0.0f};
  while (top > 0) {
    const Entry entry = stack[--top];
    if (!(entry.bound < search.threshold)) {
      if constexpr (kTrackPruned) search.prunedFloat = std::min(search.prunedFloat, entry.bound);
      continue;
    }
    if (entry.child < 0) {
      visitLeaf<kTrackPruned>(leaves_[std::size_t(~entry.child)], p, q, margin, search);
      continue;
    }
    const Node& node = nodes_[std::size_t(entry.child)];
    const Float4 vx = splat4(q[0]) - load4(node.centre[0]);
    const Float4 vy = splat4(q[1]) - load4(node.centre[1]);
    const Float4 vz = splat4(q[2]) - load4(node.centre[2]);
    Float4 sum = splat4(0.0f);
    for (int a = 0; a < 3; ++a) {
      const Float4 along = vx * load4(node.axis[a][0]) + vy * load4(node.axis[a][1]) + vz * load4(node.axis[a][2]);
      const Float4 outside = max0(abs4(along) - load4(node.halfExtent[a]));
      sum += outside * outside;
    }
    float bound[kLanes];
    std::memcpy(bound, &sum, sizeof bound);
    if constexpr (kTrackPruned) {
      for (int lane = 0; lane < node.count; ++lane) {
        if (!(bound[lane] < search.threshold)) search.prunedFloat = std::min(search.prunedFloat, bound[lane]);
      }
    }
    if (search.threshold == kInfinityF) {
      // No bound yet: nearest child on top of the stack, so the first leaves tighten it fastest.
      int order[kLanes];
      const int n = lanesBelow(bound, search.threshold, true, order);
      for (int k = n; k-- > 0;) stack[top++] = {node.child[order[k]], bound[order[k]]};
    } else {
      // Bounded (the usual, seeded case): order hardly matters, so push without branches.
      for (int lane = 0; lane < kLanes; ++lane) {
        stack[top] = {node.child[lane], bound[lane]};
        top += bound[lane] < search.threshold ? 1 : 0;
      }
    }
  }
  // Every float bound overflowed (p is some 1e19 mesh radii away): nothing could be pruned safely.
  if (hit.triangle == UINT32_MAX && std::isinf(boundSquared)) return closestByScan(p);
  if (hit.triangle == UINT32_MAX) hit.distanceSquared = kInfinity;
  hit.prunedBoundSquared =
      kTrackPruned ? std::min(search.prunedExact, trueBoundSquared(search.prunedFloat, margin)) : 0.0;
  return hit;
}

ClosestHit ClosestPointTree::closestByScan(const glm::dvec3& p) const {
  ClosestHit best;
  for (std::uint32_t t = 0; t < triangles_.size(); ++t) {
    const ClosestHit hit = distanceTo(p, t);
    if (best.triangle == UINT32_MAX || beats(hit.distanceSquared, t, best)) best = hit;
  }
  return best;
}

ClosestHit ClosestPointTree::closest(const glm::dvec3& p, const ClosestHit& seed) const { return find<false>(p, seed); }

ClosestHit ClosestPointTree::closest(const glm::dvec3& p, double boundSquared) const {
  ClosestHit bound;
  bound.distanceSquared = boundSquared;
  return find<false>(p, bound);
}

ClosestHit ClosestPointTree::closestOrBound(const glm::dvec3& p, const ClosestHit& seed) const {
  return find<true>(p, seed);
}

}  // namespace hsdf::mesh
