#pragma once
// Inside/outside near the surface of a closed mesh from the closest feature's pseudonormal
// (Baerentzen & Aanaes 2005): for a closed, consistently oriented mesh that does not intersect
// itself, p is inside iff (p - closest) . n < 0, where n is the face normal when the closest point
// lies inside a face, the sum of the two face normals on an edge, and the angle-weighted sum of
// the incident face normals at a vertex. It costs nothing beyond the closest point, unlike the
// winding number, but is only valid under those conditions, which meshTopologyAllowsPseudoNormals
// checks; other meshes keep the winding number.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "source/mesh_bvh.h"
#include "source/mesh_geometry.h"

namespace hsdf::mesh {

class PseudoNormals {
 public:
  // vertexOf: welded vertex ids of the BVH's corners (BVH order, three per triangle); the mesh
  // must be closed (every edge shared by exactly two oppositely oriented triangles).
  PseudoNormals(const TriangleBvh& bvh, const std::vector<std::uint32_t>& vertexOf);

  const glm::dvec3& normal(std::uint32_t triangle, Feature feature) const {
    return normals_[triangle][std::size_t(feature)];
  }

 private:
  std::vector<std::array<glm::dvec3, kFeatureCount>> normals_;  // BVH order, indexed by Feature
};

// True if two triangles that share no vertex touch or cross (edges of one through the other,
// touching counted as crossing). Coplanar overlaps are not detected (such duplicated faces
// already make a mesh non-closed).
bool hasSelfIntersections(const TriangleBvh& bvh, const std::vector<std::uint32_t>& vertexOf);

}  // namespace hsdf::mesh
