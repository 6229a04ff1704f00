#pragma once
// Closest-point queries on a triangle mesh: a 4-wide tree collapsed from the binary BVH.
//
// Why 4-wide and float: a dense bake asks for the exact distance at millions of points, most of
// them far from the surface, where a query must open every node whose bound is below the distance
// (the surface "cap" around the closest point). The cost is then dominated by bound tests, which
// here run on four children (or four triangles) at once from one contiguous block of floats the
// compiler vectorises. Bounds are computed in float relative to the mesh centre, in units of the
// mesh radius (rounded to a power of two), and used only to prune, with a margin that covers their
// rounding; the closest point itself is always computed in double on the exact triangle, so results
// are exact to double rounding. The unit keeps squared float bounds in range at every mesh scale (a
// mesh 1e30 across would overflow float squares in world units, one 1e-30 across underflow them).
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

#include "source/mesh_bvh.h"
#include "source/mesh_geometry.h"

namespace hsdf::mesh {

struct ClosestHit {
  double distanceSquared = std::numeric_limits<double>::infinity();
  glm::dvec3 point{0.0};
  std::uint32_t triangle = UINT32_MAX;  // BVH order; UINT32_MAX when nothing beat the bound
  Feature feature = Feature::Face;      // where on the triangle the closest point lies
  double prunedBoundSquared = std::numeric_limits<double>::infinity();  // see closest()
};

class ClosestPointTree {
 public:
  explicit ClosestPointTree(const TriangleBvh& bvh);

  // The closest point of the mesh to p: of the triangles at the smallest distance, the one of lowest
  // index (BVH order), whatever the seed. `seed` is either a hit already known (distanceTo: the
  // result is that triangle unless another is closer or as close with a lower index) or, with no
  // triangle, a strict bound (hit.triangle == UINT32_MAX when nothing is closer than
  // sqrt(seed.distanceSquared); never with an infinite bound, even for a p so far away that its
  // float bounds overflow).
  // Why the tie rule: the seed comes from the previous queries of the calling thread, and points
  // equidistant from two faces (a cube's medial planes) are common on grids. With "the seed unless
  // something is strictly closer", such a sample's gradient depended on which slab that thread had
  // baked before: the bake differed from run to run with the scheduling (the 108-object scene drew
  // 5-15 different pixels under load).
  ClosestHit closest(const glm::dvec3& p, const ClosestHit& seed) const;
  ClosestHit closest(const glm::dvec3& p, double boundSquared) const;
  // The same, and when no triangle is found, hit.prunedBoundSquared is a lower bound on the squared
  // distance from p to the mesh, itself >= the bound (costs a little more bookkeeping).
  ClosestHit closestOrBound(const glm::dvec3& p, const ClosestHit& seed) const;

  // Squared distance from p to triangle t (BVH order) and the closest point on it.
  ClosestHit distanceTo(const glm::dvec3& p, std::uint32_t t) const;

 private:
  static constexpr int kLanes = 4;
  // Up to four children; lane i bounds child i by an oriented box. An unused lane has a negative
  // extent (its bound is +inf).
  struct Node {
    float centre[3][kLanes];
    float axis[3][3][kLanes];  // axis a, component c
    float halfExtent[3][kLanes];
    std::int32_t child[kLanes];  // >= 0: node index; < 0: ~leaf index
    int count = 0;               // lanes in use
  };
  // Up to four triangles with their bounding disks; an unused lane has a negative radius.
  struct Leaf {
    float centre[3][kLanes];
    float normal[3][kLanes];
    float radius[kLanes];
    std::uint32_t first = 0;  // BVH-order index of lane 0's triangle
    std::uint32_t count = 0;
  };

  // State of one query: the best hit so far, the float bound below which a node may still hold
  // something closer, and the smallest bounds of everything pruned (float bounds still carrying
  // the rounding margin; exact squared distances of triangles that lost).
  struct Search {
    ClosestHit hit;
    float threshold = std::numeric_limits<float>::infinity();
    float prunedFloat = std::numeric_limits<float>::infinity();
    double prunedExact = std::numeric_limits<double>::infinity();
  };

  std::int32_t collapse(const TriangleBvh& bvh, std::uint32_t binaryNode);
  std::int32_t addLeaf(const TriangleBvh& bvh, const BvhNode& binaryLeaf);
  void setLane(Node& node, int lane, const OrientedBox* box) const;
  template <bool kTrackPruned>
  ClosestHit find(const glm::dvec3& p, const ClosestHit& seed) const;
  ClosestHit closestByScan(const glm::dvec3& p) const;
  float pruneThreshold(double bestSquared, double margin) const;
  double trueBoundSquared(float boundF, double margin) const;
  template <bool kTrackPruned>
  void visitLeaf(const Leaf& leaf, const glm::dvec3& p, const float q[3], double margin, Search& search) const;

  glm::dvec3 origin_{0.0};  // float coordinates are relative to it (the mesh centre)
  double radius_ = 0.0;     // of the mesh around origin_, for the rounding margin
  double unit_ = 1.0;       // float coordinates are in this unit: a power of two near radius_
  double inverseUnit_ = 1.0;  // exact (a power of two): queries multiply instead of dividing
  std::vector<Node> nodes_;
  std::vector<Leaf> leaves_;
  std::vector<PreparedTriangle> triangles_;  // BVH order
};

}  // namespace hsdf::mesh
