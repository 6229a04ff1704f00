#pragma once
// Distance inside a solid made of closed parts pushed through each other (kitbashed assets, limbs
// through a torso), one mesh that intersects itself. Inside it the closest triangle may be a face
// of one part that runs inside another: the distance to it goes to zero there without a change of
// sign, a tangential zero that samples and cell classification take for a surface (grooves along
// the parts' intersection curves). Inside, the field is instead the union of the parts' own
// signed distances: -max, over the parts containing p, of the distance to that part's surface.
//
// Why it is right: a point q outside the union is outside every part, so |p - q| is at least the
// distance from p to the surface of each part containing p: the value is a lower bound of the
// distance to the union's boundary, continuous (a part starts containing p where its distance is
// zero, below the others'), zero only on the boundary, and exact where the deepest part's closest
// point lies on the boundary (everywhere but near the concave intersection curves). Its gradient
// is that part's (p - closest) / distance. Outside the union nothing changes: the closest point c
// of the whole mesh to an outside p is on the boundary (the segment from p to c meets no triangle,
// so c touches the outside), and the boundary is part of the mesh, so |p - c| is exact.
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "source/mesh_bvh.h"
#include "source/mesh_closest.h"

namespace hsdf::mesh {

class PartUnion {
 public:
  // The parts of a closed mesh (vertexOf: welded vertex ids of the BVH's corners). Null unless it
  // has two parts or more and each part's own inside is behind its faces (own winding number 1
  // behind, 0 in front): a part turned inside out (a hollow's inner wall) is a hole, which a union
  // of parts cannot express.
  static std::unique_ptr<PartUnion> create(const TriangleBvh& bvh, const std::vector<std::uint32_t>& vertexOf,
                                           double windingBeta);
  ~PartUnion();
  PartUnion(const PartUnion&) = delete;
  PartUnion& operator=(const PartUnion&) = delete;

  // Of the parts containing p (own winding number >= 1/2), the closest point on the surface of the
  // one whose surface is farthest, if farther than sqrt(beyondSquared); its triangle in the whole
  // mesh's BVH order. Otherwise triangle == UINT32_MAX.
  ClosestHit deepest(const glm::dvec3& p, double beyondSquared) const;

  std::size_t partCount() const { return parts_.size(); }

 private:
  struct Part;
  PartUnion(std::vector<std::unique_ptr<Part>> parts, double windingBeta);
  std::vector<std::unique_ptr<Part>> parts_;
  double windingBeta_ = 2.0;
};

}  // namespace hsdf::mesh
