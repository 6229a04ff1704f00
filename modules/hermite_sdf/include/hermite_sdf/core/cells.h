#pragma once
// Cell classification (guaranteed empty-cell culling) and the sparse cell stream.
//
// Classes (DESIGN.md):
//   Crossing  - two corners have values of different sign, or a corner value is exactly zero: the
//               surface certainly meets the cell (the fast path: 8 comparisons).
//   Ambiguous - all corners strictly one sign, but the 64 Bernstein coefficients are not all of that
//               sign (or some is "zero", below): the cell may hold surface and is kept.
//   Empty     - all 64 coefficients strictly of one sign: by the convex hull property F has that sign
//               everywhere in the cell, so the cell is dropped.
// Conservative at zero: coefficients are computed in double from the stored floats; a coefficient
// counts as nonzero only if |b| > kZeroTolerance * scale, scale = max over corners of
// |f| + (h/3)(|fx|+|fy|+|fz|), which is far above the rounding error of the coefficient formula
// (a few ulp of scale). A zero or near-zero coefficient therefore never lets a cell be dropped.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/expected.h"
#include "engine/core/progress.h"
#include "hermite_sdf/core/field.h"
#include "hermite_sdf/core/hermite.h"
#include "hermite_sdf/core/materials.h"

namespace hsdf {

enum class CellClass : std::uint8_t { Empty = 0, Crossing = 1, Ambiguous = 2 };

inline constexpr double kZeroTolerance = 1e-12;

// Fast path: true if two corners have values of opposite sign or a corner value is zero.
bool cornersCrossSurface(const HermiteCellCorners<double>& corners);

// Full Bernstein test: true if the 64 coefficients are not all strictly one-signed. With
// refineDepth > 0 a cell that fails is split by de Casteljau at the midpoints (8 children) and
// each child re-tested, recursively to that depth; it is proven empty only if every leaf is.
bool bernsteinMayContainSurface(const BernsteinCell<double>& coeffs, double zeroTolerance, int refineDepth = 0);

// Tolerance for bernsteinMayContainSurface derived from the cell data (see file comment).
double zeroToleranceFor(const HermiteCellCorners<double>& corners, double h);

// Class of one cell: fast path first, then the Bernstein test (with optional refinement).
CellClass classifyCell(const HermiteCellCorners<double>& corners, double h, int refineDepth = 0);

// The 8 stored samples of a cell (corner index x + 2y + 4z), wherever they are kept: a dense
// field or a sparse bake's local samples.
using StoredCellCorners = std::array<const HermiteSample*, 8>;
struct StoredCellDecision {
  CellClass cellClass = CellClass::Empty;
  bool refinedEmpty = false;  // Empty only thanks to refinement (CellStats::refinedEmpty)
};
// The class classifyCells gives a cell with these corners (the one decision both the dense and the
// sparse bake use, so that they cannot disagree): fast paths from the floats, then classifyCell.
StoredCellDecision classifyStoredCell(const StoredCellCorners& corners, double h, int refineDepth);

struct ClassifyOptions {
  int refineDepth = 0;  // 0..2: de Casteljau refinement depth for ambiguous cells
  unsigned threads = 0; // 0: all hardware threads
  // makeSdfAsset refuses more kept cells than this after classifying, before it extracts their
  // records (fp32 + fp16: 192 B a cell, then as much again on the GPU).
  std::uint64_t maxKeptCells = std::uint64_t(-1);
  // Checked between slabs: the classification of a large grid takes long (the bunny at K = 256:
  // 0.7 s on 2 cores, growing with K^3), and a cancelled bake waited for it. Fails with "cancelled".
  const engine::CancelToken* cancel = nullptr;
};

struct CellStats {
  std::uint64_t cells = 0;         // (K-1)^3
  std::uint64_t crossing = 0;      // kept by the fast path
  std::uint64_t ambiguous = 0;     // kept by the Bernstein test (after refinement, if enabled)
  std::uint64_t empty = 0;         // dropped
  std::uint64_t refinedEmpty = 0;  // failed the plain Bernstein test but were proven empty by refinement
  std::uint64_t kept() const { return crossing + ambiguous; }
};

struct CellClassification {
  GridSpec grid;
  std::vector<CellClass> classes;  // one per cell, index cx + (K-1) (cy + (K-1) cz)
  CellStats stats;
  int refineDepth = 0;

  std::size_t cellIndex(int cx, int cy, int cz) const {
    const std::size_t n = std::size_t(grid.cellsPerAxis());
    return std::size_t(cx) + n * (std::size_t(cy) + n * std::size_t(cz));
  }
  CellClass at(int cx, int cy, int cz) const { return classes[cellIndex(cx, cy, cz)]; }
  bool kept(int cx, int cy, int cz) const { return at(cx, cy, cz) != CellClass::Empty; }
};

// Classifies every cell of a field. Errors: invalid grid, sample count not matching the grid,
// refineDepth outside 0..2.
engine::Expected<CellClassification> classifyCells(const HermiteField& field, const ClassifyOptions& options = {});

// ---- Sparse cell stream --------------------------------------------------------------------------
// One record per kept cell, in cell index order (x fastest). Records are tightly packed POD, uploaded
// as instance-rate vertex attributes: corners as 8 x vec4 (R32G32B32A32_SFLOAT / R16G16B16A16_SFLOAT),
// then the cell coordinate + class as R16G16B16A16_UINT. Corner order x + 2y + 4z; each corner is
// (f, fx, fy, fz) with the gradient in world units, exactly as in the field.

struct CellRecord {
  std::array<HermiteSample, 8> corners;
  std::uint16_t x = 0, y = 0, z = 0;
  std::uint16_t cellClass = 0;  // CellClass (Crossing / Ambiguous), for debug views
};
static_assert(sizeof(CellRecord) == 8 * 16 + 8, "CellRecord must stay tightly packed (136 bytes)");
// The record's corners in double precision, as the CPU's interpolant and Bernstein code take them.
HermiteCellCorners<double> cellCorners(const CellRecord& record);

struct CellRecordHalf {
  std::array<std::uint16_t, 32> corners{};  // IEEE binary16, corner-major: f, fx, fy, fz
  std::uint16_t x = 0, y = 0, z = 0;
  std::uint16_t cellClass = 0;
};
static_assert(sizeof(CellRecordHalf) == 8 * 8 + 8, "CellRecordHalf must stay tightly packed (72 bytes)");

template <class Record>
struct CellStreamOf {
  GridSpec grid;
  std::vector<Record> records;
  // A multi-material asset's material slots of each record's 8 corners (materials.h), one entry
  // per record, beside the records (the GPU records keep their layout); empty for one material.
  std::vector<CellMaterialSlots> materials;

  // As the paper counts them: 32 scalars (8 corners x 4) per kept cell. The cell coordinate is
  // NOT counted (it is implied by the position in a dense grid; the paper's table omits it).
  std::uint64_t stored_scalars() const { return std::uint64_t(records.size()) * 32u; }
  // Actual bytes of the records, coordinates included.
  std::uint64_t stored_bytes() const { return std::uint64_t(records.size()) * sizeof(Record); }
};
using CellStream = CellStreamOf<CellRecord>;
using CellStreamHalf = CellStreamOf<CellRecordHalf>;

// RenderMethod::CellRuns: the most cells one run's box covers unless the renderer is set otherwise
// (HermiteCellFeature::Settings::maxRunLength). Every asset carries its runs of this length, made
// with it (SdfAsset::derived), so the frame that first draws it builds none.
inline constexpr std::uint32_t kDefaultMaxRunLength = 8;

// Records of all kept cells. Errors: classification grid differs from the field's.
engine::Expected<CellStream> extractCells(const HermiteField& field, const CellClassification& classification);
CellStreamHalf toHalf(const CellStream& stream);
// Whether fp16 records / textures hold a field on `grid` faithfully: a spacing of at least 2^-13
// (finer grids put the values near the surface among fp16's subnormals) and a grid diagonal below
// fp16's largest finite value (a distance across the grid must not overflow to infinity).
inline constexpr double kMinFp16Spacing = 1.0 / 8192.0;
bool halfPrecisionFits(const GridSpec& grid);
CellStream toFloat(const CellStreamHalf& stream);
CellRecord toFloat(const CellRecordHalf& record);

// IEEE 754 binary16 conversion, round to nearest even; overflow gives +-inf, NaN stays NaN
// (quiet, sign and top payload bits kept), subnormals are produced and read exactly.
std::uint16_t floatToHalf(float value);
float halfToFloat(std::uint16_t bits);

// ---- Proxy boxes ---------------------------------------------------------------------------------
// The part of a kept cell that can hold its zero set: the renderers draw and search it instead of
// the whole cell (box overdraw: on the bunny its boxes have ~0.57x the cells' surface
// area, so ~0.57x as many rays meet them). Per axis, F lies between the Bernstein polynomials of
// the least and of the greatest coefficient of each slice across that axis (the other axes' basis
// functions are positive and sum to 1), so F can vanish only where the convex hulls of those two
// control polygons reach zero (one step of Bezier clipping). Coefficients within the classifier's
// zero band (zeroToleranceFor) count as zero, so a root the classifier keeps a cell for (a face on a
// sample plane) is never clipped away. The box is rounded outward to kProxySteps-ths of the cell:
// three (lo, hi) pairs of 0..6, 21 pairs per axis, pack into 14 bits (packProxyBox), which the GPU
// records carry beside the cell class (hermite_host_device.h, CELL_PROXY_*).
inline constexpr int kProxySteps = 6;
struct CellProxyBox {
  std::array<std::uint8_t, 3> lo{0, 0, 0};  // in kProxySteps-ths of the cell, lo < hi
  std::array<std::uint8_t, 3> hi{kProxySteps, kProxySteps, kProxySteps};
  bool operator==(const CellProxyBox&) const = default;
};
CellProxyBox cellProxyBox(const HermiteCellCorners<double>& corners, double h);
// 0 is the whole cell; every code is below 21^3.
std::uint16_t packProxyBox(const CellProxyBox& box);
CellProxyBox unpackProxyBox(std::uint16_t code);
// packProxyBox(cellProxyBox(...)) of every record, from the values the record stores (fp16 records
// have their own: their interpolant is not the fp32 one).
std::vector<std::uint16_t> proxyBoxCodes(const CellStream& cells);
std::vector<std::uint16_t> proxyBoxCodes(const CellStreamHalf& cells);

// ---- Statistics ----------------------------------------------------------------------------------

// Kept cells that dense sampling of the interpolant finds empty (no sample of different sign from
// the others, no zero): the false positives of the classification.
struct FalsePositiveReport {
  std::uint64_t keptCells = 0;
  std::uint64_t ambiguousCells = 0;
  std::uint64_t falsePositives = 0;  // among the kept cells
  double rate() const { return keptCells == 0 ? 0.0 : double(falsePositives) / double(keptCells); }
};

// Samples F at samplesPerAxis^3 points (corners included) of every kept cell.
FalsePositiveReport countFalsePositives(const HermiteField& field, const CellClassification& classification,
                                        int samplesPerAxis = 17);

// The same count from the kept cells' records alone (a sparse bake has no dense field).
FalsePositiveReport countFalsePositives(const CellStream& cells, int samplesPerAxis = 17);

// F at the samplesPerAxis^3 points u = (i,j,k)/(samplesPerAxis-1), index i + m (j + m k), evaluated
// separably from the Hermite form (independently of the Bernstein conversion).
std::vector<double> sampleCellDensely(const HermiteCellCorners<double>& corners, double h, int samplesPerAxis);

// True if F sampled at samplesPerAxis^3 points of the cell shows a sign change or a zero.
bool denseSamplingFindsSurface(const HermiteCellCorners<double>& corners, double h, int samplesPerAxis);

// One line per class: counts and percentages, for tools and logs.
std::string formatCellStats(const CellStats& stats);

}  // namespace hsdf
