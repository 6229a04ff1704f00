// The cell feature's draw order and cell lookup (modules/hermite_sdf/src/core/cells/cell_rows.h), on
// the CPU. The reference is a scan of every record: what the lookup must find, whatever the order
// of the stream.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "hermite_sdf/core/bake_job.h"
#include "cells/cell_rows.h"

namespace hsdf {
namespace {

CellStream bakedSphere() {
  BakeSettings settings;
  settings.resolution = 16;
  auto asset = bakeAsset(BakeSource::fromShape("sphere"), settings);
  EXPECT_TRUE(asset.ok()) << asset.error().message;
  return asset.ok() ? (*asset)->cells : CellStream{};
}

// The records whose unit cell box comes within `radius` of `point`, by scanning them all.
std::vector<std::uint32_t> scanNear(const CellStream& stream, const glm::dvec3& point, double radius) {
  std::vector<std::uint32_t> near;
  for (std::uint32_t i = 0; i < stream.records.size(); ++i) {
    const CellRecord& r = stream.records[i];
    const glm::dvec3 c(r.x, r.y, r.z);
    const glm::dvec3 d = glm::max(glm::max(c - point, point - (c + 1.0)), glm::dvec3(0.0));
    if (glm::dot(d, d) <= radius * radius) near.push_back(i);
  }
  return near;
}

void expectLookupsMatchTheScan(const CellStream& stream) {
  const CellRows rows = buildCellRows(stream);
  for (std::uint32_t i = 0; i < stream.records.size(); ++i) {
    const CellRecord& r = stream.records[i];
    ASSERT_EQ(rows.recordOf(r.x, r.y, r.z), i);
  }
  EXPECT_EQ(rows.recordOf(0, 0, 0), std::nullopt) << "a corner cell of the padding holds no surface";
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-2.0, 17.0), radius(0.0, 3.0);
  for (int trial = 0; trial < 200; ++trial) {
    const glm::dvec3 point(coordinate(random), coordinate(random), coordinate(random));
    const double r = radius(random);
    std::vector<std::uint32_t> found = cellsNearPoint(rows, stream, point, r);
    std::sort(found.begin(), found.end());
    ASSERT_EQ(found, scanNear(stream, point, r)) << "near (" << point.x << ", " << point.y << ", " << point.z
                                                 << ") within " << r;
  }
}

// Bakes store the records in cell order (x fastest), so the lookup's table needs no sort; every
// kept cell must be found at its own record, and the cells near a point (the eye's neighbourhood,
// drawn from its near plane) must be exactly the scan's.
TEST(CellRows, LookupsInABakedStreamMatchAScan) {
  const CellStream stream = bakedSphere();
  ASSERT_GT(stream.records.size(), 100u);
  expectLookupsMatchTheScan(stream);
}

// Tricky: an asset made by hand may hold its records in any order. A binary search that trusted
// the bakes' cell order would miss cells (the eye's neighbourhood drawn with holes); the table is
// sorted instead, and each cell still maps to its own record index in the shuffled stream.
TEST(CellRows, LookupsInAShuffledStreamMatchAScan) {
  CellStream stream = bakedSphere();
  ASSERT_GT(stream.records.size(), 100u);
  std::shuffle(stream.records.begin(), stream.records.end(), std::mt19937(11));
  expectLookupsMatchTheScan(stream);
}

}  // namespace
}  // namespace hsdf
