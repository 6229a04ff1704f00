#pragma once
// Sparse bake: the kept-cell stream of a source, straight from the source, without a dense K^3
// field or class array, so that time and memory grow with the kept cells (about K^2).
//
// Coarse-to-fine descent over bricks of cells (16^3 -> 8^3 -> 4^3). For a brick with centre c and
// half-diagonal R (centre to its farthest sample), one band query d = SdfSource::sampleNear(c, R + m)
// decides: if the surface is farther than R + m, no cell of the brick is kept and none of its
// samples is ever computed. In a 4^3 leaf that stays, each sample needed by a cell is queried with
// the band q (kSparseLeafQueryCells) and cached per 16^3 brick; cells whose 8 corners are exact are
// classified by classifyStoredCell, the very decision classifyCells makes on a dense field.
//
// Why this keeps exactly the dense bake's cells with bit-identical corners (sources 1-Lipschitz
// with |gradient| <= 1, source.h / analytic.h): a cell is dropped unexamined only when each of its
// corners p has |f(p)| >= m (pruned brick: |f(p)| >= |d(c)| - |p - c| >= R + m - R) or >= q - sqrt(3) h
// (a leaf cell with a corner found farther than q, its other corners lying within sqrt(3) h of it),
// all of one sign (f cannot change sign between them without crossing a zero closer than that).
// Every one of its 64 Bernstein coefficients is f_corner + (h/3)(+-fx +- fy +- fz), and
// (h/3)|grad|_1 <= (h/3) sqrt(3) |grad|_2 <= h/sqrt(3) ~ 0.577 h. With both bounds >= 0.75 h, every
// coefficient keeps its corner's sign by more than 0.17 h, far beyond the float rounding of the
// stored samples and the classifier's zero band (kZeroTolerance): the dense bake makes such a cell
// Empty, by the corner test and by the Bernstein test alike (refinement never runs: the plain test
// already proves it empty). That holds for the Ambiguous class too, whose cells have no corner sign
// change: a cell whose corners all lie 0.75 h or more from the surface cannot be Ambiguous. All
// other cells get exact samples, from the same query sampleBand makes exact (source.h: equal to
// sample(), which the dense bake's sampleRow equals), converted to float the same way.
// Open meshes: their sign comes from the winding number, which can flip across a hole without a
// zero of the distance; there the signed distance is not 1-Lipschitz, and cells that the dense
// bake keeps only for such a flip (no surface in them) may be pruned, as bakeHermiteFieldNarrowBand
// prunes them. Closed meshes and the analytic shapes are exact.
#include <cstdint>

#include "engine/core/expected.h"
#include "engine/core/progress.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/core/field.h"
#include "hermite_sdf/core/source.h"

namespace hsdf {

// m, in cells: the pruning margin (see above: >= 0.75 h keeps 0.17 h of slack over h/sqrt(3)).
inline constexpr double kSparsePruneMarginCells = 0.75;
// q, in cells: a leaf sample farther than q is only a sign; q - sqrt(3) >= 0.75 (see above).
inline constexpr double kSparseLeafQueryCells = 2.5;

// Peak bytes a sparse bake holds per kept cell: while the stream is assembled, the fp32 record in
// its slab's chunks, its 8-byte order key and its copy in the stream. (The asset then holds the
// stream and its fp16 copy, 208 bytes a cell, its proxy codes, 4, and its derived cones and
// bricks, 22 on a torus (cell_derived.h), all made after the slabs are freed.)
inline constexpr std::uint64_t kSparseBakeBytesPerKeptCell = 2 * sizeof(CellRecord) + 8;
// A bake of a source of several materials (SdfSource::materialSlots() > 0) holds each kept cell's
// corner slots twice as well: in its slab and in the stream.
constexpr std::uint64_t sparseBakeBytesPerKeptCell(bool materialSlots) {
  return kSparseBakeBytesPerKeptCell + (materialSlots ? 2 * sizeof(CellMaterialSlots) : 0);
}

struct SparseBakeOptions {
  int refineDepth = 0;  // as ClassifyOptions::refineDepth (0..2)
  // Budget, checked while baking (the kept cells are only known then): the bake stops with an
  // error naming the limit as soon as the cells kept so far exceed either.
  std::uint64_t maxKeptCells = std::uint64_t(-1);
  std::uint64_t maxBytes = std::uint64_t(-1);  // kept cells * sparseBakeBytesPerKeptCell
  engine::ProgressCallback progress;            // called from the calling thread only
  const engine::CancelToken* cancel = nullptr;
  unsigned threads = 0;  // 0: all hardware threads
};

struct SparseBakeResult {
  CellStream cells;  // kept cells in cell index order (x fastest), as extractCells gives them
  CellStats stats;   // as classifyCells counts them (cells = (K-1)^3, empty = all others)
  // Band queries at samples (exact or not), each sample queried at most once per 16^3 brick: the
  // bake's main cost, about 6 per kept cell for the bunny and the sphere.
  std::uint64_t sampleQueries = 0;
  std::uint64_t brickProbes = 0;   // band queries at brick centres
};

// Errors: invalid grid, refineDepth outside 0..2, non-finite source output (names the sample),
// over the budget (names the limit), "cancelled".
engine::Expected<SparseBakeResult> bakeCellsSparse(const SdfSource& source, const GridSpec& grid,
                                                   const SparseBakeOptions& options = {});

}  // namespace hsdf
