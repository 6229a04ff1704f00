#include "hermite_sdf/field.h"

#include <cmath>
#include <new>

#include <fmt/format.h>

#include "field/parallel.h"

namespace hsdf {
namespace {

bool isFinite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string describeBox(const Aabb& b) {
  return fmt::format("[({}, {}, {}) .. ({}, {}, {})]", b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z);
}

std::string describeSample(const GridSpec& grid, int i, int j, int k) {
  const glm::dvec3 p = grid.samplePosition(i, j, k);
  return fmt::format("sample ({}, {}, {}) at position ({}, {}, {})", i, j, k, p.x, p.y, p.z);
}

// Converts a source sample to the stored float form; fails if anything is not finite in float.
engine::Expected<HermiteSample> toStoredSample(const SdfSample& s, const GridSpec& grid, int i, int j, int k) {
  const HermiteSample out{float(s.value), float(s.gradient.x), float(s.gradient.y), float(s.gradient.z)};
  if (!std::isfinite(out.f) || !std::isfinite(out.fx) || !std::isfinite(out.fy) || !std::isfinite(out.fz))
    return engine::makeError(fmt::format("source returned a non-finite value or gradient ({}, [{}, {}, {}]) at {}",
                                         s.value, s.gradient.x, s.gradient.y, s.gradient.z,
                                         describeSample(grid, i, j, k)));
  return out;
}

engine::Status checkBudget(const GridSpec& grid, FieldKind kind, std::uint64_t budget) {
  const std::uint64_t bytes = estimateFieldBytes(grid, kind);
  if (bytes > budget)
    return engine::makeError(fmt::format(
        "a {} field of resolution {} ({} samples) needs {} bytes ({:.1f} MiB), over the memory budget of {} bytes "
        "({:.1f} MiB)",
        kind == FieldKind::Hermite ? "Hermite" : "trilinear", grid.resolution, grid.sampleCount(), bytes,
        double(bytes) / (1024.0 * 1024.0), budget, double(budget) / (1024.0 * 1024.0)));
  return {};
}

// Allocates `count` default elements, turning allocation failure into an error.
template <class T>
engine::Status allocate(std::vector<T>& out, std::size_t count) {
  try {
    out.assign(count, T{});
  } catch (const std::bad_alloc&) {
    return engine::makeError(fmt::format("out of memory allocating {} bytes for the field", count * sizeof(T)));
  }
  return {};
}

// Shared by the dense bakes: validates, checks the budget, allocates `storage`, then runs
// writeSample(i,j,k) over z-slabs in parallel.
template <class Storage, class WriteSample>
engine::Status bakeDense(const GridSpec& grid, FieldKind kind, const BakeOptions& options, Storage& storage,
                         WriteSample writeSample) {
  ENGINE_TRY(validateGrid(grid));
  ENGINE_TRY(checkBudget(grid, kind, options.memoryBudgetBytes));
  ENGINE_TRY(allocate(storage, grid.sampleCount()));
  const int n = grid.resolution;
  return detail::runParallel(std::size_t(n), options, [&](std::size_t slab) -> engine::Status {
    const int k = int(slab);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) ENGINE_TRY(writeSample(i, j, k));
    return {};
  });
}

}  // namespace

engine::Status validateGrid(const GridSpec& grid) {
  if (grid.resolution < 2 || grid.resolution > kMaxResolution)
    return engine::makeError(
        fmt::format("grid resolution {} is outside the supported range 2..{}", grid.resolution, kMaxResolution));
  if (!std::isfinite(grid.spacing) || grid.spacing <= 0.0)
    return engine::makeError(fmt::format("grid spacing {} must be finite and positive", grid.spacing));
  if (!isFinite(grid.origin) || !isFinite(grid.samplePosition(grid.resolution, grid.resolution, grid.resolution)))
    return engine::makeError(
        fmt::format("grid origin ({}, {}, {}) is not finite or the grid overflows", grid.origin.x, grid.origin.y,
                    grid.origin.z));
  return {};
}

engine::Expected<GridSpec> fitGrid(const Aabb& bounds, int resolution, int paddingCells) {
  if (resolution < 2 || resolution > kMaxResolution)
    return engine::makeError(fmt::format("resolution {} is outside the supported range 2..{}", resolution, kMaxResolution));
  if (paddingCells < 0) return engine::makeError(fmt::format("padding {} cells must not be negative", paddingCells));
  const int spanCells = resolution - 1 - 2 * paddingCells;
  if (spanCells < 1)
    return engine::makeError(fmt::format(
        "resolution {} with {} padding cells per side leaves {} cells for the shape (need at least 1)", resolution,
        paddingCells, spanCells));
  if (!isFinite(bounds.min) || !isFinite(bounds.max))
    return engine::makeError(fmt::format("bounds {} are not finite", describeBox(bounds)));
  const glm::dvec3 size = bounds.size();
  if (size.x < 0.0 || size.y < 0.0 || size.z < 0.0)
    return engine::makeError(fmt::format("bounds {} are inverted (min > max)", describeBox(bounds)));
  const double longest = std::max(size.x, std::max(size.y, size.z));
  if (!(longest > 0.0) || !std::isfinite(longest))
    return engine::makeError(fmt::format("bounds {} have no extent to fit a grid to", describeBox(bounds)));
  GridSpec grid;
  grid.resolution = resolution;
  grid.spacing = longest / double(spanCells);
  grid.origin = bounds.center() - 0.5 * grid.spacing * double(resolution - 1);
  ENGINE_TRY(validateGrid(grid));
  return grid;
}

std::uint64_t estimateFieldBytes(const GridSpec& grid, FieldKind kind) {
  const std::uint64_t perSample = kind == FieldKind::Hermite ? sizeof(HermiteSample) : sizeof(float);
  const std::uint64_t k = grid.resolution > 0 ? std::uint64_t(grid.resolution) : 0;
  return k * k * k * perSample;
}

engine::Expected<HermiteField> bakeHermiteField(const SdfSource& source, const GridSpec& grid,
                                                const BakeOptions& options) {
  HermiteField field;
  field.grid = grid;
  ENGINE_TRY(bakeDense(grid, FieldKind::Hermite, options, field.samples, [&](int i, int j, int k) -> engine::Status {
    ENGINE_TRY_ASSIGN(field.samples[grid.sampleIndex(i, j, k)],
                      toStoredSample(source.sample(grid.samplePosition(i, j, k)), grid, i, j, k));
    return {};
  }));
  return field;
}

engine::Expected<TrilinearField> bakeTrilinearField(const SdfSource& source, const GridSpec& grid,
                                                    const BakeOptions& options) {
  TrilinearField field;
  field.grid = grid;
  ENGINE_TRY(bakeDense(grid, FieldKind::Trilinear, options, field.values, [&](int i, int j, int k) -> engine::Status {
    ENGINE_TRY_ASSIGN(const HermiteSample s, toStoredSample(source.sample(grid.samplePosition(i, j, k)), grid, i, j, k));
    field.values[grid.sampleIndex(i, j, k)] = s.f;
    return {};
  }));
  return field;
}

// ---- Narrow band -------------------------------------------------------------------------------

namespace {

constexpr int kTopBlockSamples = 16;  // samples per axis of a work item
constexpr int kMinBlockSamples = 4;   // below this, blocks are sampled exactly

struct SampleBox {
  glm::ivec3 lo;  // inclusive
  glm::ivec3 hi;  // exclusive
};

class NarrowBandBaker {
 public:
  NarrowBandBaker(const SdfSource& source, HermiteField& field) : source_(source), field_(field) {}

  engine::Status processBlock(const SampleBox& box) const {
    const GridSpec& grid = field_.grid;
    const glm::dvec3 centre = grid.origin + grid.spacing * 0.5 * glm::dvec3(box.lo + box.hi - 1);
    const double radius = grid.spacing * 0.5 * glm::length(glm::dvec3(box.hi - 1 - box.lo));
    const SdfSample probe = source_.sample(centre);
    if (!std::isfinite(probe.value))
      return engine::makeError(fmt::format("source returned a non-finite value {} at block centre ({}, {}, {})",
                                           probe.value, centre.x, centre.y, centre.z));
    if (std::abs(probe.value) - radius > kNarrowBandMarginCells * grid.spacing) {
      fillBound(box, centre, probe.value);
      return {};
    }
    const glm::ivec3 size = box.hi - box.lo;
    if (size.x <= kMinBlockSamples && size.y <= kMinBlockSamples && size.z <= kMinBlockSamples)
      return sampleExactly(box);
    return processChildren(box);
  }

 private:
  // Splits every axis longer than the minimum block in two and processes the parts.
  engine::Status processChildren(const SampleBox& box) const {
    glm::ivec3 mid = box.hi;
    for (int a = 0; a < 3; ++a)
      if (box.hi[a] - box.lo[a] > kMinBlockSamples) mid[a] = box.lo[a] + (box.hi[a] - box.lo[a]) / 2;
    for (int child = 0; child < 8; ++child) {
      SampleBox part = box;
      bool empty = false;
      for (int a = 0; a < 3; ++a) {
        const bool upper = (child >> a) & 1;
        if (upper && mid[a] == box.hi[a]) empty = true;  // this axis was not split
        part.lo[a] = upper ? mid[a] : box.lo[a];
        part.hi[a] = upper ? box.hi[a] : mid[a];
      }
      if (!empty) ENGINE_TRY(processBlock(part));
    }
    return {};
  }

  void fillBound(const SampleBox& box, const glm::dvec3& centre, double distance) const {
    const GridSpec& grid = field_.grid;
    const double sign = distance < 0.0 ? -1.0 : 1.0;
    for (int k = box.lo.z; k < box.hi.z; ++k)
      for (int j = box.lo.y; j < box.hi.y; ++j)
        for (int i = box.lo.x; i < box.hi.x; ++i) {
          const double bound = std::abs(distance) - glm::length(grid.samplePosition(i, j, k) - centre);
          field_.samples[grid.sampleIndex(i, j, k)] = {float(sign * bound), 0.0f, 0.0f, 0.0f};
        }
  }

  engine::Status sampleExactly(const SampleBox& box) const {
    const GridSpec& grid = field_.grid;
    for (int k = box.lo.z; k < box.hi.z; ++k)
      for (int j = box.lo.y; j < box.hi.y; ++j)
        for (int i = box.lo.x; i < box.hi.x; ++i) {
          ENGINE_TRY_ASSIGN(field_.samples[grid.sampleIndex(i, j, k)],
                            toStoredSample(source_.sample(grid.samplePosition(i, j, k)), grid, i, j, k));
        }
    return {};
  }

  const SdfSource& source_;
  HermiteField& field_;
};

}  // namespace

engine::Expected<HermiteField> bakeHermiteFieldNarrowBand(const SdfSource& source, const GridSpec& grid,
                                                          const BakeOptions& options) {
  ENGINE_TRY(validateGrid(grid));
  ENGINE_TRY(checkBudget(grid, FieldKind::Hermite, options.memoryBudgetBytes));
  HermiteField field;
  field.grid = grid;
  ENGINE_TRY(allocate(field.samples, grid.sampleCount()));
  const int blocksPerAxis = (grid.resolution + kTopBlockSamples - 1) / kTopBlockSamples;
  const NarrowBandBaker baker(source, field);
  ENGINE_TRY(detail::runParallel(std::size_t(blocksPerAxis) * std::size_t(blocksPerAxis) * std::size_t(blocksPerAxis),
                                 options, [&](std::size_t item) -> engine::Status {
                                   const int n = blocksPerAxis;
                                   const glm::ivec3 block(int(item % std::size_t(n)), int(item / std::size_t(n) % std::size_t(n)),
                                                          int(item / (std::size_t(n) * std::size_t(n))));
                                   const glm::ivec3 lo = block * kTopBlockSamples;
                                   const glm::ivec3 hi = glm::min(lo + kTopBlockSamples, glm::ivec3(grid.resolution));
                                   return baker.processBlock({lo, hi});
                                 }));
  return field;
}

}  // namespace hsdf
