#include "hermite_sdf/core/mesh_source.h"

#include <atomic>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "source/mesh_bvh.h"
#include "source/mesh_closest.h"
#include "source/mesh_input.h"
#include "source/mesh_sign.h"
#include "source/mesh_union.h"

namespace hsdf {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Below this fraction of the mesh size a point counts as on the surface: (p - closest) has no
// reliable direction there, so the gradient is the closest feature's normal (onSurfaceGradient).
constexpr double kOnSurfaceRelative = 1e-12;
// A reused sign must come from a ball that strictly contains the point; this margin keeps rounding
// in the distance from letting a point on the ball's boundary (possibly on the surface) through.
constexpr double kBallShrink = 1.0 - 1e-9;
// For meshes with boundary edges: only winding numbers this far from 0.5 are passed on.
constexpr double kDecisiveWinding = 0.25;
// A query farther than this many times the previous step from the previous query starts a new
// run (a new grid row); its result becomes the anchor the next run starts from.
constexpr double kJumpFactor = 4.0;

std::atomic<std::uint64_t> nextSourceId{1};

// A recent query whose ball of radius `radius` around `p` holds no surface.
struct Anchor {
  glm::dvec3 p{0.0};
  double radius = -1.0;
  double winding = 0.0;
  std::uint32_t triangle = UINT32_MAX;  // closest triangle (BVH order) of the query, if known
};

// Coherence state of one sequence of queries: the previous query and the start of the current run.
struct QueryCache {
  std::uint64_t owner = 0;
  bool hasPrevious = false;
  Anchor previous;
  Anchor runStart;
  double previousStep = 0.0;
};

QueryCache freshCache(std::uint64_t owner) {
  QueryCache cache;
  cache.owner = owner;
  return cache;
}

QueryCache& threadCache(std::uint64_t owner) {
  thread_local QueryCache cache;
  if (cache.owner != owner) cache = freshCache(owner);
  return cache;
}

}  // namespace

struct MeshSource::Impl {
  mesh::TriangleBvh bvh;         // winding numbers, normals
  mesh::ClosestPointTree tree;   // distances
  std::unique_ptr<mesh::PseudoNormals> pseudoNormals;  // set when they give the sign
  std::unique_ptr<mesh::PartUnion> partUnion;  // set for overlapping closed parts: distances inside
  std::vector<std::uint32_t> inputTriangle;  // input index of each kept triangle (input order of kept)
  MeshSourceStats stats;
  MeshSourceOptions options;
  Aabb bounds;
  double onSurfaceDistance = 0.0;
  double halfShell = 0.0;  // options.shellThickness / 2: a shell's surface lies this far off the triangles
  std::uint64_t id = nextSourceId.fetch_add(1);
  std::vector<std::uint32_t> interiorTriangles;  // of `clean`: parts inside the solid (PartSides)
  std::vector<std::uint32_t> openTriangles;      // of `clean`: open parts bounding nothing
  // The material slot of each triangle in BVH order (options.triangleSlots looked up once, so that
  // a sample costs one load); empty for one material.
  std::vector<std::uint8_t> slotOfTriangle;
  std::size_t materialSlots = 0;

  Impl(const mesh::CleanTriangles& clean, const MeshSourceOptions& opts)
      : bvh(clean.corners), tree(bvh), inputTriangle(clean.inputTriangle), options(opts) {
    bounds.min = glm::dvec3(kInfinity);
    bounds.max = glm::dvec3(-kInfinity);
    for (const glm::dvec3& c : clean.corners) {
      bounds.min = glm::min(bounds.min, c);
      bounds.max = glm::max(bounds.max, c);
    }
    onSurfaceDistance = kOnSurfaceRelative * glm::length(bounds.size());
    halfShell = 0.5 * opts.shellThickness;
    bounds.min -= glm::dvec3(halfShell);
    bounds.max += glm::dvec3(halfShell);
    setMaterialSlots(clean);
    std::vector<std::uint32_t> vertexOf = mesh::weldVertices(bvh.corners());
    mesh::EdgeTopology topology = mesh::edgeTopology(vertexOf);
    // Only a mesh open by equal positions looks for copies a rounding apart (a seam computed twice):
    // a closed mesh keeps its cost, and two closed parts touching at nearly the same point keep
    // their own vertices (and pseudonormals).
    if (!topology.closed)
      if (auto welded = mesh::weldBoundaryWithinRounding(bvh.corners(), vertexOf, topology.boundaryVertices)) {
        vertexOf = std::move(*welded);
        topology = mesh::edgeTopology(vertexOf);
      }
    stats.droppedZeroArea = clean.droppedZeroArea;
    stats.triangles = bvh.triangleCount();
    stats.inputTriangles = stats.triangles + stats.droppedZeroArea;
    stats.boundaryEdges = topology.boundaryEdges;
    stats.closed = topology.closed;
    stats.bvhNodes = bvh.nodeCount();
    if (halfShell == 0.0) analyseSign(vertexOf);
  }

  // What signs the field: pseudonormals where valid, else the winding number; the parts that bound
  // nothing, lie inside the solid or overlap (mesh_sign.h, mesh_union.h). A shell needs no sign.
  void analyseSign(const std::vector<std::uint32_t>& vertexOf) {
    if (stats.closed) stats.selfIntersecting = mesh::hasSelfIntersections(bvh, vertexOf);
    if (stats.closed && stats.selfIntersecting) partUnion = mesh::PartUnion::create(bvh, vertexOf, options.windingBeta);
    if (!stats.closed)
      for (const std::uint32_t t : mesh::partsBoundingNothing(bvh, vertexOf, options.windingBeta))
        openTriangles.push_back(bvh.inputIndex(t));
    if (options.signMode == SignMode::Auto && stats.closed && !stats.selfIntersecting) {
      mesh::PartSides sides = mesh::partSides(bvh, vertexOf, options.windingBeta);
      stats.partsMisoriented = !sides.faceOutside;
      for (const std::uint32_t t : sides.interior) interiorTriangles.push_back(bvh.inputIndex(t));
      if (!stats.partsMisoriented) {
        pseudoNormals = std::make_unique<mesh::PseudoNormals>(bvh, vertexOf);
        stats.pseudoNormalSign = true;
      }
    }
  }

  // The slot of each BVH triangle: the input triangle's (options.triangleSlots, already checked).
  void setMaterialSlots(const mesh::CleanTriangles& clean) {
    if (options.triangleSlots.empty()) return;
    slotOfTriangle.resize(bvh.triangleCount());
    for (std::uint32_t t = 0; t < bvh.triangleCount(); ++t) {
      slotOfTriangle[t] = options.triangleSlots[clean.inputTriangle[bvh.inputIndex(t)]];
      materialSlots = std::max<std::size_t>(materialSlots, std::size_t(slotOfTriangle[t]) + 1);
    }
  }

  // Inside by the winding number: for a closed mesh wherever it is not 0 (the nonzero rule: a part
  // nested in another with the same orientation adds to it, a part turned inside out has -1), for
  // an open one where the generalized winding number passes 1/2.
  bool inside(double w) const { return stats.closed ? std::abs(w) >= 0.5 : w >= 0.5; }

  bool mayPassOn(const Anchor& anchor) const {
    return stats.closed || std::abs(anchor.winding - 0.5) >= kDecisiveWinding;
  }

  // The winding number of an anchor whose surface-free ball holds p, if any.
  std::optional<double> reusedWinding(const glm::dvec3& p, const QueryCache& cache) const {
    if (!options.reuseSign || !cache.hasPrevious) return std::nullopt;
    for (const Anchor* anchor : {&cache.previous, &cache.runStart}) {
      const glm::dvec3 d = p - anchor->p;
      const double r = anchor->radius * kBallShrink;
      if (r > 0.0 && glm::dot(d, d) < r * r && mayPassOn(*anchor)) return anchor->winding;
    }
    return std::nullopt;
  }

  // The winding number at p: inherited from an anchor whose surface-free ball holds p, else computed.
  double winding(const glm::dvec3& p, const QueryCache& cache) const {
    if (const std::optional<double> reused = reusedWinding(p, cache)) return *reused;
    return bvh.windingNumber(p, options.windingBeta);
  }

  // Squared distance bound from the closest triangles of the anchors (the nearer anchor's first):
  // the closest triangle rarely changes between neighbouring grid samples, so this bound is
  // usually the answer and prunes nearly the whole BVH.
  mesh::ClosestHit seedHit(const glm::dvec3& p, const QueryCache& cache) const {
    mesh::ClosestHit seed;
    if (!cache.hasPrevious) return seed;
    for (const Anchor* anchor : {&cache.previous, &cache.runStart}) {
      if (anchor->triangle == UINT32_MAX) continue;
      const mesh::ClosestHit candidate = tree.distanceTo(p, anchor->triangle);
      if (candidate.distanceSquared < seed.distanceSquared) seed = candidate;
    }
    return seed;
  }

  mesh::ClosestHit closest(const glm::dvec3& p, const QueryCache& cache) const {
    return tree.closest(p, seedHit(p, cache));
  }

  void remember(QueryCache& cache, const Anchor& anchor) const {
    const double step = cache.hasPrevious ? glm::length(anchor.p - cache.previous.p) : kInfinity;
    if (!cache.hasPrevious || step > kJumpFactor * cache.previousStep) cache.runStart = anchor;
    cache.previous = anchor;
    cache.previousStep = step;
    cache.hasPrevious = true;
  }

  // The gradient at a sample on the surface, where (p - closest) has no direction: the normal of
  // the closest feature. On an edge or a vertex (an axis-aligned box's samples lie on its edges),
  // the face normal was that of whichever adjacent face the search met first, so the Hermite
  // interpolant leaned out past the other face and the edge bulged, differently for each
  // triangulation; the pseudonormal (the faces' normals summed, angle-weighted at a vertex) is
  // the same for every triangulation and leans to neither face.
  glm::dvec3 onSurfaceGradient(const mesh::ClosestHit& hit) const {
    if (!pseudoNormals) return bvh.unitNormal(hit.triangle);
    const glm::dvec3& n = pseudoNormals->normal(hit.triangle, hit.feature);
    const double length = glm::length(n);
    return length > 0.0 ? n / length : bvh.unitNormal(hit.triangle);
  }

  SdfSample signedSample(const glm::dvec3& p, const mesh::ClosestHit& hit, double winding) const {
    const double distance = std::sqrt(hit.distanceSquared);
    const double sign = inside(winding) ? -1.0 : 1.0;
    SdfSample s;
    s.value = sign * distance;
    s.gradient = distance > onSurfaceDistance ? (p - hit.point) * (sign / distance) : onSurfaceGradient(hit);
    // The closest triangle's material: of the triangles equally close (an edge, a vertex), the one
    // the query picks, the lowest in BVH order whatever the seed (mesh_closest.h), so the slot,
    // like the gradient, does not depend on the thread schedule.
    if (!slotOfTriangle.empty()) s.material = slotOfTriangle[hit.triangle];
    return s;
  }

  // Winding number, or its stand-in (1 inside, 0 outside) from the pseudonormal of the closest
  // feature when the mesh allows it.
  double windingAt(const glm::dvec3& p, const mesh::ClosestHit& hit, const QueryCache& cache) const {
    if (!pseudoNormals) return winding(p, cache);
    return glm::dot(p - hit.point, pseudoNormals->normal(hit.triangle, hit.feature)) < 0.0 ? 1.0 : 0.0;
  }

  // The point the distance is measured to: the closest of the mesh, except inside overlapping
  // parts, where that may lie inside another part; there the deepest containing part's
  // (mesh_union.h). Anchors keep the mesh's closest: their balls must hold no triangle at all.
  mesh::ClosestHit boundaryHit(const glm::dvec3& p, const mesh::ClosestHit& hit, double winding) const {
    if (!partUnion || !inside(winding)) return hit;
    const mesh::ClosestHit deepest = partUnion->deepest(p, hit.distanceSquared);
    return deepest.triangle == UINT32_MAX ? hit : deepest;
  }

  // A shell's sample: |d| - t/2, its gradient (p - closest) / |d| (on the triangles, where the
  // shell's middle is, any unit vector: no surface is there, t/2 away from both of its sides).
  SdfSample shellSample(const glm::dvec3& p, const mesh::ClosestHit& hit, QueryCache& cache) const {
    const double distance = std::sqrt(hit.distanceSquared);
    remember(cache, {p, distance, 0.0, hit.triangle});
    SdfSample s;
    s.value = distance - halfShell;
    s.gradient = distance > onSurfaceDistance ? (p - hit.point) / distance : bvh.unitNormal(hit.triangle);
    if (!slotOfTriangle.empty()) s.material = slotOfTriangle[hit.triangle];
    return s;
  }

  SdfSample sample(const glm::dvec3& p, QueryCache& cache) const {
    if (halfShell > 0.0) return shellSample(p, closest(p, cache), cache);
    const mesh::ClosestHit hit = closest(p, cache);
    const double w = windingAt(p, hit, cache);
    remember(cache, {p, std::sqrt(hit.distanceSquared), w, hit.triangle});
    return signedSample(p, boundaryHit(p, hit, w), w);
  }

  // The closest triangle when it lies within `band` of p; otherwise no triangle and, in
  // prunedBoundSquared, the traversal's bound.
  mesh::ClosestHit closestWithin(const glm::dvec3& p, double band, const QueryCache& cache) const {
    mesh::ClosestHit seed = seedHit(p, cache);  // a candidate, or the band as a strict bound
    const double bandSquared = band * band;
    if (seed.distanceSquared > bandSquared) {
      seed = mesh::ClosestHit{};
      seed.distanceSquared = bandSquared;
    }
    return tree.closestOrBound(p, seed);
  }

  SdfSample exactSample(const glm::dvec3& p, const mesh::ClosestHit& hit, QueryCache& cache) const {
    if (halfShell > 0.0) return shellSample(p, hit, cache);
    const double w = windingAt(p, hit, cache);
    remember(cache, {p, std::sqrt(hit.distanceSquared), w, hit.triangle});
    return signedSample(p, boundaryHit(p, hit, w), w);
  }

  // A far point is not remembered: its anchor would need the sign, the query this skips.
  std::optional<SdfSample> sampleNear(const glm::dvec3& p, double band, QueryCache& cache) const {
    const mesh::ClosestHit hit = closestWithin(p, band + halfShell, cache);
    if (hit.triangle == UINT32_MAX) return std::nullopt;
    return exactSample(p, hit, cache);
  }

  SdfBandSample sampleBand(const glm::dvec3& p, double band, QueryCache& cache) const {
    const mesh::ClosestHit hit = closestWithin(p, band + halfShell, cache);
    if (hit.triangle != UINT32_MAX) return {exactSample(p, hit, cache), true};
    if (halfShell > 0.0) return shellBound(p, std::max(hit.prunedBoundSquared, (band + halfShell) * (band + halfShell)), cache);
    const double bandSquared = band * band;
    // Nothing within the band: the traversal's pruning bound is a safe distance bound. The sign
    // comes from a recent query's ball if one holds p; otherwise, where pseudonormals are valid,
    // the full closest-point query (cheaper than a winding number next to the surface) gives it
    // together with the exact distance, the best bound there is.
    Anchor anchor{p, std::sqrt(std::max(hit.prunedBoundSquared, bandSquared)), 0.0,
                  cache.hasPrevious ? cache.previous.triangle : UINT32_MAX};
    if (const std::optional<double> reused = reusedWinding(p, cache)) {
      anchor.winding = *reused;
    } else if (pseudoNormals) {
      const mesh::ClosestHit full = closest(p, cache);
      anchor = {p, std::sqrt(full.distanceSquared), windingAt(p, full, cache), full.triangle};
    } else {
      anchor.winding = bvh.windingNumber(p, options.windingBeta);
    }
    remember(cache, anchor);
    SdfBandSample out;
    out.sample.value = (inside(anchor.winding) ? -1.0 : 1.0) * anchor.radius;
    out.exact = false;
    return out;
  }

  // No triangle within sqrt(boundSquared) of p: a shell's surface is at least t/2 less away, on
  // the outside (a shell has no inside farther than t/2 from its triangles).
  SdfBandSample shellBound(const glm::dvec3& p, double boundSquared, QueryCache& cache) const {
    const double radius = std::sqrt(boundSquared);
    remember(cache, {p, radius, 0.0, cache.hasPrevious ? cache.previous.triangle : UINT32_MAX});
    SdfBandSample out;
    out.sample.value = radius - halfShell;
    out.exact = false;
    return out;
  }
};

namespace {

// `clean` less the triangles listed (indices into it).
mesh::CleanTriangles withoutTriangles(const mesh::CleanTriangles& clean, const std::vector<std::uint32_t>& dropped) {
  std::vector<bool> drop(clean.inputTriangle.size(), false);
  for (const std::uint32_t t : dropped) drop[t] = true;
  mesh::CleanTriangles kept;
  kept.droppedZeroArea = clean.droppedZeroArea;
  for (std::size_t t = 0; t < drop.size(); ++t) {
    if (drop[t]) continue;
    kept.corners.insert(kept.corners.end(), clean.corners.begin() + std::ptrdiff_t(3 * t),
                        clean.corners.begin() + std::ptrdiff_t(3 * t + 3));
    kept.inputTriangle.push_back(clean.inputTriangle[t]);
  }
  return kept;
}

}  // namespace

engine::Expected<std::unique_ptr<MeshSource>> MeshSource::create(std::vector<glm::vec3> positions,
                                                                  std::vector<std::uint32_t> indices,
                                                                  const MeshSourceOptions& options) {
  if (!(options.windingBeta > 0.0) || !std::isfinite(options.windingBeta))
    return engine::makeError("mesh source: windingBeta must be a positive finite number");
  if (!(options.shellThickness >= 0.0) || !std::isfinite(options.shellThickness))
    return engine::makeError(fmt::format("mesh source: shell thickness {}: it must be a finite number, 0 (a solid) or "
                                         "positive (a shell around the triangles)",
                                         options.shellThickness));
  if (!options.triangleSlots.empty() && options.triangleSlots.size() != indices.size() / 3)
    return engine::makeError(fmt::format("mesh source: {} material slots for {} triangles",
                                         options.triangleSlots.size(), indices.size() / 3));
  auto clean = mesh::cleanTriangles(positions, indices);
  if (!clean) return clean.error().withContext("mesh source");
  auto impl = std::make_unique<Impl>(*clean, options);
  // An open part across which the winding number does not decide inside and outside would be
  // signed by rounding: a terrain drew as scattered specks. Such parts are dropped (a floor under a
  // closed ball: the ball is baked), and a mesh made of nothing else is refused.
  if (const std::size_t open = impl->openTriangles.size(); open > 0) {
    if (open == clean->inputTriangle.size())
      return engine::makeError(fmt::format(
          "mesh source: the mesh bounds no volume: across most of its area the winding number does not tell an "
          "inside from an outside ({} triangles, {} boundary edges: an open sheet such as a terrain or a plane, or "
          "triangles doubled with both windings); draw it as triangles, close it, or bake it as a shell of some "
          "thickness (--shell T of hsdf_bake and scene_runner, the panel's shell thickness)",
          open, impl->stats.boundaryEdges));
    impl = std::make_unique<Impl>(withoutTriangles(*clean, impl->openTriangles), options);
    impl->stats.droppedOpen = open;
    impl->stats.inputTriangles += open;
    return std::unique_ptr<MeshSource>(new MeshSource(std::move(impl)));
  }
  // Every part inside (coincident copies of a part, which read nonzero on both sides): nothing is
  // its boundary for sure, so nothing is dropped and the winding number signs it.
  if (!impl->interiorTriangles.empty() && impl->interiorTriangles.size() < clean->inputTriangle.size()) {
    // Parts with the solid on both sides (the inner of two nested boxes) are not its boundary:
    // dropped, so that distances are to the boundary (else the field touches zero inside the
    // solid, and cells are kept there). What is left bounds the same solid by the nonzero rule.
    const std::size_t interior = impl->interiorTriangles.size();
    impl = std::make_unique<Impl>(withoutTriangles(*clean, impl->interiorTriangles), options);
    impl->stats.droppedInterior = interior;
    impl->stats.inputTriangles += interior;
  }
  return std::unique_ptr<MeshSource>(new MeshSource(std::move(impl)));
}

engine::Expected<std::unique_ptr<MeshSource>> MeshSource::create(const engine::scene::TriangleSoup& soup,
                                                                  const MeshSourceOptions& options) {
  return create(soup.positions, soup.indices, options);
}

MeshSource::MeshSource(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
MeshSource::~MeshSource() = default;

SdfSample MeshSource::sample(const glm::dvec3& p) const { return impl_->sample(p, threadCache(impl_->id)); }

Aabb MeshSource::bounds() const { return impl_->bounds; }

std::size_t MeshSource::materialSlots() const { return impl_->materialSlots; }

void MeshSource::sampleRow(const glm::dvec3& start, const glm::dvec3& step, std::span<SdfSample> out) const {
  // The thread's cache, not a fresh one: a bake walks neighbouring rows on the same thread, so the
  // previous row's start seeds this row's first query.
  QueryCache& cache = threadCache(impl_->id);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = impl_->sample(start + double(i) * step, cache);
}

SdfBandSample MeshSource::sampleBand(const glm::dvec3& p, double band) const {
  return impl_->sampleBand(p, band, threadCache(impl_->id));
}

std::optional<SdfSample> MeshSource::sampleNear(const glm::dvec3& p, double band) const {
  return impl_->sampleNear(p, band, threadCache(impl_->id));
}

void MeshSource::sampleBandRow(const glm::dvec3& start, const glm::dvec3& step, double band,
                               std::span<SdfBandSample> out) const {
  QueryCache& cache = threadCache(impl_->id);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = impl_->sampleBand(start + double(i) * step, band, cache);
}

MeshClosestPoint MeshSource::closestPoint(const glm::dvec3& p) const {
  const mesh::ClosestHit hit = impl_->tree.closest(p, kInfinity);
  return {hit.point, std::sqrt(hit.distanceSquared), impl_->inputTriangle[impl_->bvh.inputIndex(hit.triangle)]};
}

double MeshSource::windingNumber(const glm::dvec3& p) const {
  return impl_->bvh.windingNumber(p, impl_->options.windingBeta);
}

double MeshSource::windingNumberExact(const glm::dvec3& p) const { return impl_->bvh.windingNumberExact(p); }

const MeshSourceStats& MeshSource::stats() const { return impl_->stats; }

}  // namespace hsdf
