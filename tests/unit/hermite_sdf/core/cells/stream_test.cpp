// Sparse cell stream (fp32 and fp16 records) and the binary16 conversion.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "hermite_sdf/core/analytic.h"
#include "hermite_sdf/core/cells.h"

namespace hsdf {
namespace {

// Tricky: every one of the 65536 encodings (zeros, subnormals, the largest finite, infinities,
// NaNs) must survive half -> float -> half unchanged (NaNs: stay NaN with the same sign).
TEST(Half, EveryHalfRoundTripsThroughFloat) {
  for (std::uint32_t bits = 0; bits < 65536; ++bits) {
    const auto half = std::uint16_t(bits);
    const float f = halfToFloat(half);
    const bool isNaN = (half & 0x7c00u) == 0x7c00u && (half & 0x3ffu) != 0;
    if (isNaN) {
      ASSERT_TRUE(std::isnan(f)) << bits;
      const std::uint16_t back = floatToHalf(f);
      ASSERT_EQ(back & 0x8000u, half & 0x8000u);
      ASSERT_EQ(back & 0x7c00u, 0x7c00u);
      ASSERT_NE(back & 0x3ffu, 0u);
    } else {
      ASSERT_EQ(floatToHalf(f), half) << "bits 0x" << std::hex << bits;
    }
  }
}

// Tricky: hand-picked ties and boundaries where a truncating or round-half-up converter differs
// from round-to-nearest-even: exact ties go to the even neighbour, including into the subnormals,
// the largest finite value, the overflow threshold and the underflow threshold.
TEST(Half, RoundsToNearestEven) {
  EXPECT_EQ(floatToHalf(1.0f), 0x3c00);
  EXPECT_EQ(floatToHalf(1.0f + 0x1p-11f), 0x3c00);           // tie -> even (1.0)
  EXPECT_EQ(floatToHalf(1.0f + 3 * 0x1p-11f), 0x3c02);       // tie -> even (1 + 2^-9)
  EXPECT_EQ(floatToHalf(1.0f + 0x1p-11f + 0x1p-20f), 0x3c01);  // just above the tie
  EXPECT_EQ(floatToHalf(-2.0f), 0xc000);
  EXPECT_EQ(floatToHalf(65504.0f), 0x7bff);                  // largest finite half
  EXPECT_EQ(floatToHalf(65519.99f), 0x7bff);
  EXPECT_EQ(floatToHalf(65520.0f), 0x7c00);                  // tie with 2^16 -> even -> inf
  EXPECT_EQ(floatToHalf(1e10f), 0x7c00);
  EXPECT_EQ(floatToHalf(-std::numeric_limits<float>::infinity()), 0xfc00);
  EXPECT_EQ(floatToHalf(0x1p-24f), 0x0001);                  // smallest subnormal
  EXPECT_EQ(floatToHalf(0x1p-25f), 0x0000);                  // tie with 0 -> even -> 0
  EXPECT_EQ(floatToHalf(0x1.000002p-25f), 0x0001);           // just above the tie
  EXPECT_EQ(floatToHalf(3 * 0x1p-25f), 0x0002);              // tie between 1 and 2 -> 2
  EXPECT_EQ(floatToHalf(0x1p-14f), 0x0400);                  // smallest normal
  EXPECT_EQ(floatToHalf(0x1p-14f - 0x1p-25f), 0x0400);       // rounds up into the normals
  EXPECT_EQ(floatToHalf(-0.0f), 0x8000);
  EXPECT_TRUE(std::isnan(halfToFloat(floatToHalf(std::numeric_limits<float>::quiet_NaN()))));
  EXPECT_EQ(halfToFloat(0x0001), 0x1p-24f);
  EXPECT_EQ(halfToFloat(0x7bff), 65504.0f);
}

#if defined(__FLT16_MAX__)
// Tricky: an independent oracle (the compiler's own _Float16 conversion, IEEE RNE) over a million
// random bit patterns spanning every float exponent, not just the hand-picked cases.
TEST(Half, MatchesTheCompilersFloat16Conversion) {
  std::mt19937 rng(61);
  for (int i = 0; i < 1000000; ++i) {
    const float f = std::bit_cast<float>(std::uint32_t(rng()));
    if (std::isnan(f)) continue;
    const _Float16 reference = static_cast<_Float16>(f);
    ASSERT_EQ(floatToHalf(f), std::bit_cast<std::uint16_t>(reference)) << f;
  }
}
#endif

HermiteField bakeShape(const char* name, int k) {
  auto source = makeAnalyticSource(name);
  EXPECT_TRUE(source.ok());
  auto grid = fitGrid((*source)->bounds(), k, 1);
  EXPECT_TRUE(grid.ok());
  auto field = bakeHermiteField(**source, *grid, {});
  EXPECT_TRUE(field.ok());
  return std::move(*field);
}

// Tricky: records must come out in cell order with the right coordinate, class and the 8 corner
// samples in x + 2y + 4z order; counts: 32 scalars per kept cell, 136 / 72 bytes per record.
TEST(CellStream, HoldsEveryKeptCellWithItsCorners) {
  const HermiteField field = bakeShape("torus", 20);
  auto cells = classifyCells(field, {});
  ASSERT_TRUE(cells.ok());
  auto stream = extractCells(field, *cells);
  ASSERT_TRUE(stream.ok()) << stream.error().message;
  ASSERT_EQ(stream->records.size(), cells->stats.kept());
  ASSERT_GT(stream->records.size(), 100u);
  EXPECT_EQ(stream->stored_scalars(), 32u * cells->stats.kept());
  EXPECT_EQ(stream->stored_bytes(), 136u * cells->stats.kept());
  std::size_t previous = 0;
  for (const CellRecord& r : stream->records) {
    const std::size_t index = cells->cellIndex(r.x, r.y, r.z);
    EXPECT_TRUE(previous == 0 || index > previous);
    previous = index;
    EXPECT_EQ(CellClass(r.cellClass), cells->at(r.x, r.y, r.z));
    EXPECT_NE(CellClass(r.cellClass), CellClass::Empty);
    for (int c = 0; c < 8; ++c)
      EXPECT_EQ(std::memcmp(&r.corners[c], &field.at(r.x + (c & 1), r.y + ((c >> 1) & 1), r.z + ((c >> 2) & 1)),
                            sizeof(HermiteSample)),
                0);
  }
  const CellStreamHalf half = toHalf(*stream);
  EXPECT_EQ(half.stored_scalars(), stream->stored_scalars());
  EXPECT_EQ(half.stored_bytes(), 72u * cells->stats.kept());
}

// Tricky: the fp16 stream keeps coordinates and classes exactly and every scalar to within half
// an fp16 ulp (relative 2^-11 for normals), and fp16 -> fp32 -> fp16 is lossless.
TEST(CellStream, HalfRoundTripIsWithinHalfPrecision) {
  const HermiteField field = bakeShape("blob", 24);
  auto cells = classifyCells(field, {});
  ASSERT_TRUE(cells.ok());
  auto stream = extractCells(field, *cells);
  ASSERT_TRUE(stream.ok());
  const CellStreamHalf half = toHalf(*stream);
  const CellStream back = toFloat(half);
  ASSERT_EQ(back.records.size(), stream->records.size());
  for (std::size_t i = 0; i < back.records.size(); ++i) {
    const CellRecord &a = stream->records[i], &b = back.records[i];
    ASSERT_EQ(a.x, b.x);
    ASSERT_EQ(a.y, b.y);
    ASSERT_EQ(a.z, b.z);
    ASSERT_EQ(a.cellClass, b.cellClass);
    for (int c = 0; c < 8; ++c) {
      const float in[4] = {a.corners[c].f, a.corners[c].fx, a.corners[c].fy, a.corners[c].fz};
      const float out[4] = {b.corners[c].f, b.corners[c].fx, b.corners[c].fy, b.corners[c].fz};
      for (int s = 0; s < 4; ++s) ASSERT_LE(std::abs(in[s] - out[s]), std::abs(in[s]) * 0x1p-11f + 0x1p-25f);
    }
  }
  const CellStreamHalf again = toHalf(back);
  ASSERT_EQ(std::memcmp(again.records.data(), half.records.data(), half.stored_bytes()), 0);
}

// Tricky: a classification of another grid (same cell count, other spacing) must be refused.
TEST(CellStream, RefusesAClassificationOfAnotherGrid) {
  HermiteField field = bakeShape("sphere", 10);
  auto cells = classifyCells(field, {});
  ASSERT_TRUE(cells.ok());
  field.grid.spacing *= 2.0;
  auto stream = extractCells(field, *cells);
  ASSERT_FALSE(stream.ok());
  EXPECT_NE(stream.error().message.find("different grid"), std::string::npos);
}

}  // namespace
}  // namespace hsdf
