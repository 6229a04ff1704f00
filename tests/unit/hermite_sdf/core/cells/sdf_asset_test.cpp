// makeSdfAsset / makeSdfAssetFromCells on fields nobody baked (a file, a user's generator): NaN or
// infinity anywhere is refused by name before anything reaches a renderer.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/render/renderable.h"

namespace hsdf {
namespace {

// A valid 4^3 field (the plane z = 1.5, unit gradient in z).
HermiteField planeField() {
  HermiteField field;
  field.grid.resolution = 4;
  field.grid.spacing = 1.0;
  field.samples.resize(field.grid.sampleCount());
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) field.samples[field.grid.sampleIndex(i, j, k)] = {float(k) - 1.5f, 0.0f, 0.0f, 1.0f};
  return field;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Tricky: the bad value sits in one component of one sample (a gradient, not f), in a cell the
// classification would keep; an infinity is as bad as a NaN; the message must name the asset and
// the sample by its (i, j, k), not by its flat index.
TEST(SdfAsset, NonFiniteSamplesAreRefusedByName) {
  ASSERT_TRUE(makeSdfAsset("plane", planeField(), planeField().grid.bounds()).ok());
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                       -std::numeric_limits<float>::infinity()};
  for (const float value : bad) {
    HermiteField field = planeField();
    field.samples[field.grid.sampleIndex(2, 1, 3)].fy = value;
    const auto asset = makeSdfAsset("user field", field, field.grid.bounds());
    ASSERT_FALSE(asset.ok()) << value;
    EXPECT_TRUE(contains(asset.error().message, "asset 'user field': sample (2, 1, 3) is not finite"))
        << asset.error().message;
  }
  HermiteField short_ = planeField();
  short_.samples.pop_back();
  const auto asset = makeSdfAsset("short", short_, short_.grid.bounds());
  ASSERT_FALSE(asset.ok());
  EXPECT_TRUE(contains(asset.error().message, "63 samples for a grid of 4^3")) << asset.error().message;
}

// Tricky: a cells-only asset has no field to check; its records carry the corner values that go to
// the GPU, so they are checked one by one (corner 7 of the last record here).
TEST(SdfAsset, NonFiniteCellRecordsAreRefusedByName) {
  const HermiteField field = planeField();
  auto classification = classifyCells(field);
  ASSERT_TRUE(classification.ok());
  auto cells = extractCells(field, *classification);
  ASSERT_TRUE(cells.ok());
  ASSERT_FALSE(cells->records.empty());
  ASSERT_TRUE(makeSdfAssetFromCells("cells", *cells).ok());
  CellRecord& last = cells->records.back();
  last.corners[7].f = std::numeric_limits<float>::quiet_NaN();
  const auto asset = makeSdfAssetFromCells("cells", *cells);
  ASSERT_FALSE(asset.ok());
  EXPECT_TRUE(contains(asset.error().message, "asset 'cells': cell (" + std::to_string(last.x) + ", " +
                                                  std::to_string(last.y) + ", " + std::to_string(last.z) +
                                                  ") corner 7 is not finite"))
      << asset.error().message;
}

}  // namespace
}  // namespace hsdf
