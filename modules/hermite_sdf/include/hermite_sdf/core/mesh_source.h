#pragma once
// MeshSource: signed distance to a triangle mesh.
//
// - Distance: exact unsigned distance to the closest point of any triangle (BVH, double precision).
//   Except inside a closed mesh of parts pushed through each other (self-intersecting, each part
//   facing outward): there the closest triangle may be a face of one part running inside another,
//   whose distance goes to zero without a sign change (grooves along the intersection curves), so
//   the value is instead -max, over the parts whose own winding number contains p, of the distance
//   to that part's surface (the parts' union; each part has its own BVH): a lower bound of the
//   distance to the solid's boundary, continuous, zero only on it (src/core/source/mesh_union.h).
//   Outside, the closest triangle lies on the boundary, so the distance there is exact.
// - Sign: inside where the generalized winding number is >= 0.5 (Jacobson et al. 2013), evaluated
//   hierarchically (Barill et al. 2018: exact solid angles near the query, an order-2 far-field
//   expansion for distant BVH nodes). The winding number of a closed mesh is 1 inside and 0
//   outside; small cracks, holes and flipped triangles only perturb it near the defect, so the
//   sign stays right away from it. Open meshes (a single sheet, a cup) get the sign of their
//   winding number too: inside is where the surface, closed by its minimal "membrane", wraps the
//   point more than halfway. A connected part (triangles joined by welded vertices) of a mesh with
//   boundary edges is dropped when it bounds no volume: when its own winding number, of its
//   triangles alone, does not go decisively from below 1/2 to above across most of it (an open
//   sheet: a floor plane, a decal, crossed foliage cards), unless such parts close a volume together
//   (a tube and cap disks on corners of their own). Its own, not the whole mesh's: a closed arm
//   pushed through a torso lies where the whole mesh's goes from 1 to 2, and a large floor adds
//   about 1/2 to the whole mesh's near the objects on it. A mesh of nothing else is refused.
//   Fast path: for a mesh that is closed (every edge shared by exactly two oppositely oriented
//   triangles, vertices welded by position; where equal positions leave edges unpaired, also
//   positions within 4 float ulps of the mesh's size, a seam computed twice with trigonometry)
//   and does not intersect itself, the winding-number sign equals the sign given by the
//   pseudonormal of the closest feature (Baerentzen & Aanaes 2005), which costs nothing beyond the
//   closest point; such meshes use it (SignMode::Auto).
//   Meshes with defects, open meshes and self-intersecting ones (e.g. overlapping closed parts)
//   use the winding number.
// - Gradient: (p - closest) / |p - closest| times the sign (closest: the point the distance is
//   measured to, the deepest part's inside overlapping parts); on the surface itself (distance below
//   1e-12 of the mesh size) the unit normal of the closest feature: the face's, or on an edge or a
//   vertex its pseudonormal where the mesh has them (else the closest triangle's normal).
// - Shells (MeshSourceOptions::shellThickness): |d| - thickness / 2 with the same distance, and no
//   sign at all: for surfaces without an inside.
// - Degenerate input: no triangles, an index count that is not a multiple of 3, indices out of
//   range, NaN/inf coordinates are errors naming the problem. Zero-area triangles (repeated
//   vertices, collinear corners: height below 1e-12 of the longest edge) are dropped: they bound
//   no area, so they change neither the distance of a closed mesh (their edges belong to
//   neighbours) nor its winding number.
//
// Speed: every query starts its BVH search bounded by the distance to the previous query's (on
// the same thread, or in the same row) closest triangle. Where the winding number is needed, a
// query inside the ball of radius |d| around a recent query reuses that query's sign: no surface
// crosses the ball, so for a closed mesh the sign is the same. For meshes with boundary edges the
// winding number varies continuously, so a sign is reused only from queries whose winding number
// was decisive (at least 0.25 away from 0.5); set reuseSign = false for a sign computed at every
// point. Results do not depend on the order or thread of queries, except that near the defects of
// a defective mesh a reused sign may differ from a fresh one.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/expected.h"
#include "engine/scene/scene_data.h"
#include "hermite_sdf/core/source.h"

namespace hsdf {

enum class SignMode {
  Auto,           // pseudonormals for closed, self-intersection-free meshes, else the winding number
  WindingNumber,  // always the winding number
};

struct MeshSourceOptions {
  SignMode signMode = SignMode::Auto;
  // Far-field expansion of a BVH node is used when the query is farther than beta times the
  // node's radius from its centre (Barill et al. use 2; larger is more accurate and slower).
  double windingBeta = 2.0;
  // Reuse the sign of a recent query whose surface-free ball contains the point (see above).
  bool reuseSign = true;
  // The material slot of each input triangle (materials.h, MeshMaterials::triangleSlots), for a
  // mesh of several materials: each sample then reports its closest triangle's slot. Empty: one
  // material (samples report slot 0 and materialSlots() is 0).
  std::vector<std::uint8_t> triangleSlots;
  // Above 0: the mesh is a shell of this thickness around its triangles, f = |d| - thickness / 2,
  // for surfaces with no inside (zero-thickness walls, cloth, cards, an open cup) that the
  // winding number would fill (a cup baked solid to its rim) or refuse (a sheet bounds no volume).
  // Nothing is signed or dropped: no winding number is computed. The field is exact outside the
  // shell; its middle (on the triangles) is a crease of f = -thickness / 2, where no surface is.
  // A shell thinner than a grid cell bakes rough, and with holes when far thinner: both of its faces
  // then lie between the same samples.
  double shellThickness = 0.0;
};

struct MeshSourceStats {
  std::size_t inputTriangles = 0;
  std::size_t droppedZeroArea = 0;   // dropped because their area is zero
  std::size_t triangles = 0;         // kept, in the BVH
  std::size_t boundaryEdges = 0;     // edges (after welding, see above) without an opposite twin
  bool closed = false;               // every edge has exactly one oppositely oriented twin
  bool selfIntersecting = false;     // two triangles without a common vertex touch (closed meshes only)
  bool pseudoNormalSign = false;     // the sign comes from pseudonormals (else the winding number)
  // Closed, not self-intersecting, yet a part is nested in another with the same orientation or
  // turned inside out: pseudonormals would sign it wrongly, the winding number (nonzero) signs it.
  bool partsMisoriented = false;
  // Triangles of parts with the solid on both sides (the inner of two boxes nested with the same
  // orientation): not its boundary, so dropped; counted in inputTriangles, not in triangles.
  std::size_t droppedInterior = 0;
  // Triangles of open parts that bound no volume (mesh_sign.h, partsBoundingNothing: a floor quad
  // beside a closed ball, crossed foliage cards), dropped; counted in inputTriangles, not in
  // triangles. A mesh of nothing else is refused.
  std::size_t droppedOpen = 0;
  std::size_t bvhNodes = 0;
};

// Closest point of the mesh to a query point.
struct MeshClosestPoint {
  glm::dvec3 point{0.0};
  double distance = 0.0;
  std::uint32_t triangle = 0;  // input triangle index (indices[3*triangle ...])
};

class MeshSource final : public SdfSource {
 public:
  // positions: vertices; indices: a triangle list (three per triangle).
  static engine::Expected<std::unique_ptr<MeshSource>> create(std::vector<glm::vec3> positions,
                                                              std::vector<std::uint32_t> indices,
                                                              const MeshSourceOptions& options = {});
  static engine::Expected<std::unique_ptr<MeshSource>> create(const engine::scene::TriangleSoup& soup,
                                                              const MeshSourceOptions& options = {});
  ~MeshSource() override;
  MeshSource(const MeshSource&) = delete;
  MeshSource& operator=(const MeshSource&) = delete;

  SdfSample sample(const glm::dvec3& p) const override;
  Aabb bounds() const override;
  std::size_t materialSlots() const override;
  void sampleRow(const glm::dvec3& start, const glm::dvec3& step, std::span<SdfSample> out) const override;
  SdfBandSample sampleBand(const glm::dvec3& p, double band) const override;
  std::optional<SdfSample> sampleNear(const glm::dvec3& p, double band) const override;
  void sampleBandRow(const glm::dvec3& start, const glm::dvec3& step, double band,
                     std::span<SdfBandSample> out) const override;

  // Exact unsigned distance query (no sign).
  MeshClosestPoint closestPoint(const glm::dvec3& p) const;
  // Hierarchical (fast) generalized winding number at p.
  double windingNumber(const glm::dvec3& p) const;
  // The same summed over every triangle exactly: O(triangles), for verification.
  double windingNumberExact(const glm::dvec3& p) const;

  const MeshSourceStats& stats() const;

 private:
  struct Impl;
  explicit MeshSource(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace hsdf
