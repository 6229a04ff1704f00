#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "hermite_sdf/core/reference.h"
#include "reference/caster_internal.h"
#include "reference/root_finder.h"

namespace hsdf {
namespace detail {

namespace {

bool isFinite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Clips the ray to the grid box; false if it misses the box within [tMin, tMax].
bool clipToGrid(const GridSpec& grid, const Ray& ray, double& tEnter, double& tExit) {
  const Aabb box = grid.bounds();
  for (int a = 0; a < 3; ++a) {
    if (ray.direction[a] == 0.0) {
      if (ray.origin[a] < box.min[a] || ray.origin[a] > box.max[a]) return false;
      continue;
    }
    const double t1 = (box.min[a] - ray.origin[a]) / ray.direction[a];
    const double t2 = (box.max[a] - ray.origin[a]) / ray.direction[a];
    tEnter = std::max(tEnter, std::min(t1, t2));
    tExit = std::min(tExit, std::max(t1, t2));
  }
  return tEnter <= tExit;
}

// Ray parameter where the ray crosses the far boundary of `cell` along axis a (inf if parallel).
double nextBoundary(const GridSpec& grid, const Ray& ray, const glm::ivec3& cell, const glm::ivec3& step, int a) {
  if (step[a] == 0) return HUGE_VAL;
  const double plane = grid.origin[a] + grid.spacing * double(cell[a] + (step[a] > 0 ? 1 : 0));
  return (plane - ray.origin[a]) / ray.direction[a];
}

// 3D DDA over the grid's cells along the part of the ray inside the grid and inside [tMin, tMax].
// Calls visit(cell, t0, t1) for each cell the ray crosses, in order, with the ray parameters where
// it enters and leaves the cell (t0 < t1); visit returning true stops the walk. A template, not a
// std::function: it runs once per cell crossed, millions of times per image.
template <class Visit>
void walkCells(const GridSpec& grid, const Ray& ray, double tMin, double tMax, const Visit& visit) {
  double tEnter = tMin, tExit = tMax;
  if (!clipToGrid(grid, ray, tEnter, tExit)) return;
  const int n = grid.cellsPerAxis();
  const glm::dvec3 start = (ray.origin + tEnter * ray.direction - grid.origin) / grid.spacing;
  glm::ivec3 cell, step;
  glm::dvec3 tNext;
  for (int a = 0; a < 3; ++a) {
    cell[a] = std::clamp(int(std::floor(start[a])), 0, n - 1);
    step[a] = ray.direction[a] > 0.0 ? 1 : (ray.direction[a] < 0.0 ? -1 : 0);
    tNext[a] = nextBoundary(grid, ray, cell, step, a);
  }
  double tCurrent = tEnter;
  while (true) {
    const int axis = tNext.x <= tNext.y ? (tNext.x <= tNext.z ? 0 : 2) : (tNext.y <= tNext.z ? 1 : 2);
    const double tEnd = std::max(tCurrent, std::min(tNext[axis], tExit));
    if (tEnd > tCurrent && visit(cell, tCurrent, tEnd)) return;
    if (tEnd >= tExit) return;
    cell[axis] += step[axis];
    if (cell[axis] < 0 || cell[axis] >= n) return;
    tNext[axis] = nextBoundary(grid, ray, cell, step, axis);
    tCurrent = tEnd;
  }
}

}  // namespace

glm::dvec3 cellLocal(const GridSpec& grid, const glm::ivec3& cell, const glm::dvec3& p) {
  return glm::clamp((p - grid.origin) / grid.spacing - glm::dvec3(cell), 0.0, 1.0);
}

engine::Status validateRay(const Ray& ray, const CastOptions& options) {
  if (!isFinite(ray.origin))
    return engine::makeError(fmt::format("ray origin ({}, {}, {}) is not finite", ray.origin.x, ray.origin.y, ray.origin.z));
  if (!isFinite(ray.direction) || ray.direction == glm::dvec3(0.0))
    return engine::makeError(fmt::format("ray direction ({}, {}, {}) must be finite and nonzero", ray.direction.x,
                                         ray.direction.y, ray.direction.z));
  if (!(options.tMin <= options.tMax))
    return engine::makeError(fmt::format("ray range [{}, {}] is empty or NaN", options.tMin, options.tMax));
  return {};
}

template <class Field>
engine::Status validateField(const Field& field, std::size_t storedSamples) {
  ENGINE_TRY(validateGrid(field.grid));
  if (storedSamples != field.grid.sampleCount())
    return engine::makeError(fmt::format("field has {} samples but its grid of resolution {} needs {}", storedSamples,
                                         field.grid.resolution, field.grid.sampleCount()));
  return {};
}

engine::Status validateField(const HermiteField& field) { return validateField(field, field.samples.size()); }

engine::Status validateClassification(const GridSpec& grid, const CellClassification& cells) {
  const std::size_t n = std::size_t(grid.cellsPerAxis());
  if (cells.grid.resolution != grid.resolution || cells.grid.spacing != grid.spacing ||
      cells.grid.origin != grid.origin || cells.classes.size() != n * n * n)
    return engine::makeError("the cell classification does not belong to this field's grid");
  return {};
}
engine::Status validateField(const TrilinearField& field) { return validateField(field, field.values.size()); }

namespace {

RayHit makeHit(const Ray& ray, const glm::ivec3& cell, double t, bool contact) {
  RayHit hit;
  hit.t = t;
  hit.position = ray.origin + t * ray.direction;
  hit.cell = cell;
  hit.contact = contact;
  return hit;
}

glm::dvec3 normalized(const glm::dvec3& g) {
  const double len = glm::length(g);
  return len > 0.0 && std::isfinite(len) ? g / len : glm::dvec3(0.0);
}

}  // namespace

std::optional<RayHit> castHermiteUnchecked(const HermiteField& field, const Ray& ray, const CastOptions& options,
                                           const CellClassification* cells) {
  const GridSpec& grid = field.grid;
  const double h = grid.spacing;
  std::optional<RayHit> result;
  walkCells(grid, ray, options.tMin, options.tMax, [&](const glm::ivec3& cell, double t0, double t1) {
    if (cells != nullptr && !cells->kept(cell.x, cell.y, cell.z)) return false;
    const HermiteCellCorners<double> corners = field.cellCorners<double>(cell.x, cell.y, cell.z);
    const glm::dvec3 u0 = cellLocal(grid, cell, ray.origin + t0 * ray.direction);
    const glm::dvec3 u1 = cellLocal(grid, cell, ray.origin + t1 * ray.direction);
    const std::array<double, 10> line = restrictToSegment<3, double>(toBernstein(corners, h), u0, u1);
    const double tolerance = kContactTolerance / kZeroTolerance * zeroToleranceFor(corners, h);
    const std::optional<SegmentRoot> root = firstRootBernstein(line, tolerance);
    if (!root) return false;
    result = makeHit(ray, cell, t0 + root->s * (t1 - t0), root->contact);
    result->normal = normalized(hermiteValueGradient(corners, h, glm::mix(u0, u1, root->s)).gradient);
    return true;
  });
  return result;
}

std::optional<RayHit> castTrilinearUnchecked(const TrilinearField& field, const Ray& ray, const CastOptions& options) {
  const GridSpec& grid = field.grid;
  const double h = grid.spacing;
  std::optional<RayHit> result;
  walkCells(grid, ray, options.tMin, options.tMax, [&](const glm::ivec3& cell, double t0, double t1) {
    const TrilinearCellCorners<double> corners = field.cellCorners<double>(cell.x, cell.y, cell.z);
    const glm::dvec3 u0 = cellLocal(grid, cell, ray.origin + t0 * ray.direction);
    const glm::dvec3 u1 = cellLocal(grid, cell, ray.origin + t1 * ray.direction);
    const std::array<double, 4> line = restrictToSegment<1, double>(corners, u0, u1);
    double scale = 0.0;
    for (double f : corners) scale = std::max(scale, std::abs(f));
    const std::optional<SegmentRoot> root = firstRootBernstein(line, kContactTolerance * scale);
    if (!root) return false;
    result = makeHit(ray, cell, t0 + root->s * (t1 - t0), root->contact);
    result->normal = normalized(trilinearValueGradient(corners, h, glm::mix(u0, u1, root->s)).gradient);
    return true;
  });
  return result;
}

}  // namespace detail

engine::Expected<std::optional<RayHit>> castRay(const HermiteField& field, const Ray& ray, const CastOptions& options) {
  ENGINE_TRY(detail::validateField(field));
  ENGINE_TRY(detail::validateRay(ray, options));
  return detail::castHermiteUnchecked(field, ray, options, nullptr);
}

engine::Expected<std::optional<RayHit>> castRay(const TrilinearField& field, const Ray& ray,
                                                const CastOptions& options) {
  ENGINE_TRY(detail::validateField(field));
  ENGINE_TRY(detail::validateRay(ray, options));
  return detail::castTrilinearUnchecked(field, ray, options);
}

engine::Expected<std::optional<RayHit>> castRayKeptCells(const HermiteField& field, const CellClassification& cells,
                                                         const Ray& ray, const CastOptions& options) {
  ENGINE_TRY(detail::validateField(field));
  ENGINE_TRY(detail::validateRay(ray, options));
  ENGINE_TRY(detail::validateClassification(field.grid, cells));
  return detail::castHermiteUnchecked(field, ray, options, &cells);
}

}  // namespace hsdf
