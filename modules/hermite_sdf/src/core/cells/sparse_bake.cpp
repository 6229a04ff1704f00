#include "hermite_sdf/core/sparse_bake.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>
#include <memory>
#include <type_traits>
#include <vector>

#include <fmt/format.h>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "field/index_box.h"
#include "field/parallel.h"
#include "field/stored_sample.h"

namespace hsdf {
namespace {

constexpr int kTopBrickCells = 16;  // bricks of a work item's slab; their samples are cached together
constexpr int kLeafBrickCells = 4;  // bricks this small that stay near are examined cell by cell
constexpr int kCacheSide = kTopBrickCells + 1;

// Cells lo (inclusive) to hi (exclusive); their samples run lo..hi inclusive.
using CellBox = detail::IndexBox;

// The records are written once into fresh memory and copied once into the stream: at K = 1024
// that is 2 x 460 MB first touched, and on 4 KiB pages the page faults alone took ~10 % of the bake
// (perf, BM_BakeSparseBunny/512). Both go on transparent huge pages where the kernel offers them
// on request (Linux "madvise" mode, Debian's default): one fault per 2 MiB instead of 512.
constexpr std::size_t kHugePage = std::size_t(2) << 20;

void adviseHugePages(void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  const auto begin = (reinterpret_cast<std::uintptr_t>(data) + kHugePage - 1) & ~std::uintptr_t(kHugePage - 1);
  const auto end = (reinterpret_cast<std::uintptr_t>(data) + bytes) & ~std::uintptr_t(kHugePage - 1);
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);  // a hint: failure is harmless
#else
  (void)data, (void)bytes;
#endif
}

struct AlignedFree {
  void operator()(std::byte* p) const { std::free(p); }
};

// Records in fixed-size chunks: appending never moves or copies what is stored (a growing vector
// would copy every record about twice and hold up to twice its size), and the slack is one chunk.
// The chunks are raw bytes, one huge page each, written once by push(): first touches of fresh
// memory (page faults, and zeroing a value-initialised array) are most of the cost of storing a record.
class RecordChunks {
 public:
  static constexpr std::size_t kChunk = kHugePage / sizeof(CellRecord);  // records (15,420)

  void push(const CellRecord& record) {
    if (size_ % kChunk == 0) chunks_.push_back(newChunk());
    std::memcpy(&chunks_.back()[(size_ % kChunk) * sizeof(CellRecord)], &record, sizeof(CellRecord));
    ++size_;
  }
  CellRecord operator[](std::size_t i) const {
    CellRecord record;
    std::memcpy(&record, &chunks_[i / kChunk][(i % kChunk) * sizeof(CellRecord)], sizeof(CellRecord));
    return record;
  }
  std::size_t size() const { return size_; }
  void clear() {
    chunks_.clear();
    size_ = 0;
  }

 private:
  using Chunk = std::unique_ptr<std::byte[], AlignedFree>;
  static Chunk newChunk() {
    auto* bytes = static_cast<std::byte*>(std::aligned_alloc(kHugePage, kHugePage));
    if (bytes == nullptr) throw std::bad_alloc();
    adviseHugePages(bytes, kHugePage);
    return Chunk(bytes);
  }

  static_assert(std::is_trivially_copyable_v<CellRecord>);
  std::vector<Chunk> chunks_;
  std::size_t size_ = 0;
};

// Where a kept record goes: its cell's index within the slab (z, then y, then x, as the stream
// orders cells) and its position in the slab's chunks. Sorting these 8-byte keys orders the slab
// without moving any 136-byte record. 32 bits suffice: a slab has at most 16 * 4095^2 < 2^32 cells.
struct RecordOrder {
  std::uint32_t cellInSlab = 0;
  std::uint32_t record = 0;
};

// What the slab of one work item found: its kept records, their order, and its counts.
struct SlabResult {
  RecordChunks records;
  std::vector<CellMaterialSlots> materials;  // per record in push order, for a source with materials
  std::vector<RecordOrder> order;  // sorted by cellInSlab once the slab is done
  std::uint64_t crossing = 0, ambiguous = 0, refinedEmpty = 0;
  std::uint64_t sampleQueries = 0, brickProbes = 0;
};

// The samples of one top brick, evaluated on first use: a sample is needed by up to 8 cells and
// by up to 8 leaves of the brick, and is computed once for all of them.
class BrickSampleCache {
 public:
  enum class State : std::uint8_t { Unknown, Exact, Far };

  // O(1), not a fill: at K = 2048 there are 2 million top bricks, most of them pruned by their
  // first probe, and clearing 5 KiB of states for each would cost seconds.
  void reset(const glm::ivec3& firstSample) {
    origin_ = firstSample;
    ++brick_;
  }
  std::size_t index(const glm::ivec3& s) const {
    const glm::ivec3 d = s - origin_;
    return std::size_t(d.x) + std::size_t(kCacheSide) * (std::size_t(d.y) + std::size_t(kCacheSide) * std::size_t(d.z));
  }
  // Entry i's state; Unknown when it was last written for an earlier brick.
  State& state(std::size_t i) {
    if (stamps_[i] != brick_) {
      stamps_[i] = brick_;
      states_[i] = State::Unknown;
    }
    return states_[i];
  }
  HermiteSample& sample(std::size_t i) { return samples_[i]; }
  MaterialSlot& material(std::size_t i) { return materials_[i]; }
  // The slot stored beside a sample this cache handed out (sampleAt's pointer).
  MaterialSlot materialOf(const HermiteSample* s) const { return materials_[std::size_t(s - samples_.data())]; }

 private:
  glm::ivec3 origin_{0};
  std::uint32_t brick_ = 0;  // bricks reset so far (a slab has at most 256^2)
  std::array<std::uint32_t, kCacheSide * kCacheSide * kCacheSide> stamps_{};  // brick_ when written
  std::array<State, kCacheSide * kCacheSide * kCacheSide> states_{};
  std::array<HermiteSample, kCacheSide * kCacheSide * kCacheSide> samples_{};
  std::array<MaterialSlot, kCacheSide * kCacheSide * kCacheSide> materials_{};
};

// The budget: cells kept so far over all slabs, checked after every top brick.
class KeptCellBudget {
 public:
  KeptCellBudget(const SparseBakeOptions& options, bool materialSlots)
      : options_(options), bytesPerCell_(sparseBakeBytesPerKeptCell(materialSlots)) {}

  engine::Status add(std::uint64_t cells) {
    const std::uint64_t kept = kept_.fetch_add(cells) + cells;
    if (kept > options_.maxKeptCells)
      return engine::makeError(fmt::format("more than {} kept cells (stopped at {}), over the bake budget's max kept "
                                           "cells {}",
                                           options_.maxKeptCells, kept, options_.maxKeptCells));
    const std::uint64_t bytes = kept * bytesPerCell_;
    if (bytes > options_.maxBytes)
      return engine::makeError(fmt::format("{} kept cells need {} bytes ({:.1f} MiB) at {} bytes a cell, over the bake "
                                           "budget's max bytes {} ({:.1f} MiB)",
                                           kept, bytes, double(bytes) / 1048576.0, bytesPerCell_,
                                           options_.maxBytes, double(options_.maxBytes) / 1048576.0));
    return {};
  }

 private:
  const SparseBakeOptions& options_;
  const std::uint64_t bytesPerCell_;
  std::atomic<std::uint64_t> kept_{0};
};

// One work item: a slab of kTopBrickCells cell layers in z over the whole x, y extent.
class SlabBaker {
 public:
  SlabBaker(const SdfSource& source, const GridSpec& grid, int refineDepth, KeptCellBudget& budget)
      : source_(source),
        grid_(grid),
        refineDepth_(refineDepth),
        budget_(budget),
        margin_(kSparsePruneMarginCells * grid.spacing),
        leafBand_(kSparseLeafQueryCells * grid.spacing),
        materials_(source.materialSlots() > 0) {}

  engine::Status bakeSlab(int cz, SlabResult& out) {
    const int n = grid_.cellsPerAxis();
    for (int by = 0; by < n; by += kTopBrickCells)
      for (int bx = 0; bx < n; bx += kTopBrickCells) {
        const glm::ivec3 lo(bx, by, cz);
        const std::size_t before = out.records.size();
        cache_.reset(lo);
        ENGINE_TRY(descend({lo, glm::min(lo + kTopBrickCells, glm::ivec3(n))}, out));
        ENGINE_TRY(budget_.add(out.records.size() - before));
      }
    sortByCellIndex(out.order);
    return {};
  }

 private:
  // Prunes the box when the surface is provably farther than its half-diagonal + margin (file
  // comment of sparse_bake.h), else splits it down to leaves.
  engine::Status descend(const CellBox& box, SlabResult& out) {
    const glm::dvec3 centre = grid_.origin + grid_.spacing * 0.5 * glm::dvec3(box.lo + box.hi);
    const double radius = grid_.spacing * 0.5 * glm::length(glm::dvec3(box.hi - box.lo));
    const std::optional<SdfSample> probe = source_.sampleNear(centre, radius + margin_);
    ++out.brickProbes;
    // None: the source itself proved the surface farther than radius + margin.
    if (!probe) return {};
    if (!std::isfinite(probe->value))
      return engine::makeError(fmt::format("source returned a non-finite value {} at brick centre ({}, {}, {})",
                                           probe->value, centre.x, centre.y, centre.z));
    if (std::abs(probe->value) - radius >= margin_) return {};
    const glm::ivec3 size = box.hi - box.lo;
    if (size.x <= kLeafBrickCells && size.y <= kLeafBrickCells && size.z <= kLeafBrickCells)
      return examineLeaf(box, centre, probe->value, out);
    return descendChildren(box, out);
  }

  // Halves every axis longer than a leaf and descends into the parts.
  engine::Status descendChildren(const CellBox& box, SlabResult& out) {
    return detail::forEachHalf(box, kLeafBrickCells, [this, &out](const CellBox& part) { return descend(part, out); });
  }

  // Every cell of a leaf whose 8 corners are exact is classified; a cell with a far corner is
  // Empty (sparse_bake.h) and costs no more queries.
  engine::Status examineLeaf(const CellBox& box, const glm::dvec3& centre, double distance, SlabResult& out) {
    for (int cz = box.lo.z; cz < box.hi.z; ++cz)
      for (int cy = box.lo.y; cy < box.hi.y; ++cy)
        for (int cx = box.lo.x; cx < box.hi.x; ++cx) {
          StoredCellCorners corners{};
          bool far = false;
          for (int c = 0; c < 8 && !far; ++c) {
            const glm::ivec3 s(cx + (c & 1), cy + ((c >> 1) & 1), cz + ((c >> 2) & 1));
            ENGINE_TRY_ASSIGN(corners[std::size_t(c)], sampleAt(s, centre, distance, out));
            far = corners[std::size_t(c)] == nullptr;
          }
          if (!far) keepIfNotEmpty(glm::ivec3(cx, cy, cz), corners, out);
        }
    return {};
  }

  // The exact stored sample s, or nullptr when the surface is farther than the leaf band q from
  // it. `distance` (exact, at `centre`) bounds it first: 1-Lipschitz, |f(s)| >= |distance| - |s - centre|.
  engine::Expected<const HermiteSample*> sampleAt(const glm::ivec3& s, const glm::dvec3& centre, double distance,
                                                  SlabResult& out) {
    const std::size_t i = cache_.index(s);
    BrickSampleCache::State& state = cache_.state(i);
    if (state == BrickSampleCache::State::Unknown) {
      const glm::dvec3 p = grid_.samplePosition(s.x, s.y, s.z);
      if (std::abs(distance) - glm::length(p - centre) >= leafBand_) {
        state = BrickSampleCache::State::Far;
      } else {
        const std::optional<SdfSample> q = source_.sampleNear(p, leafBand_);
        ++out.sampleQueries;
        if (q) {
          ENGINE_TRY_ASSIGN(cache_.sample(i), detail::toStoredSample(*q, grid_, s.x, s.y, s.z));
          cache_.material(i) = q->material;
        }
        // An exact value beyond q proves as much as a bound would (and analytic sources, whose
        // band queries are always exact, would otherwise fetch every corner of far cells).
        const bool far = !q || std::abs(q->value) >= leafBand_;
        state = far ? BrickSampleCache::State::Far : BrickSampleCache::State::Exact;
      }
    }
    return state == BrickSampleCache::State::Exact ? &cache_.sample(i) : nullptr;
  }

  void keepIfNotEmpty(const glm::ivec3& cell, const StoredCellCorners& corners, SlabResult& out) {
    const StoredCellDecision d = classifyStoredCell(corners, grid_.spacing, refineDepth_);
    out.refinedEmpty += d.refinedEmpty;
    if (d.cellClass == CellClass::Empty) return;
    out.crossing += d.cellClass == CellClass::Crossing;
    out.ambiguous += d.cellClass == CellClass::Ambiguous;
    CellRecord record;
    for (std::size_t c = 0; c < 8; ++c) record.corners[c] = *corners[c];
    record.x = std::uint16_t(cell.x);
    record.y = std::uint16_t(cell.y);
    record.z = std::uint16_t(cell.z);
    record.cellClass = std::uint16_t(d.cellClass);
    const std::uint32_t layer = std::uint32_t(cell.z % kTopBrickCells), n = std::uint32_t(grid_.cellsPerAxis());
    out.order.push_back({(layer * n + std::uint32_t(cell.y)) * n + std::uint32_t(cell.x), std::uint32_t(out.records.size())});
    out.records.push(record);
    if (materials_) {
      CellMaterialSlots slots{};
      for (std::size_t c = 0; c < 8; ++c) slots[c] = cache_.materialOf(corners[c]);
      out.materials.push_back(slots);
    }
  }

  // Cell index order (x fastest, then y, then z), as extractCells writes the dense bake's records.
  static void sortByCellIndex(std::vector<RecordOrder>& order) {
    std::sort(order.begin(), order.end(),
              [](const RecordOrder& a, const RecordOrder& b) { return a.cellInSlab < b.cellInSlab; });
  }

  const SdfSource& source_;
  const GridSpec& grid_;
  int refineDepth_;
  KeptCellBudget& budget_;
  double margin_;    // m
  double leafBand_;  // q
  bool materials_;   // the source reports material slots: the records get their corners'
  BrickSampleCache cache_;
};

engine::Status checkOptions(const GridSpec& grid, const SparseBakeOptions& options) {
  ENGINE_TRY(validateGrid(grid));
  if (options.refineDepth < 0 || options.refineDepth > 2)
    return engine::makeError(fmt::format("refinement depth {} is outside 0..2", options.refineDepth));
  return {};
}

// Slabs in z order, each in its sorted order, concatenated: the stream in cell index order. Each
// slab's records are freed once copied.
SparseBakeResult assemble(const GridSpec& grid, std::vector<SlabResult>& slabs) {
  SparseBakeResult result;
  result.cells.grid = grid;
  std::size_t total = 0;
  for (const SlabResult& slab : slabs) total += slab.records.size();
  result.cells.records.reserve(total);  // not resize(): zeroing the stream first would touch it twice
  adviseHugePages(result.cells.records.data(), total * sizeof(CellRecord));
  const bool materials = std::any_of(slabs.begin(), slabs.end(), [](const SlabResult& s) { return !s.materials.empty(); });
  if (materials) result.cells.materials.reserve(total);
  for (SlabResult& slab : slabs) {
    for (const RecordOrder& o : slab.order) result.cells.records.push_back(slab.records[o.record]);
    if (materials)
      for (const RecordOrder& o : slab.order) result.cells.materials.push_back(slab.materials[o.record]);
    std::vector<CellMaterialSlots>().swap(slab.materials);
    slab.records.clear();
    std::vector<RecordOrder>().swap(slab.order);
    result.stats.crossing += slab.crossing;
    result.stats.ambiguous += slab.ambiguous;
    result.stats.refinedEmpty += slab.refinedEmpty;
    result.sampleQueries += slab.sampleQueries;
    result.brickProbes += slab.brickProbes;
  }
  const std::uint64_t n = std::uint64_t(grid.cellsPerAxis());
  result.stats.cells = n * n * n;
  result.stats.empty = result.stats.cells - result.stats.kept();
  return result;
}

}  // namespace

engine::Expected<SparseBakeResult> bakeCellsSparse(const SdfSource& source, const GridSpec& grid,
                                                   const SparseBakeOptions& options) {
  ENGINE_TRY(checkOptions(grid, options));
  const int n = grid.cellsPerAxis();
  std::vector<SlabResult> slabs(std::size_t((n + kTopBrickCells - 1) / kTopBrickCells));
  KeptCellBudget budget(options, source.materialSlots() > 0);
  BakeOptions run;
  run.progress = options.progress;
  run.cancel = options.cancel;
  run.threads = options.threads;
  ENGINE_TRY(detail::runParallel(slabs.size(), run, [&](std::size_t slab) -> engine::Status {
    // On the heap: the brick's sample cache is 100 KiB.
    const auto baker = std::make_unique<SlabBaker>(source, grid, options.refineDepth, budget);
    return baker->bakeSlab(int(slab) * kTopBrickCells, slabs[slab]);
  }));
  return assemble(grid, slabs);
}

}  // namespace hsdf
