#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "hermite_sdf/cells.h"

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

const char* cellClassName(CellClass c) {
  switch (c) {
    case CellClass::Empty: return "empty";
    case CellClass::Crossing: return "crossing";
    case CellClass::Ambiguous: return "ambiguous";
  }
  return "unknown";
}

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

// Classifies the cells of z-slab cz into `classes`, returning its counts.
SlabCounts classifySlab(const HermiteField& field, int cz, int refineDepth, std::vector<CellClass>& classes,
                        const CellClassification& layout) {
  SlabCounts counts;
  const int n = field.grid.cellsPerAxis();
  const double h = field.grid.spacing;
  for (int cy = 0; cy < n; ++cy)
    for (int cx = 0; cx < n; ++cx) {
      const HermiteCellCorners<double> corners = field.cellCorners<double>(cx, cy, cz);
      CellClass c = classifyCell(corners, h, refineDepth);
      if (c == CellClass::Empty && refineDepth > 0 && classifyCell(corners, h, 0) == CellClass::Ambiguous)
        ++counts.refinedEmpty;
      classes[layout.cellIndex(cx, cy, cz)] = c;
      counts.crossing += c == CellClass::Crossing;
      counts.ambiguous += c == CellClass::Ambiguous;
      counts.empty += c == CellClass::Empty;
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
  auto worker = [&](unsigned t) {
    for (int cz = nextSlab.fetch_add(1); cz < n; cz = nextSlab.fetch_add(1)) {
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

  out.stats.cells = out.classes.size();
  for (const SlabCounts& c : perThread) {
    out.stats.crossing += c.crossing;
    out.stats.ambiguous += c.ambiguous;
    out.stats.empty += c.empty;
    out.stats.refinedEmpty += c.refinedEmpty;
  }
  return out;
}

bool denseSamplingFindsSurface(const HermiteCellCorners<double>& corners, double h, int samplesPerAxis) {
  const int m = std::max(samplesPerAxis, 2);
  bool anyNegative = false, anyPositive = false;
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        const Vec3<double> u(double(i) / (m - 1), double(j) / (m - 1), double(k) / (m - 1));
        const double f = hermiteValue(corners, h, u);
        if (f == 0.0) return true;
        anyNegative |= f < 0.0;
        anyPositive |= f > 0.0;
        if (anyNegative && anyPositive) return true;
      }
  return false;
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

std::string formatCellStats(const CellStats& s) {
  auto percent = [&](std::uint64_t count) { return s.cells == 0 ? 0.0 : 100.0 * double(count) / double(s.cells); };
  return fmt::format(
      "cells {}: crossing {} ({:.2f}%), ambiguous {} ({:.2f}%), empty {} ({:.2f}%), kept {}, refined to empty {}",
      s.cells, s.crossing, percent(s.crossing), s.ambiguous, percent(s.ambiguous), s.empty, percent(s.empty),
      s.kept(), s.refinedEmpty);
}

}  // namespace hsdf
