#pragma once
// Binary bounding volume hierarchy over a triangle mesh (binned SAH): answers the generalized
// winding number (sign) and is the skeleton of the 4-wide closest-point tree (mesh_closest.h).
// Built once, then read-only, so queries from many threads need no locking.
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

#include "source/mesh_geometry.h"

namespace hsdf::mesh {

// Nodes are stored depth first: an inner node's left child follows it, `rightOrFirst` names its
// right child. A leaf (count > 0) holds triangles [rightOrFirst, rightOrFirst + count) of the
// BVH-ordered triangle arrays. Each node is bounded by an oriented box (the tighter of its PCA box
// and its axis-aligned box): a patch of surface is thin along its normal, and an oriented box's
// distance bound then rises as fast as the surface's own distance away from the closest point,
// which an axis-aligned box's does not (most of the pruning power for far queries).
struct BvhNode {
  OrientedBox box;
  std::uint32_t rightOrFirst = 0;
  std::uint32_t count = 0;
  bool isLeaf() const { return count > 0; }
};

// Far-field data of a node for the fast winding number (Barill et al. 2018): the node's triangles
// seen from afar are a dipole at `centre` (order 1: `areaNormal`) plus a quadrupole-like order-2
// term `secondOrder` = sum over triangles of area * normal (outer) (centroid - centre).
struct WindingNode {
  glm::dvec3 centre{0.0};
  double radius = 0.0;  // max distance from centre to any vertex of the node's triangles
  glm::dvec3 areaNormal{0.0};
  glm::dmat3 secondOrder{0.0};  // column k, row j: sum a * (c - centre)_k * n_j
};

struct BvhBuildItem;  // a triangle while the tree is built: its box, centroid and index (mesh_bvh.cpp)

class TriangleBvh {
 public:
  // triangles: vertex positions, three per triangle, every triangle with non-zero area.
  explicit TriangleBvh(const std::vector<glm::dvec3>& corners);

  std::size_t triangleCount() const { return triangles_.size(); }
  std::size_t nodeCount() const { return nodes_.size(); }
  const BvhNode& root() const { return nodes_.front(); }
  // Index of triangle t (BVH order) in the input order.
  std::uint32_t inputIndex(std::uint32_t t) const { return inputIndex_[t]; }
  const PreparedTriangle& triangle(std::uint32_t t) const { return triangles_[t]; }
  const glm::dvec3& unitNormal(std::uint32_t t) const { return normals_[t]; }

  const std::vector<BvhNode>& nodes() const { return nodes_; }
  const TriangleDisk& disk(std::uint32_t t) const { return disks_[t]; }
  // Corner k of triangle t (BVH order); all corners, three per triangle, in corners().
  const glm::dvec3& corner(std::uint32_t t, int k) const { return corners_[3 * std::size_t(t) + std::size_t(k)]; }
  const std::vector<glm::dvec3>& corners() const { return corners_; }

  // Generalized winding number at q: exact solid angles near q, the order-2 far-field expansion
  // for nodes farther than beta times their radius.
  double windingNumber(const glm::dvec3& q, double beta) const;

  // Exact generalized winding number: every triangle's solid angle (slow, for verification).
  double windingNumberExact(const glm::dvec3& q) const;

 private:
  std::uint32_t build(std::vector<BvhBuildItem>& items, std::uint32_t begin, std::uint32_t end, int depth);
  void computeNodeBoxes(const std::vector<std::uint32_t>& first, const std::vector<std::uint32_t>& last);
  void computeWindingData(const std::vector<std::uint32_t>& first, const std::vector<std::uint32_t>& last);
  double leafWinding(const glm::dvec3& q, const BvhNode& node) const;

  std::vector<BvhNode> nodes_;
  std::vector<WindingNode> winding_;     // parallel to nodes_
  std::vector<PreparedTriangle> triangles_;  // BVH order
  std::vector<glm::dvec3> normals_;      // BVH order, unit length
  std::vector<TriangleDisk> disks_;      // BVH order
  std::vector<glm::dvec3> corners_;      // BVH order, three per triangle (for solid angles)
  std::vector<std::uint32_t> inputIndex_;
};

}  // namespace hsdf::mesh
