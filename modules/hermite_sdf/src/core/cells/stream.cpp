#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

#include "hermite_sdf/core/cells.h"

namespace hsdf {

std::uint16_t floatToHalf(float value) {
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(value);
  const auto sign = std::uint16_t((bits >> 16) & 0x8000u);
  const std::uint32_t magnitude = bits & 0x7fffffffu;
  if (magnitude >= 0x7f800000u) {  // inf or NaN
    if (magnitude == 0x7f800000u) return std::uint16_t(sign | 0x7c00u);
    return std::uint16_t(sign | 0x7e00u | ((magnitude >> 13) & 0x3ffu));  // quiet NaN, top payload bits
  }
  if (magnitude >= 0x477ff000u) return std::uint16_t(sign | 0x7c00u);  // >= 65520 rounds to inf
  if (magnitude <= 0x33000000u) return sign;                            // <= 2^-25 rounds (to even) to 0
  if (magnitude < 0x38800000u) {  // below 2^-14: a half subnormal, value / 2^-24 rounded to nearest even
    const std::uint32_t mantissa = (magnitude & 0x7fffffu) | 0x800000u;
    const int shift = 126 - int(magnitude >> 23);  // 14..24
    std::uint32_t q = mantissa >> shift;
    const std::uint32_t rest = mantissa & ((1u << shift) - 1u), halfway = 1u << (shift - 1);
    if (rest > halfway || (rest == halfway && (q & 1u))) ++q;
    return std::uint16_t(sign | q);  // q == 0x400 is correctly the smallest normal
  }
  // Normal: rebias the exponent (127 -> 15) and round the 13 dropped mantissa bits to nearest even;
  // a carry out of the mantissa correctly bumps the exponent.
  std::uint32_t q = (magnitude >> 13) - (112u << 10);
  const std::uint32_t rest = magnitude & 0x1fffu;
  if (rest > 0x1000u || (rest == 0x1000u && (q & 1u))) ++q;
  return std::uint16_t(sign | q);
}

float halfToFloat(std::uint16_t half) {
  const std::uint32_t sign = std::uint32_t(half & 0x8000u) << 16;
  const std::uint32_t exponent = (half >> 10) & 0x1fu;
  const std::uint32_t mantissa = half & 0x3ffu;
  if (exponent == 0) {  // zero or subnormal: mantissa * 2^-24, exact in float
    const float magnitude = float(mantissa) * 0x1p-24f;
    return sign != 0 ? -magnitude : magnitude;
  }
  if (exponent == 31) return std::bit_cast<float>(sign | 0x7f800000u | (mantissa << 13));
  return std::bit_cast<float>(sign | ((exponent + 112u) << 23) | (mantissa << 13));
}

namespace {

bool sameGrid(const GridSpec& a, const GridSpec& b) {
  return a.resolution == b.resolution && a.spacing == b.spacing && a.origin == b.origin;
}

}  // namespace

engine::Expected<CellStream> extractCells(const HermiteField& field, const CellClassification& classification) {
  if (!sameGrid(field.grid, classification.grid))
    return engine::makeError("the classification was made for a different grid than the field's");
  const int n = field.grid.cellsPerAxis();
  if (field.samples.size() != field.grid.sampleCount() ||
      classification.classes.size() != std::size_t(n) * std::size_t(n) * std::size_t(n))
    return engine::makeError(fmt::format("field ({} samples) or classification ({} cells) does not match resolution {}",
                                         field.samples.size(), classification.classes.size(), field.grid.resolution));
  if (!field.materials.empty() && field.materials.size() != field.samples.size())
    return engine::makeError(fmt::format("field has {} material slots for {} samples", field.materials.size(),
                                         field.samples.size()));
  CellStream stream;
  stream.grid = field.grid;
  stream.records.reserve(classification.stats.kept());
  if (!field.materials.empty()) stream.materials.reserve(classification.stats.kept());
  for (int cz = 0; cz < n; ++cz)
    for (int cy = 0; cy < n; ++cy)
      for (int cx = 0; cx < n; ++cx) {
        const CellClass c = classification.at(cx, cy, cz);
        if (c == CellClass::Empty) continue;
        CellRecord record;
        for (int k = 0; k < 8; ++k) record.corners[k] = field.at(cx + (k & 1), cy + ((k >> 1) & 1), cz + ((k >> 2) & 1));
        record.x = std::uint16_t(cx);
        record.y = std::uint16_t(cy);
        record.z = std::uint16_t(cz);
        record.cellClass = std::uint16_t(c);
        stream.records.push_back(record);
        if (field.materials.empty()) continue;
        CellMaterialSlots slots{};
        for (int k = 0; k < 8; ++k)
          slots[std::size_t(k)] =
              field.materials[field.grid.sampleIndex(cx + (k & 1), cy + ((k >> 1) & 1), cz + ((k >> 2) & 1))];
        stream.materials.push_back(slots);
      }
  return stream;
}

// fp16 keeps 11 significant bits, but below 2^-14 only a fixed step of 2^-24. The values that
// place the surface are those within a cell of it; they keep fp16's relative precision only when
// the spacing is at least 2^-13. Finer grids would round them to a few steps (a mesh 1e-5 across
// would draw, and store in .hsdf files, cells that are no longer those of its own dense field).
bool halfPrecisionFits(const GridSpec& grid) {
  constexpr double kLargestHalf = 65504.0;
  const double diagonal = grid.spacing * double(std::max(grid.resolution - 1, 0)) * std::sqrt(3.0);
  return grid.spacing >= kMinFp16Spacing && diagonal <= kLargestHalf;
}

CellStreamHalf toHalf(const CellStream& stream) {
  CellStreamHalf out;
  out.grid = stream.grid;
  out.records.reserve(stream.records.size());
  for (const CellRecord& r : stream.records) {
    CellRecordHalf h;
    for (int k = 0; k < 8; ++k) {
      const HermiteSample& s = r.corners[k];
      h.corners[4 * k + 0] = floatToHalf(s.f);
      h.corners[4 * k + 1] = floatToHalf(s.fx);
      h.corners[4 * k + 2] = floatToHalf(s.fy);
      h.corners[4 * k + 3] = floatToHalf(s.fz);
    }
    h.x = r.x;
    h.y = r.y;
    h.z = r.z;
    h.cellClass = r.cellClass;
    out.records.push_back(h);
  }
  out.materials = stream.materials;
  return out;
}

CellRecord toFloat(const CellRecordHalf& h) {
  CellRecord r;
  for (int k = 0; k < 8; ++k)
    r.corners[k] = {halfToFloat(h.corners[4 * k + 0]), halfToFloat(h.corners[4 * k + 1]),
                    halfToFloat(h.corners[4 * k + 2]), halfToFloat(h.corners[4 * k + 3])};
  r.x = h.x;
  r.y = h.y;
  r.z = h.z;
  r.cellClass = h.cellClass;
  return r;
}

CellStream toFloat(const CellStreamHalf& stream) {
  CellStream out;
  out.grid = stream.grid;
  out.records.reserve(stream.records.size());
  for (const CellRecordHalf& h : stream.records) out.records.push_back(toFloat(h));
  out.materials = stream.materials;
  return out;
}

HermiteCellCorners<double> cellCorners(const CellRecord& record) {
  HermiteCellCorners<double> corners;
  for (std::size_t c = 0; c < 8; ++c) {
    const HermiteSample& s = record.corners[c];
    corners[c] = {double(s.f), double(s.fx), double(s.fy), double(s.fz)};
  }
  return corners;
}

}  // namespace hsdf
