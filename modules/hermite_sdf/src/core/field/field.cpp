#include "hermite_sdf/core/field.h"

#include <cmath>
#include <cstdint>
#include <new>

#include <fmt/format.h>

#include "field/index_box.h"
#include "field/parallel.h"
#include "field/stored_sample.h"
#include "hermite_sdf/core/materials.h"

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

using detail::toStoredSample;

// A Hermite field of a source of several materials holds a slot per sample besides the samples.
bool recordsMaterials(const SdfSource& source, FieldKind kind) {
  return kind == FieldKind::Hermite && source.materialSlots() > 0;
}

engine::Status checkBudget(const GridSpec& grid, FieldKind kind, bool materialSlots, std::uint64_t budget) {
  const std::uint64_t bytes = estimateFieldBytes(grid, kind, materialSlots);
  if (bytes > budget)
    return engine::makeError(fmt::format(
        "a {} field of resolution {} ({} samples{}) needs {} bytes ({:.1f} MiB), over the memory budget of {} bytes "
        "({:.1f} MiB)",
        kind == FieldKind::Hermite ? "Hermite" : "trilinear", grid.resolution, grid.sampleCount(),
        materialSlots ? " and their material slots" : "", bytes, double(bytes) / (1024.0 * 1024.0), budget,
        double(budget) / (1024.0 * 1024.0)));
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

// Shared by the dense bakes: validates, checks the budget, allocates `storage`, then samples the
// grid row by row (SdfSource::sampleRow, which coherent sources such as meshes speed up) over
// z-slabs in parallel and hands each row to storeRow(j, k, samples). Row positions
// start + i*step equal grid.samplePosition(i,j,k) bit for bit because rows start at i = 0.
template <class Storage, class StoreRow>
engine::Status bakeDense(const SdfSource& source, const GridSpec& grid, FieldKind kind, const BakeOptions& options,
                         Storage& storage, StoreRow storeRow) {
  ENGINE_TRY(validateGrid(grid));
  ENGINE_TRY(checkBudget(grid, kind, recordsMaterials(source, kind), options.memoryBudgetBytes));
  ENGINE_TRY(allocate(storage, grid.sampleCount()));
  const int n = grid.resolution;
  const glm::dvec3 step(grid.spacing, 0.0, 0.0);
  return detail::runParallel(std::size_t(n), options, [&](std::size_t slab) -> engine::Status {
    const int k = int(slab);
    std::vector<SdfSample> row(static_cast<std::size_t>(n));
    for (int j = 0; j < n; ++j) {
      source.sampleRow(grid.samplePosition(0, j, k), step, row);
      ENGINE_TRY(storeRow(j, k, row));
    }
    return {};
  });
}

}  // namespace

namespace detail {

engine::Expected<HermiteSample> toStoredSample(const SdfSample& s, const GridSpec& grid, int i, int j, int k) {
  const HermiteSample out{float(s.value), float(s.gradient.x), float(s.gradient.y), float(s.gradient.z)};
  if (!std::isfinite(out.f) || !std::isfinite(out.fx) || !std::isfinite(out.fy) || !std::isfinite(out.fz))
    return engine::makeError(fmt::format("source returned a non-finite value or gradient ({}, [{}, {}, {}]) at {}",
                                         s.value, s.gradient.x, s.gradient.y, s.gradient.z,
                                         describeSample(grid, i, j, k)));
  return out;
}

}  // namespace detail

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
  // In 64 bits: 2 * paddingCells overflows int for paddings above 2^30.
  const std::int64_t spanCells = std::int64_t(resolution) - 1 - 2 * std::int64_t(paddingCells);
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

std::uint64_t estimateFieldBytes(const GridSpec& grid, FieldKind kind, bool materialSlots) {
  const std::uint64_t perSample = (kind == FieldKind::Hermite ? sizeof(HermiteSample) : sizeof(float)) +
                                  (materialSlots ? sizeof(MaterialSlot) : 0);
  const std::uint64_t k = grid.resolution > 0 ? std::uint64_t(grid.resolution) : 0;
  return k * k * k * perSample;
}

engine::Expected<HermiteField> bakeHermiteField(const SdfSource& source, const GridSpec& grid,
                                                const BakeOptions& options) {
  HermiteField field;
  field.grid = grid;
  // Sized before the parallel rows write into it (a source of one material records none).
  const bool materials = source.materialSlots() > 0;
  if (materials) {
    ENGINE_TRY(validateGrid(grid));
    ENGINE_TRY(checkBudget(grid, FieldKind::Hermite, true, options.memoryBudgetBytes));
    ENGINE_TRY(allocate(field.materials, grid.sampleCount()));
  }
  ENGINE_TRY(bakeDense(source, grid, FieldKind::Hermite, options, field.samples,
                       [&](int j, int k, const std::vector<SdfSample>& row) -> engine::Status {
                         for (int i = 0; i < grid.resolution; ++i) {
                           ENGINE_TRY_ASSIGN(field.samples[grid.sampleIndex(i, j, k)],
                                             toStoredSample(row[std::size_t(i)], grid, i, j, k));
                           if (materials) field.materials[grid.sampleIndex(i, j, k)] = row[std::size_t(i)].material;
                         }
                         return {};
                       }));
  return field;
}

engine::Expected<TrilinearField> bakeTrilinearField(const SdfSource& source, const GridSpec& grid,
                                                    const BakeOptions& options) {
  TrilinearField field;
  field.grid = grid;
  ENGINE_TRY(bakeDense(source, grid, FieldKind::Trilinear, options, field.values,
                       [&](int j, int k, const std::vector<SdfSample>& row) -> engine::Status {
                         for (int i = 0; i < grid.resolution; ++i) {
                           ENGINE_TRY_ASSIGN(const HermiteSample s, toStoredSample(row[std::size_t(i)], grid, i, j, k));
                           field.values[grid.sampleIndex(i, j, k)] = s.f;
                         }
                         return {};
                       }));
  return field;
}

// ---- Narrow band -------------------------------------------------------------------------------

namespace {

constexpr int kTopBlockSamples = 16;  // samples per axis of a work item
constexpr int kMinBlockSamples = 4;   // blocks this small that stay near are sampled per point

// Per-sample queries in near blocks ask for exact values up to this many cells from the surface:
// every corner of a cell the surface crosses is within sqrt(3) h of it, so these come out exact
// at once instead of a bound now and an exact query in pass 2.
constexpr double kLeafQueryBandCells = 1.8;

// Per-sample flags of the narrow band, so that pass 2 decides a cell from 8 bytes:
// kNear: exact and within the band b (makes its cells candidates); kExact: the stored value is
// exact (otherwise it is a bound >= b); kNegative / kPositive: the sign of the stored value.
enum SampleFlags : std::uint8_t { kNear = 1, kExact = 2, kNegative = 4, kPositive = 8 };

std::uint8_t signFlags(float f) {
  return std::uint8_t((f < 0.0f ? kNegative : 0) | (f > 0.0f ? kPositive : 0));
}

using SampleBox = detail::IndexBox;  // samples

// Pass 1: hierarchical block tests, then per-sample band queries near the surface.
class NarrowBandBaker {
 public:
  NarrowBandBaker(const SdfSource& source, HermiteField& field, std::vector<std::uint8_t>& flags)
      : source_(source),
        field_(field),
        flags_(flags),
        band_(kNarrowBandExactCells * field.grid.spacing),
        queryBand_(std::max(kLeafQueryBandCells, kNarrowBandExactCells) * field.grid.spacing) {}

  engine::Status processBlock(const SampleBox& box) const {
    const GridSpec& grid = field_.grid;
    const glm::dvec3 centre = grid.origin + grid.spacing * 0.5 * glm::dvec3(box.lo + box.hi - 1);
    const double radius = grid.spacing * 0.5 * glm::length(glm::dvec3(box.hi - 1 - box.lo));
    // A band query: sources with costly exact distances (meshes) answer far points cheaply.
    const SdfBandSample probe = source_.sampleBand(centre, radius + band_);
    const double value = probe.sample.value;
    if (!std::isfinite(value))
      return engine::makeError(fmt::format("source returned a non-finite value {} at block centre ({}, {}, {})", value,
                                           centre.x, centre.y, centre.z));
    if (!probe.exact || std::abs(value) - radius > band_) {
      fillBound(box, centre, value);
      return {};
    }
    const glm::ivec3 size = box.hi - box.lo;
    if (size.x <= kMinBlockSamples && size.y <= kMinBlockSamples && size.z <= kMinBlockSamples)
      return sampleLeaf(box, centre, value);
    return processChildren(box);
  }

 private:
  // Splits every axis longer than the minimum block in two and processes the parts.
  engine::Status processChildren(const SampleBox& box) const {
    return detail::forEachHalf(box, kMinBlockSamples, [this](const SampleBox& part) { return processBlock(part); });
  }

  // Sign of `distance` times the 1-Lipschitz bound |distance| - |p - centre| (> band here).
  void storeBound(int i, int j, int k, const glm::dvec3& centre, double distance) const {
    const GridSpec& grid = field_.grid;
    const double bound = std::abs(distance) - glm::length(grid.samplePosition(i, j, k) - centre);
    const float f = float(distance < 0.0 ? -bound : bound);
    field_.samples[grid.sampleIndex(i, j, k)] = {f, 0.0f, 0.0f, 0.0f};
    flags_[grid.sampleIndex(i, j, k)] = signFlags(f);
  }

  // storeBound over a whole block, with the per-row work hoisted (most samples are filled here).
  void fillBound(const SampleBox& box, const glm::dvec3& centre, double distance) const {
    const GridSpec& grid = field_.grid;
    const float sign = distance < 0.0 ? -1.0f : 1.0f;
    const std::uint8_t flags = signFlags(sign);
    for (int k = box.lo.z; k < box.hi.z; ++k)
      for (int j = box.lo.y; j < box.hi.y; ++j) {
        const glm::dvec3 rowStart = grid.samplePosition(box.lo.x, j, k) - centre;
        const double across = rowStart.y * rowStart.y + rowStart.z * rowStart.z;
        const std::size_t index = grid.sampleIndex(box.lo.x, j, k);
        for (int i = 0; i < box.hi.x - box.lo.x; ++i) {
          const double dx = grid.samplePosition(box.lo.x + i, j, k).x - centre.x;
          const float bound = float(std::abs(distance) - std::sqrt(dx * dx + across));
          field_.samples[index + std::size_t(i)] = {sign * bound, 0.0f, 0.0f, 0.0f};
          flags_[index + std::size_t(i)] = flags;
        }
      }
  }

  // Leaf block near the surface; `distance` is the exact value at the block centre. Samples it
  // already bounds by more than the band get that bound for free, the others a band query with
  // the wider query band: exact if the surface is that close, else a sign and a bound >= band.
  engine::Status sampleLeaf(const SampleBox& box, const glm::dvec3& centre, double distance) const {
    const GridSpec& grid = field_.grid;
    for (int k = box.lo.z; k < box.hi.z; ++k)
      for (int j = box.lo.y; j < box.hi.y; ++j)
        for (int i = box.lo.x; i < box.hi.x; ++i) {
          const glm::dvec3 p = grid.samplePosition(i, j, k);
          if (std::abs(distance) - glm::length(p - centre) > band_) {
            storeBound(i, j, k, centre, distance);
            continue;
          }
          const SdfBandSample s = source_.sampleBand(p, queryBand_);
          SdfSample stored = s.sample;
          if (!s.exact) stored.gradient = glm::dvec3(0.0);
          ENGINE_TRY_ASSIGN(field_.samples[grid.sampleIndex(i, j, k)], toStoredSample(stored, grid, i, j, k));
          if (!field_.materials.empty()) field_.materials[grid.sampleIndex(i, j, k)] = stored.material;
          const std::uint8_t exactness = !s.exact ? 0 : (std::abs(s.sample.value) <= band_ ? kNear | kExact : kExact);
          flags_[grid.sampleIndex(i, j, k)] = std::uint8_t(exactness | signFlags(field_.samples[grid.sampleIndex(i, j, k)].f));
        }
    return {};
  }

  const SdfSource& source_;
  HermiteField& field_;
  std::vector<std::uint8_t>& flags_;
  double band_;       // b: exact samples within it make their cells candidates
  double queryBand_;  // band of the per-sample queries (>= b)
};

// Pass 2 for one z-slab of cells: a cell that may be kept (a near corner, or corners of both
// signs) gets exact values at all its corners, from SdfSource::sample like the dense bake.
engine::Status completeCellsOfSlab(const SdfSource& source, HermiteField& field, std::vector<std::uint8_t>& flags,
                                   int cz) {
  const GridSpec& grid = field.grid;
  const int n = grid.cellsPerAxis();
  const std::size_t k = std::size_t(grid.resolution);
  const std::size_t offsets[8] = {0, 1, k, k + 1, k * k, k * k + 1, k * k + k, k * k + k + 1};
  std::vector<std::uint8_t> column(k);  // flags OR-ed over the 4 samples of each x in this cell row
  for (int cy = 0; cy < n; ++cy) {
    const std::size_t row = grid.sampleIndex(0, cy, cz);
    for (std::size_t x = 0; x < k; ++x)
      column[x] = std::uint8_t(flags[row + x] | flags[row + k + x] | flags[row + k * k + x] | flags[row + k * k + k + x]);
    for (int cx = 0; cx < n; ++cx) {
      const std::uint8_t any = std::uint8_t(column[std::size_t(cx)] | column[std::size_t(cx) + 1]);
      const bool bothSigns = (any & kNegative) && (any & kPositive);
      if (!(any & kNear) && !bothSigns) continue;
      for (int c = 0; c < 8; ++c) {
        const std::size_t s = row + std::size_t(cx) + offsets[c];
        if (flags[s] & kExact) continue;
        const int i = cx + (c & 1), j = cy + ((c >> 1) & 1), l = cz + ((c >> 2) & 1);
        const SdfSample exact = source.sample(grid.samplePosition(i, j, l));
        ENGINE_TRY_ASSIGN(field.samples[s], toStoredSample(exact, grid, i, j, l));
        if (!field.materials.empty()) field.materials[s] = exact.material;
        flags[s] = std::uint8_t(flags[s] | kExact);  // its cell row's column entry stays valid: same signs
      }
    }
  }
  return {};
}

// Options whose progress callback maps [0,1] onto [from, to] of the caller's range.
BakeOptions withProgressRange(const BakeOptions& options, float from, float to) {
  BakeOptions scaled = options;
  if (options.progress)
    scaled.progress = [progress = options.progress, from, to](float f) { return progress(from + (to - from) * f); };
  return scaled;
}

}  // namespace

engine::Expected<HermiteField> bakeHermiteFieldNarrowBand(const SdfSource& source, const GridSpec& grid,
                                                          const BakeOptions& options) {
  ENGINE_TRY(validateGrid(grid));
  ENGINE_TRY(checkBudget(grid, FieldKind::Hermite, recordsMaterials(source, FieldKind::Hermite),
                         options.memoryBudgetBytes));
  HermiteField field;
  field.grid = grid;
  ENGINE_TRY(allocate(field.samples, grid.sampleCount()));
  if (source.materialSlots() > 0) ENGINE_TRY(allocate(field.materials, grid.sampleCount()));
  std::vector<std::uint8_t> flags;
  ENGINE_TRY(allocate(flags, grid.sampleCount()));

  const std::size_t blocksPerAxis = std::size_t((grid.resolution + kTopBlockSamples - 1) / kTopBlockSamples);
  const NarrowBandBaker baker(source, field, flags);
  ENGINE_TRY(detail::runParallel(blocksPerAxis * blocksPerAxis * blocksPerAxis, withProgressRange(options, 0.0f, 0.8f),
                                 [&](std::size_t item) -> engine::Status {
                                   const glm::ivec3 block(int(item % blocksPerAxis), int(item / blocksPerAxis % blocksPerAxis),
                                                          int(item / (blocksPerAxis * blocksPerAxis)));
                                   const glm::ivec3 lo = block * kTopBlockSamples;
                                   const glm::ivec3 hi = glm::min(lo + kTopBlockSamples, glm::ivec3(grid.resolution));
                                   return baker.processBlock({lo, hi});
                                 }));
  // Cell slab cz touches sample layers cz and cz+1: even slabs first, then odd ones, so that
  // no two threads ever write the same sample.
  const std::size_t slabs = std::size_t(grid.cellsPerAxis());
  for (std::size_t parity = 0; parity < 2; ++parity) {
    const float from = parity == 0 ? 0.8f : 0.9f;
    ENGINE_TRY(detail::runParallel((slabs + 1 - parity) / 2, withProgressRange(options, from, from + 0.1f),
                                   [&](std::size_t item) {
                                     return completeCellsOfSlab(source, field, flags, int(2 * item + parity));
                                   }));
  }
  return field;
}

}  // namespace hsdf
