#include "source/mesh_union.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "source/mesh_sign.h"

namespace hsdf::mesh {

struct PartUnion::Part {
  TriangleBvh bvh;        // the part's triangles alone: its own winding number
  ClosestPointTree tree;  // and its own closest point
  std::vector<std::uint32_t> wholeTriangle;  // the whole mesh's BVH index of each of the part's (its BVH order)
  glm::dvec3 min{0.0}, max{0.0};             // bounds: a point outside them is outside the part

  Part(const TriangleBvh& whole, const std::vector<std::uint32_t>& members)
      : bvh(cornersOf(whole, members)), tree(bvh), wholeTriangle(members.size()), min(whole.corner(members[0], 0)),
        max(min) {
    for (std::uint32_t t = 0; t < bvh.triangleCount(); ++t) wholeTriangle[t] = members[bvh.inputIndex(t)];
    for (const glm::dvec3& c : bvh.corners()) {
      min = glm::min(min, c);
      max = glm::max(max, c);
    }
  }

  bool mayContain(const glm::dvec3& p) const {
    return glm::all(glm::greaterThanEqual(p, min)) && glm::all(glm::lessThanEqual(p, max));
  }

  // Own winding number 1 behind its largest face and 0 in front: its inside is behind its faces.
  // `members` are its triangles in the whole mesh, from which it was made.
  bool facesOutward(const TriangleBvh& whole, const std::vector<std::uint32_t>& members, double windingBeta) const {
    const std::uint32_t largest = largestTriangle(whole, members);
    const auto own = std::uint32_t(std::find(wholeTriangle.begin(), wholeTriangle.end(), largest) - wholeTriangle.begin());
    const auto [front, back] = windingBothSides(bvh, own, windingBeta);
    return std::abs(front) < 0.5 && back >= 0.5;
  }
};

PartUnion::PartUnion(std::vector<std::unique_ptr<Part>> parts, double windingBeta)
    : parts_(std::move(parts)), windingBeta_(windingBeta) {}
PartUnion::~PartUnion() = default;

std::unique_ptr<PartUnion> PartUnion::create(const TriangleBvh& bvh, const std::vector<std::uint32_t>& vertexOf,
                                             double windingBeta) {
  const std::vector<std::vector<std::uint32_t>> members = connectedPartTriangles(bvh, vertexOf);
  if (members.size() < 2) return nullptr;
  std::vector<std::unique_ptr<Part>> parts;
  for (const std::vector<std::uint32_t>& part : members) {
    parts.push_back(std::make_unique<Part>(bvh, part));
    if (!parts.back()->facesOutward(bvh, part, windingBeta)) return nullptr;
  }
  return std::unique_ptr<PartUnion>(new PartUnion(std::move(parts), windingBeta));
}

ClosestHit PartUnion::deepest(const glm::dvec3& p, double beyondSquared) const {
  ClosestHit best;
  best.distanceSquared = beyondSquared;
  // The distance first: the winding number is needed only for a part that would raise the maximum.
  for (const std::unique_ptr<Part>& part : parts_) {
    if (!part->mayContain(p)) continue;
    ClosestHit hit = part->tree.closest(p, std::numeric_limits<double>::infinity());
    if (!(hit.distanceSquared > best.distanceSquared) || part->bvh.windingNumber(p, windingBeta_) < 0.5) continue;
    hit.triangle = part->wholeTriangle[hit.triangle];
    best = hit;
  }
  return best;
}

}  // namespace hsdf::mesh
