#pragma once
// Fields: regular grids of K samples per axis. Sample (i,j,k) lies at origin + spacing*(i,j,k);
// samples are stored x fastest, then y, then z. A grid of K samples per axis has (K-1)^3 cells.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/expected.h"
#include "engine/core/progress.h"
#include "hermite_sdf/core/hermite.h"
#include "hermite_sdf/core/source.h"

namespace hsdf {

struct GridSpec {
  int resolution = 0;          // K: samples per axis
  glm::dvec3 origin{0.0};      // world position of sample (0,0,0)
  double spacing = 1.0;        // h: distance between neighbouring samples

  int cellsPerAxis() const { return resolution - 1; }
  std::size_t sampleCount() const {
    return std::size_t(resolution) * std::size_t(resolution) * std::size_t(resolution);
  }
  std::size_t sampleIndex(int i, int j, int k) const {
    return std::size_t(i) + std::size_t(resolution) * (std::size_t(j) + std::size_t(resolution) * std::size_t(k));
  }
  glm::dvec3 samplePosition(int i, int j, int k) const { return origin + spacing * glm::dvec3(i, j, k); }
  Aabb bounds() const { return {origin, origin + spacing * double(resolution - 1)}; }
};

// One Hermite sample: value f and gradient (fx, fy, fz) in world units. 16 bytes, GPU friendly.
struct HermiteSample {
  float f = 0.0f;
  float fx = 0.0f;
  float fy = 0.0f;
  float fz = 0.0f;
};
static_assert(sizeof(HermiteSample) == 16);

struct HermiteField {
  GridSpec grid;
  std::vector<HermiteSample> samples;  // grid.sampleCount() entries
  // A multi-material bake's material slot of every sample (materials.h), in the order of
  // `samples`; empty for a source of one material.
  std::vector<std::uint8_t> materials;
  const HermiteSample& at(int i, int j, int k) const { return samples[grid.sampleIndex(i, j, k)]; }
  // The 8 corners of cell (cx,cy,cz) (corner index x + 2y + 4z), widened to T for the cell maths.
  template <class T = double>
  HermiteCellCorners<T> cellCorners(int cx, int cy, int cz) const {
    HermiteCellCorners<T> out{};
    for (int c = 0; c < 8; ++c) {
      const HermiteSample& s = at(cx + (c & 1), cy + ((c >> 1) & 1), cz + ((c >> 2) & 1));
      out[c] = {T(s.f), T(s.fx), T(s.fy), T(s.fz)};
    }
    return out;
  }
};

struct TrilinearField {
  GridSpec grid;
  std::vector<float> values;  // grid.sampleCount() entries
  float at(int i, int j, int k) const { return values[grid.sampleIndex(i, j, k)]; }
  template <class T = double>
  TrilinearCellCorners<T> cellCorners(int cx, int cy, int cz) const {
    TrilinearCellCorners<T> out{};
    for (int c = 0; c < 8; ++c) out[c] = T(at(cx + (c & 1), cy + ((c >> 1) & 1), cz + ((c >> 2) & 1)));
    return out;
  }
};

// ---- Grids -------------------------------------------------------------------------------------

// Largest K accepted anywhere (cell coordinates must fit the 16-bit cell stream records).
inline constexpr int kMaxResolution = 4096;

// Checks a grid: 2 <= K <= kMaxResolution, spacing finite and > 0, origin finite.
engine::Status validateGrid(const GridSpec& grid);

// A cubic grid of K samples per axis around `bounds`: the longest side of the box spans
// K-1-2P cells, P cells of padding lie on each side, and the grid is centred on the box.
// Errors: K < 2, K-1-2P < 1, P < 0, K > kMaxResolution, NaN/inf or inverted bounds, zero-size box.
engine::Expected<GridSpec> fitGrid(const Aabb& bounds, int resolution, int paddingCells);

enum class FieldKind { Hermite, Trilinear };

// Bytes the samples of a field on `grid` occupy (16 per Hermite sample, 4 per trilinear sample),
// with `materialSlots` (a Hermite field of a source of several materials) one more per sample: the
// slot of each (HermiteField::materials).
std::uint64_t estimateFieldBytes(const GridSpec& grid, FieldKind kind, bool materialSlots = false);

// ---- Baking ------------------------------------------------------------------------------------

struct BakeOptions {
  std::uint64_t memoryBudgetBytes = std::uint64_t(4) << 30;  // refuse larger fields (4 GiB)
  engine::ProgressCallback progress;                         // called from the calling thread only
  const engine::CancelToken* cancel = nullptr;               // checked while baking
  unsigned threads = 0;                                      // 0: all hardware threads
};

// Dense bakes: every sample is source.sample(grid.samplePosition(i,j,k)), converted to float.
// Errors: invalid grid, over budget (names both numbers), non-finite source output (names the
// sample and position), "cancelled" (token or progress callback returning false).
engine::Expected<HermiteField> bakeHermiteField(const SdfSource& source, const GridSpec& grid,
                                                const BakeOptions& options = {});
engine::Expected<TrilinearField> bakeTrilinearField(const SdfSource& source, const GridSpec& grid,
                                                    const BakeOptions& options = {});

// Narrow-band bake for the sparse cell path: exact samples wherever a cell may be kept, elsewhere
// a sign-correct lower bound of |distance| (>= the band) with a zero gradient. Relies on the
// source being 1-Lipschitz with |gradient| <= 1 (true for the SDFs here). Band b =
// kNarrowBandExactCells * h.
//   Pass 1: blocks of samples are tested hierarchically (16^3 -> 8^3 -> 4^3) with one band query
//   (SdfSource::sampleBand) at the block centre c with band r + b (r = distance from c to the
//   block's farthest sample): if the surface is farther, every sample p of the block gets
//   f = sign(d) * (|d(c)| - |p - c|) (> b, a valid bound) and gradient 0. In 4^3 blocks that stay
//   near, each sample gets sampleBand(p, 1.8 h): exact (and "near" if |f| <= b) or a bound >= b;
//   1.8 h > sqrt(3) h makes every corner of a crossed cell exact in this pass already.
//   Pass 2: every cell with a near corner or corners of both signs gets exact values
//   (SdfSource::sample) at all its corners.
// Why the classification then equals the dense field's, with bit-identical kept cells: a cell
// that pass 2 skipped has all corners of one sign with true |f| > b > h/sqrt(3) >= (h/3)|grad|_1,
// so all 64 of its dense Bernstein coefficients are strictly of that sign (Empty), and in the
// narrow-band field its bound corners contribute coefficients f (zero gradient) of the same sign
// (Empty too). Every other cell has only exact corners, sampled at grid.samplePosition(i,j,k) as
// in the dense bake. b = 0.75 h leaves slack for |grad| up to 1.3.
inline constexpr double kNarrowBandExactCells = 0.75;
engine::Expected<HermiteField> bakeHermiteFieldNarrowBand(const SdfSource& source, const GridSpec& grid,
                                                          const BakeOptions& options = {});

}  // namespace hsdf
