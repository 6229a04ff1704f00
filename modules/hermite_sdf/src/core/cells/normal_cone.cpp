#include "hermite_sdf/core/normal_cone.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "field/parallel.h"

namespace hsdf {
namespace {

constexpr double kHalfPi = 1.57079632679489661923;
// A control vector this much shorter than the longest of its cell may stand for a zero gradient
// (a tangent touching root, whose ray does not enter the solid there): such a cell never culls.
constexpr double kZeroVectorRatio = 1e-9;

// Forward difference of b along `axis` at (a, b, c) with that axis's index i in 0..2; 0 outside,
// which is what the degree elevation's end terms need.
double difference(const BernsteinCell<double>& b, int axis, int i, int j, int k) {
  if (i < 0 || i > 2) return 0.0;
  const int stride = axis == 0 ? 1 : axis == 1 ? 4 : 16;
  const int base = axis == 0 ? bernsteinIndex(i, j, k) : axis == 1 ? bernsteinIndex(j, i, k) : bernsteinIndex(j, k, i);
  return b[std::size_t(base + stride)] - b[std::size_t(base)];
}

// The derivative along `axis` is cubic in the other axes and quadratic in its own; degree elevation
// to cubic: q_i = (i/3) p_{i-1} + (1 - i/3) p_i. (The common factor 3 / h is dropped: cones only
// see directions.)
double elevated(const BernsteinCell<double>& b, int axis, int i, int j, int k) {
  return double(i) / 3.0 * difference(b, axis, i - 1, j, k) + (1.0 - double(i) / 3.0) * difference(b, axis, i, j, k);
}

// Appends the 64 control vectors of a cell's gradient (index a + 4b + 16c of the cubic basis).
void appendControlVectors(const CellRecord& record, double h, std::vector<glm::dvec3>& out) {
  const BernsteinCell<double> b = toBernstein(cellCorners(record), h);
  for (int c = 0; c < 4; ++c)
    for (int bb = 0; bb < 4; ++bb)
      for (int a = 0; a < 4; ++a)
        out.push_back({elevated(b, 0, a, bb, c), elevated(b, 1, bb, a, c), elevated(b, 2, c, a, bb)});
}

// An axis near that of the narrowest cone holding the directions: the centre of their (approximate)
// smallest enclosing ball, by Badoiu-Clarkson steps towards the farthest direction from the mean
// direction on. Any axis gives a valid cone (its cutoff is measured from the vectors after); this
// one only makes it narrower than the mean direction's.
glm::dvec3 narrowestAxis(const std::vector<glm::dvec3>& units, const glm::dvec3& mean) {
  constexpr int kSteps = 48;
  glm::dvec3 centre = mean;
  for (int step = 1; step <= kSteps; ++step) {
    glm::dvec3 farthest = centre;
    double farthestDistance = -1.0;
    for (const glm::dvec3& unit : units) {
      const double distance = glm::length(unit - centre);
      if (distance > farthestDistance) farthestDistance = distance, farthest = unit;
    }
    centre += (farthest - centre) / double(step + 1);
  }
  return glm::length(centre) > 0.0 ? glm::normalize(centre) : mean;
}

// The cone around narrowestAxis that holds every vector; never culls when a vector
// is (nearly) zero or the cone is not narrower than a half-space.
shader::CellBrickCone coneOf(const std::vector<glm::dvec3>& vectors) {
  double longest = 0.0;
  for (const glm::dvec3& v : vectors) longest = std::max(longest, glm::length(v));
  if (!(longest > 0.0) || !std::isfinite(longest)) return neverCullCone();
  std::vector<glm::dvec3> units;
  units.reserve(vectors.size());
  glm::dvec3 sum(0.0);
  for (const glm::dvec3& v : vectors) {
    const double length = glm::length(v);
    if (length <= kZeroVectorRatio * longest) return neverCullCone();
    units.push_back(v / length);
    sum += units.back();
  }
  if (glm::length(sum) <= 1e-9 * double(vectors.size())) return neverCullCone();
  const glm::dvec3 axis = narrowestAxis(units, glm::normalize(sum));
  double minCos = 1.0;
  for (const glm::dvec3& u : units) minCos = std::min(minCos, glm::dot(axis, u));
  const double theta = std::acos(std::clamp(minCos, -1.0, 1.0)) + kConeAngleMargin;
  if (theta >= kHalfPi) return neverCullCone();
  return {glm::vec4(glm::vec3(axis), float(std::sin(theta)))};
}

bool touchesBoundary(const CellRecord& r, int cellsPerAxis) {
  const int coords[3] = {r.x, r.y, r.z};
  for (int c : coords)
    if (c == 0 || c >= cellsPerAxis - 1) return true;
  return false;
}

// The interpolant on a face of the cell is the bicubic whose Bernstein coefficients are the 16 of
// the cell's with that axis's index 0 (low face) or 3 (high face): all > 0 make it positive there.
bool boundaryFacesPositive(const CellRecord& r, const GridSpec& grid) {
  const BernsteinCell<double> b = toBernstein(cellCorners(r), grid.spacing);
  const int coords[3] = {r.x, r.y, r.z};
  for (int axis = 0; axis < 3; ++axis) {
    for (int side : {0, 3}) {
      if (coords[axis] != (side == 0 ? 0 : grid.cellsPerAxis() - 1)) continue;
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
          const int index = axis == 0 ? bernsteinIndex(side, i, j) : axis == 1 ? bernsteinIndex(i, side, j)
                                                                                : bernsteinIndex(i, j, side);
          if (!(b[std::size_t(index)] > 0.0)) return false;
        }
    }
  }
  return true;
}

}  // namespace

shader::CellBrickCone cellGradientCone(const CellRecord& record, double h) {
  std::vector<glm::dvec3> vectors;
  vectors.reserve(64);
  appendControlVectors(record, h, vectors);
  return coneOf(vectors);
}

namespace {

// Cones built by calls made on this thread (gradientConesBuiltOnThisThread).
thread_local std::uint64_t conesBuiltHere = 0;

// Each cone of `cones` made by cone(i) on worker threads, chunks of `chunk` items.
engine::Status buildConesInParallel(std::vector<shader::CellBrickCone>& cones, std::size_t chunk, unsigned threads,
                                    const engine::CancelToken* cancel,
                                    const std::function<shader::CellBrickCone(std::size_t)>& cone) {
  BakeOptions options;
  options.threads = threads;
  options.cancel = cancel;
  ENGINE_TRY(detail::runParallel((cones.size() + chunk - 1) / chunk, options, [&](std::size_t item) {
    const std::size_t end = std::min(cones.size(), (item + 1) * chunk);
    for (std::size_t i = item * chunk; i < end; ++i) cones[i] = cone(i);
    return engine::Status{};
  }));
  conesBuiltHere += cones.size();
  return {};
}

// A brick whose cells run past the index list or name a record the stream lacks (both named).
engine::Status checkBrickIndices(const CellStream& cells, std::span<const shader::CellBrickGpu> bricks,
                                 std::span<const std::uint32_t> indices) {
  for (std::size_t b = 0; b < bricks.size(); ++b) {
    const shader::CellBrickGpu& brick = bricks[b];
    const std::size_t count = std::size_t(std::popcount(brick.maskLo) + std::popcount(brick.maskHi));
    if (std::size_t(brick.firstIndex) + count > indices.size())
      return engine::makeError(fmt::format("brick {}: cells {}..{} of a list of {} record indices", b,
                                           brick.firstIndex, std::size_t(brick.firstIndex) + count, indices.size()));
    for (std::uint32_t index : indices.subspan(brick.firstIndex, count))
      if (index >= cells.records.size())
        return engine::makeError(fmt::format("brick {}: record index {} of a stream of {} records", b, index,
                                             cells.records.size()));
  }
  return {};
}

}  // namespace

engine::Expected<std::vector<shader::CellBrickCone>> cellGradientCones(const CellStream& cells, unsigned threads,
                                                                       const engine::CancelToken* cancel) {
  constexpr std::size_t kChunk = 4096;  // records per work item: the claim per item stays negligible
  std::vector<shader::CellBrickCone> cones(cells.records.size());
  ENGINE_TRY(buildConesInParallel(cones, kChunk, threads, cancel, [&](std::size_t i) {
    return cellGradientCone(cells.records[i], cells.grid.spacing);
  }));
  return cones;
}

shader::CellBrickCone brickGradientCone(const CellStream& cells, std::span<const std::uint32_t> recordIndices) {
  if (recordIndices.empty()) return neverCullCone();
  std::vector<glm::dvec3> vectors;
  vectors.reserve(64 * recordIndices.size());
  for (std::uint32_t index : recordIndices) appendControlVectors(cells.records.at(index), cells.grid.spacing, vectors);
  return coneOf(vectors);
}

engine::Expected<std::vector<shader::CellBrickCone>> brickGradientCones(const CellStream& cells,
                                                                        std::span<const shader::CellBrickGpu> bricks,
                                                                        std::span<const std::uint32_t> indices,
                                                                        unsigned threads,
                                                                        const engine::CancelToken* cancel) {
  ENGINE_TRY(checkBrickIndices(cells, bricks, indices));
  constexpr std::size_t kChunk = 256;  // bricks per work item (up to 64 cells each)
  std::vector<shader::CellBrickCone> cones(bricks.size());
  ENGINE_TRY(buildConesInParallel(cones, kChunk, threads, cancel, [&](std::size_t b) {
    const std::size_t count = std::size_t(std::popcount(bricks[b].maskLo) + std::popcount(bricks[b].maskHi));
    return brickGradientCone(cells, indices.subspan(bricks[b].firstIndex, count));
  }));
  return cones;
}

std::uint64_t gradientConesBuiltOnThisThread() { return conesBuiltHere; }

bool boundaryIsPositive(const CellStream& cells) {
  if (cells.records.empty()) return false;
  bool touches = false;
  for (const CellRecord& r : cells.records) {
    if (!touchesBoundary(r, cells.grid.cellsPerAxis())) continue;
    touches = true;
    if (!boundaryFacesPositive(r, cells.grid)) return false;
  }
  if (touches) return true;
  const auto first = std::min_element(cells.records.begin(), cells.records.end(), [](const CellRecord& a, const CellRecord& b) {
    return std::tie(a.z, a.y, a.x) < std::tie(b.z, b.y, b.x);
  });
  return first->corners[0].f > 0.0f;
}

namespace {

// The box of the grid block at integer coordinate `index` whose side is `side` (normal_cone.glsl's
// gridBlockBox).
BrickBox gridBlockBox(const glm::vec3& index, const glm::vec3& gridOrigin, float side) {
  BrickBox box;
  box.lo = gridOrigin + side * index;
  box.hi = box.lo + glm::vec3(side);
  return box;
}

}  // namespace

BrickBox brickBox(std::uint32_t packedXyz, const glm::vec3& gridOrigin, float h) {
  const glm::vec3 brick(float(packedXyz & 1023u), float((packedXyz >> 10) & 1023u), float((packedXyz >> 20) & 1023u));
  return gridBlockBox(brick, gridOrigin, h * float(CELL_BRICK_SIZE));
}

BrickBox cellBox(const glm::uvec3& cell, const glm::vec3& gridOrigin, float h) {
  return gridBlockBox(glm::vec3(cell), gridOrigin, h);
}

glm::vec3 boxCorner(const BrickBox& box, int corner) {
  return {(corner & 1) ? box.hi.x : box.lo.x, (corner & 2) ? box.hi.y : box.lo.y, (corner & 4) ? box.hi.z : box.lo.z};
}

bool coneCullsBox(const shader::CellBrickCone& cone, const BrickBox& box, const glm::vec3& eye) {
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 toCorner = boxCorner(box, corner) - eye;
    const float along = glm::dot(glm::vec3(cone.axisCutoff), toCorner);
    const float bound = cone.axisCutoff.w * glm::length(toCorner);
    if (!(along > bound)) return false;
  }
  return true;
}

bool boxOutsideFrustum(const glm::mat4& objectToClip, const BrickBox& box) {
  // Per plane (w+x, w-x, w+y, w-y, w-z): is some corner inside?
  bool inside[5] = {false, false, false, false, false};
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec4 clip = objectToClip * glm::vec4(boxCorner(box, corner), 1.0f);
    inside[0] = inside[0] || clip.w + clip.x >= 0.0f;
    inside[1] = inside[1] || clip.w - clip.x >= 0.0f;
    inside[2] = inside[2] || clip.w + clip.y >= 0.0f;
    inside[3] = inside[3] || clip.w - clip.y >= 0.0f;
    inside[4] = inside[4] || clip.w - clip.z >= 0.0f;
  }
  return !(inside[0] && inside[1] && inside[2] && inside[3] && inside[4]);
}

BrickVerdict brickVerdict(const glm::mat4& objectToClip, const BrickBox& box, const shader::CellBrickCone& cone,
                          const glm::vec3& eye, bool coneTest) {
  if (boxOutsideFrustum(objectToClip, box)) return BrickVerdict::FrustumCulled;
  return coneTest && coneCullsBox(cone, box, eye) ? BrickVerdict::ConeCulled : BrickVerdict::Kept;
}

bool brickConeCullAllowed(bool boundaryPositive, const glm::dvec3& eyeObject, double nearPlaneReachObject,
                          const GridSpec& grid) {
  if (!boundaryPositive) return false;
  const Aabb bounds = grid.bounds();
  const glm::dvec3 nearest = glm::clamp(eyeObject, bounds.min, bounds.max);
  return glm::length(eyeObject - nearest) > nearPlaneReachObject;
}

}  // namespace hsdf
