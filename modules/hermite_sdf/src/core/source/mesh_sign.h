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
#include <span>
#include <utility>
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

// How the connected parts of a closed mesh that does not intersect itself sit in the solid of
// nonzero winding number, from points just off each part's largest triangle on either side.
struct PartSides {
  // Every part faces the region of winding number 0 (its normals' side is outside): pseudonormals
  // then sign each part's own inside, which is the solid's. It fails for a part nested in another
  // with the same orientation (a box inside a box: between them the winding number is 1, yet the
  // inner box's pseudonormals say outside, and the field jumps sign there without a surface) and
  // for a part turned inside out (its normals point into winding number -1). A hollow passes.
  bool faceOutside = true;
  // BVH triangles of the parts with a nonzero winding number on both sides: inside the solid, not
  // on its boundary (the inner box of two nested ones).
  std::vector<std::uint32_t> interior;
};
PartSides partSides(const TriangleBvh& bvh, const std::vector<std::uint32_t>& vertexOf, double windingBeta);

// The BVH triangles of a mesh with boundary edges whose connected part bounds no volume. A part
// bounds one alone when across at least half of its area (sampled) its own winding number (of its
// triangles alone) goes decisively from one side of 1/2 to the other: a closed part's goes from 0
// to 1 everywhere, also where it runs inside another part or beside a large sheet, whose winding
// numbers the whole mesh's would add; a bowl's, or a closed surface's with a hole, does across most
// of its area. An open sheet's (a terrain, a plane, a foliage card: about 1/2 under it and -1/2 over
// it) and triangles doubled with both windings (0 on both sides) do not. Parts that bound nothing
// alone are kept if, together, they separate across three quarters of each one's area (a tube and
// caps on corners of their own); crossed cards separate about half.
std::vector<std::uint32_t> partsBoundingNothing(const TriangleBvh& bvh, const std::vector<std::uint32_t>& vertexOf,
                                                double windingBeta);

// The BVH triangles of each connected part (triangles joined by welded vertices), in BVH order.
std::vector<std::vector<std::uint32_t>> connectedPartTriangles(const TriangleBvh& bvh,
                                                               const std::vector<std::uint32_t>& vertexOf);

// The largest (by area) of BVH triangles `triangles`, the first of equals: the points just off it
// are farthest from its edges. UINT32_MAX for none.
std::uint32_t largestTriangle(const TriangleBvh& bvh, std::span<const std::uint32_t> triangles);

// The corners of BVH triangles `triangles`, three per triangle: a BVH of these alone.
std::vector<glm::dvec3> cornersOf(const TriangleBvh& bvh, const std::vector<std::uint32_t>& triangles);

// The winding numbers just in front of and just behind triangle t at its centroid, a step off it
// far less than any part's thickness.
std::pair<double, double> windingBothSides(const TriangleBvh& bvh, std::uint32_t t, double windingBeta);

}  // namespace hsdf::mesh
