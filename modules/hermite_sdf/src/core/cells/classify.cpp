#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "hermite_sdf/core/cells.h"

namespace hsdf {
namespace {

// Sign of a coefficient with the zero band: +1, -1, or 0 for |b| <= tolerance.
int toleranceSign(double b, double tolerance) { return b > tolerance ? 1 : (b < -tolerance ? -1 : 0); }

// +1 / -1 if all coefficients are strictly of that sign beyond the tolerance, 0 otherwise.
int uniformSign(const BernsteinCell<double>& coeffs, double tolerance) {
  const int first = toleranceSign(coeffs[0], tolerance);
  if (first == 0) return 0;
  for (double b : coeffs)
    if (toleranceSign(b, tolerance) != first) return 0;
  return first;
}

// Cheap sufficient condition for Empty, checked before building the 64 coefficients: every
// coefficient b satisfies |b - f_corner| <= (h/3)|grad|_1 of its corner, so if all corners have
// one strict sign with |f| - (h/3)|grad|_1 > tolerance, all 64 coefficients share that sign.
bool obviouslyEmpty(const HermiteCellCorners<double>& corners, double h, double tolerance) {
  const double third = h / 3.0;
  const bool positive = corners[0].f > 0.0;
  for (const HermiteCorner<double>& c : corners) {
    const double margin = (positive ? c.f : -c.f) - third * (std::abs(c.fx) + std::abs(c.fy) + std::abs(c.fz));
    if (margin <= tolerance) return false;
  }
  return true;
}

}  // namespace

bool cornersCrossSurface(const HermiteCellCorners<double>& corners) {
  bool anyNegative = false, anyPositive = false;
  for (const HermiteCorner<double>& c : corners) {
    if (c.f == 0.0) return true;
    anyNegative |= c.f < 0.0;
    anyPositive |= c.f > 0.0;
  }
  return anyNegative && anyPositive;
}

double zeroToleranceFor(const HermiteCellCorners<double>& corners, double h) {
  double scale = 0.0;
  for (const HermiteCorner<double>& c : corners)
    scale = std::max(scale, std::abs(c.f) + h / 3.0 * (std::abs(c.fx) + std::abs(c.fy) + std::abs(c.fz)));
  return kZeroTolerance * scale;
}

bool bernsteinMayContainSurface(const BernsteinCell<double>& coeffs, double zeroTolerance, int refineDepth) {
  if (uniformSign(coeffs, zeroTolerance) != 0) return false;
  if (refineDepth <= 0) return true;
  for (const BernsteinCell<double>& child : subdivideBernsteinCell(coeffs))
    if (bernsteinMayContainSurface(child, zeroTolerance, refineDepth - 1)) return true;
  return false;
}

CellClass classifyCell(const HermiteCellCorners<double>& corners, double h, int refineDepth) {
  if (cornersCrossSurface(corners)) return CellClass::Crossing;
  const double tolerance = zeroToleranceFor(corners, h);
  if (obviouslyEmpty(corners, h, tolerance)) return CellClass::Empty;
  return bernsteinMayContainSurface(toBernstein(corners, h), tolerance, refineDepth) ? CellClass::Ambiguous
                                                                                      : CellClass::Empty;
}

namespace {

struct SlabCounts {
  std::uint64_t crossing = 0, ambiguous = 0, empty = 0, refinedEmpty = 0;
};

// The common cases of classifyCell (corner crossing, obviously empty) straight from the stored
// samples, without building the corner array; nullopt where the Bernstein test must decide.
// Same decisions as classifyCell: same formulas, same tolerance.
std::optional<CellClass> quickClass(const StoredCellCorners& corners, double h) {
  const double third = h / 3.0;
  bool negative = false, positive = false;
  double scale = 0.0, minMargin = HUGE_VAL;
  for (int c = 0; c < 8; ++c) {
    const HermiteSample& s = *corners[c];
    if (s.f == 0.0f) return CellClass::Crossing;
    negative |= s.f < 0.0f;
    positive |= s.f > 0.0f;
    const double slope = third * (std::abs(double(s.fx)) + std::abs(double(s.fy)) + std::abs(double(s.fz)));
    const double f = std::abs(double(s.f));
    scale = std::max(scale, f + slope);
    minMargin = std::min(minMargin, f - slope);
  }
  if (negative && positive) return CellClass::Crossing;
  if (minMargin > kZeroTolerance * scale) return CellClass::Empty;
  return std::nullopt;
}

// Classifies the cells of z-slab cz into `classes`, returning its counts.
SlabCounts classifySlab(const HermiteField& field, int cz, int refineDepth, std::vector<CellClass>& classes,
                        const CellClassification& layout) {
  SlabCounts counts;
  const GridSpec& grid = field.grid;
  const int n = grid.cellsPerAxis();
  const std::size_t k = std::size_t(grid.resolution);
  const std::size_t offsets[8] = {0, 1, k, k + 1, k * k, k * k + 1, k * k + k, k * k + k + 1};
  for (int cy = 0; cy < n; ++cy)
    for (int cx = 0; cx < n; ++cx) {
      const HermiteSample* base = &field.samples[grid.sampleIndex(cx, cy, cz)];
      StoredCellCorners corners;
      for (int c = 0; c < 8; ++c) corners[std::size_t(c)] = base + offsets[c];
      const StoredCellDecision d = classifyStoredCell(corners, grid.spacing, refineDepth);
      classes[layout.cellIndex(cx, cy, cz)] = d.cellClass;
      counts.crossing += d.cellClass == CellClass::Crossing;
      counts.ambiguous += d.cellClass == CellClass::Ambiguous;
      counts.empty += d.cellClass == CellClass::Empty;
      counts.refinedEmpty += d.refinedEmpty;
    }
  return counts;
}

engine::Status checkField(const HermiteField& field) {
  ENGINE_TRY(validateGrid(field.grid));
  if (field.samples.size() != field.grid.sampleCount())
    return engine::makeError(fmt::format("field has {} samples but its grid of resolution {} needs {}",
                                         field.samples.size(), field.grid.resolution, field.grid.sampleCount()));
  return {};
}

}  // namespace

StoredCellDecision classifyStoredCell(const StoredCellCorners& corners, double h, int refineDepth) {
  if (const std::optional<CellClass> quick = quickClass(corners, h)) return {*quick, false};
  HermiteCellCorners<double> cell{};
  for (std::size_t c = 0; c < 8; ++c) cell[c] = {corners[c]->f, corners[c]->fx, corners[c]->fy, corners[c]->fz};
  StoredCellDecision d;
  d.cellClass = classifyCell(cell, h, refineDepth);
  d.refinedEmpty = d.cellClass == CellClass::Empty && refineDepth > 0 && classifyCell(cell, h, 0) == CellClass::Ambiguous;
  return d;
}

engine::Expected<CellClassification> classifyCells(const HermiteField& field, const ClassifyOptions& options) {
  ENGINE_TRY(checkField(field));
  if (options.refineDepth < 0 || options.refineDepth > 2)
    return engine::makeError(fmt::format("refinement depth {} is outside 0..2", options.refineDepth));
  CellClassification out;
  out.grid = field.grid;
  out.refineDepth = options.refineDepth;
  const int n = field.grid.cellsPerAxis();
  out.classes.assign(std::size_t(n) * std::size_t(n) * std::size_t(n), CellClass::Empty);

  const unsigned threads = std::min<unsigned>(
      options.threads != 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency()), unsigned(n));
  std::vector<SlabCounts> perThread(threads);
  std::atomic<int> nextSlab{0};
  const auto cancelled = [&options] { return options.cancel && options.cancel->isCancelled(); };
  auto worker = [&](unsigned t) {
    for (int cz = nextSlab.fetch_add(1); cz < n && !cancelled(); cz = nextSlab.fetch_add(1)) {
      const SlabCounts c = classifySlab(field, cz, options.refineDepth, out.classes, out);
      perThread[t].crossing += c.crossing;
      perThread[t].ambiguous += c.ambiguous;
      perThread[t].empty += c.empty;
      perThread[t].refinedEmpty += c.refinedEmpty;
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker, t);
  worker(0);
  for (std::thread& thread : pool) thread.join();
  if (cancelled()) return engine::makeError("cancelled");

  out.stats.cells = out.classes.size();
  for (const SlabCounts& c : perThread) {
    out.stats.crossing += c.crossing;
    out.stats.ambiguous += c.ambiguous;
    out.stats.empty += c.empty;
    out.stats.refinedEmpty += c.refinedEmpty;
  }
  return out;
}

std::vector<double> sampleCellDensely(const HermiteCellCorners<double>& corners, double h, int samplesPerAxis) {
  const int m = std::max(samplesPerAxis, 2);
  // Hermite form as a 4x4x4 tensor over the per-axis basis (H0, H1, h*G0, h*G1); twist entries are 0.
  double coeff[4][4][4] = {};
  for (int c = 0; c < 8; ++c) {
    const int x = c & 1, y = (c >> 1) & 1, z = (c >> 2) & 1;
    coeff[z][y][x] = corners[c].f;
    coeff[z][y][2 + x] = h * corners[c].fx;
    coeff[z][2 + y][x] = h * corners[c].fy;
    coeff[2 + z][y][x] = h * corners[c].fz;
  }
  const auto count = static_cast<std::size_t>(m);
  std::vector<std::array<double, 4>> basis(count);
  for (std::size_t i = 0; i < count; ++i) {
    const HermiteBasis1D<double> b = hermiteBasis(double(i) / double(m - 1));
    basis[i] = {b.h0, b.h1, b.g0, b.g1};
  }
  // Contract x, then y, then z: O(m^3 * 4) work instead of O(m^3 * 64) per cell.
  std::vector<std::array<std::array<double, 4>, 4>> alongX(count);  // [i][g][b]
  for (std::size_t i = 0; i < count; ++i)
    for (int g = 0; g < 4; ++g)
      for (int b = 0; b < 4; ++b) {
        double sum = 0.0;
        for (int a = 0; a < 4; ++a) sum += basis[i][a] * coeff[g][b][a];
        alongX[i][g][b] = sum;
      }
  std::vector<std::array<double, 4>> alongY(count * count);  // [j * m + i][g]
  for (std::size_t j = 0; j < count; ++j)
    for (std::size_t i = 0; i < count; ++i)
      for (int g = 0; g < 4; ++g) {
        double sum = 0.0;
        for (int b = 0; b < 4; ++b) sum += basis[j][b] * alongX[i][g][b];
        alongY[j * count + i][g] = sum;
      }
  std::vector<double> values(count * count * count);
  for (std::size_t k = 0; k < count; ++k)
    for (std::size_t ji = 0; ji < count * count; ++ji) {
      double sum = 0.0;
      for (int g = 0; g < 4; ++g) sum += basis[k][g] * alongY[ji][g];
      values[k * count * count + ji] = sum;
    }
  return values;
}

bool denseSamplingFindsSurface(const HermiteCellCorners<double>& corners, double h, int samplesPerAxis) {
  bool anyNegative = false, anyPositive = false;
  for (double f : sampleCellDensely(corners, h, samplesPerAxis)) {
    if (f == 0.0) return true;
    anyNegative |= f < 0.0;
    anyPositive |= f > 0.0;
  }
  return anyNegative && anyPositive;
}

FalsePositiveReport countFalsePositives(const HermiteField& field, const CellClassification& classification,
                                        int samplesPerAxis) {
  FalsePositiveReport report;
  const int n = classification.grid.cellsPerAxis();
  for (int cz = 0; cz < n; ++cz)
    for (int cy = 0; cy < n; ++cy)
      for (int cx = 0; cx < n; ++cx) {
        const CellClass c = classification.at(cx, cy, cz);
        if (c == CellClass::Empty) continue;
        ++report.keptCells;
        if (c != CellClass::Ambiguous) continue;  // crossing cells certainly hold surface
        ++report.ambiguousCells;
        if (!denseSamplingFindsSurface(field.cellCorners<double>(cx, cy, cz), field.grid.spacing, samplesPerAxis))
          ++report.falsePositives;
      }
  return report;
}

FalsePositiveReport countFalsePositives(const CellStream& cells, int samplesPerAxis) {
  FalsePositiveReport report;
  for (const CellRecord& r : cells.records) {
    ++report.keptCells;
    if (r.cellClass != std::uint16_t(CellClass::Ambiguous)) continue;  // crossing cells certainly hold surface
    ++report.ambiguousCells;
    if (!denseSamplingFindsSurface(cellCorners(r), cells.grid.spacing, samplesPerAxis)) ++report.falsePositives;
  }
  return report;
}

std::string formatCellStats(const CellStats& s) {
  auto percent = [&](std::uint64_t count) { return s.cells == 0 ? 0.0 : 100.0 * double(count) / double(s.cells); };
  return fmt::format(
      "cells {}: crossing {} ({:.2f}%), ambiguous {} ({:.2f}%), empty {} ({:.2f}%), kept {}, refined to empty {}",
      s.cells, s.crossing, percent(s.crossing), s.ambiguous, percent(s.ambiguous), s.empty, percent(s.empty),
      s.kept(), s.refinedEmpty);
}

}  // namespace hsdf
