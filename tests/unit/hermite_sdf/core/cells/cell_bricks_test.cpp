// Cell bricks (RenderMethod::CellBricks, render/cell_bricks.h): every kept cell in exactly one
// brick, each brick's cells listed in mask-bit order, the kept cells' bounds the shaders decode,
// and fewer bricks than cells on a surface.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <tuple>

#include "cells/cell_bricks.h"

namespace hsdf {
namespace {

// A stream of the given cells in storage order (x fastest, then y, then z); only the coordinates
// matter to the bricks.
CellStream streamOf(std::set<std::tuple<int, int, int>> zyx) {
  CellStream stream;
  for (const auto& [z, y, x] : zyx) {
    CellRecord r;
    r.x = std::uint16_t(x);
    r.y = std::uint16_t(y);
    r.z = std::uint16_t(z);
    stream.records.push_back(r);
  }
  return stream;
}

// The cells within half a cell diagonal of a sphere of radius k/3 around the grid's centre: a
// surface's kept cells at K = k.
CellStream sphereShell(int k) {
  std::set<std::tuple<int, int, int>> cells;
  const double c = k / 2.0, radius = k / 3.0;
  for (int z = 0; z < k; ++z)
    for (int y = 0; y < k; ++y)
      for (int x = 0; x < k; ++x) {
        const double d = std::sqrt((x + 0.5 - c) * (x + 0.5 - c) + (y + 0.5 - c) * (y + 0.5 - c) + (z + 0.5 - c) * (z + 0.5 - c));
        if (std::abs(d - radius) < 0.87) cells.insert({z, y, x});
      }
  return streamOf(cells);
}

std::uint64_t maskOf(const shader::CellBrickGpu& b) { return std::uint64_t(b.maskLo) | (std::uint64_t(b.maskHi) << 32); }

// The property the fragment shader relies on (bricks_depth.glsl brickCellRecord): kept cell bit b
// of a brick has record cellRecords[firstIndex + popcount(mask below b)], and that record is the
// cell at the brick's coordinate * 4 + (b & 3, (b >> 2) & 3, b >> 4). Every record appears once.
void expectEveryCellInOneBrick(const CellStream& stream, const CellBricks& bricks) {
  std::multiset<std::uint32_t> seen;
  std::uint32_t expectedFirst = 0;
  for (const shader::CellBrickGpu& brick : bricks.bricks) {
    const std::uint64_t mask = maskOf(brick);
    ASSERT_NE(mask, 0u) << "a brick without a kept cell";
    EXPECT_EQ(brick.firstIndex, expectedFirst) << "bricks' lists follow each other";
    expectedFirst += std::uint32_t(std::popcount(mask));
    const glm::uvec3 origin = brickCoordinate(brick) * CELL_BRICK_SIZE;
    for (std::uint32_t bit = 0; bit < 64; ++bit) {
      if (!((mask >> bit) & 1u)) continue;
      const std::uint64_t below = bit == 0 ? 0 : mask & ((std::uint64_t(1) << bit) - 1);
      const std::uint32_t record = bricks.cellRecords.at(brick.firstIndex + std::popcount(below));
      const CellRecord& r = stream.records.at(record);
      EXPECT_EQ(glm::uvec3(r.x, r.y, r.z), origin + glm::uvec3(bit & 3u, (bit >> 2) & 3u, bit >> 4)) << "bit " << bit;
      seen.insert(record);
    }
  }
  EXPECT_EQ(bricks.cellRecords.size(), stream.records.size());
  EXPECT_EQ(seen.size(), stream.records.size());
  for (std::uint32_t i = 0; i < stream.records.size(); ++i) EXPECT_EQ(seen.count(i), 1u) << "record " << i;
}

TEST(CellBricks, EveryKeptCellIsInExactlyOneBrickInMaskBitOrder) {
  std::mt19937 rng(7);
  std::set<std::tuple<int, int, int>> cells;
  for (int i = 0; i < 3000; ++i) cells.insert({int(rng() % 37), int(rng() % 29), int(rng() % 41)});
  const CellStream stream = streamOf(cells);
  auto bricks = buildCellBricks(stream);
  ASSERT_TRUE(bricks) << bricks.error().message;
  expectEveryCellInOneBrick(stream, *bricks);
  std::set<std::uint32_t> coordinates;
  for (const auto& b : bricks->bricks) EXPECT_TRUE(coordinates.insert(b.xyz).second) << "two bricks at one place";
}

TEST(CellBricks, AFullBlockIsEightFullBricks) {
  std::set<std::tuple<int, int, int>> cells;
  for (int z = 4; z < 12; ++z)
    for (int y = 0; y < 8; ++y)
      for (int x = 8; x < 16; ++x) cells.insert({z, y, x});
  auto bricks = buildCellBricks(streamOf(cells));
  ASSERT_TRUE(bricks);
  ASSERT_EQ(bricks->bricks.size(), 8u);
  for (const auto& b : bricks->bricks) {
    EXPECT_EQ(maskOf(b), ~std::uint64_t(0));
    glm::uvec3 lo, hi;
    brickCellBounds(b, lo, hi);
    EXPECT_EQ(lo, glm::uvec3(0));
    EXPECT_EQ(hi, glm::uvec3(3));
  }
  EXPECT_EQ(brickCoordinate(bricks->bricks.front()), glm::uvec3(2, 0, 1));
  EXPECT_EQ(brickCoordinate(bricks->bricks.back()), glm::uvec3(3, 1, 2));
}

// The proxy covers the kept cells only: the bounds are those of the set bits, per axis.
TEST(CellBricks, BoundsAreThoseOfTheKeptCells) {
  auto bricks = buildCellBricks(streamOf({{1, 3, 2}, {2, 1, 3}, {3, 2, 1}}));  // (z, y, x), one brick
  ASSERT_TRUE(bricks);
  ASSERT_EQ(bricks->bricks.size(), 1u);
  glm::uvec3 lo, hi;
  brickCellBounds(bricks->bricks[0], lo, hi);
  EXPECT_EQ(lo, glm::uvec3(1, 1, 1));
  EXPECT_EQ(hi, glm::uvec3(3, 3, 3));
  auto single = buildCellBricks(streamOf({{6, 5, 7}}));
  ASSERT_TRUE(single);
  brickCellBounds(single->bricks[0], lo, hi);
  EXPECT_EQ(lo, glm::uvec3(3, 1, 2));
  EXPECT_EQ(hi, glm::uvec3(3, 1, 2));
  EXPECT_EQ(brickCoordinate(single->bricks[0]), glm::uvec3(1, 1, 1));
}

// On a surface the proxies are far fewer than the kept cells: a brick holds many cells of the
// shell (one box per cell would be a ratio of 1; a brick can hold at most 64).
TEST(CellBricks, FewerBricksThanCellsOnASurface) {
  for (int k : {16, 32, 64, 128}) {
    const CellStream stream = sphereShell(k);
    auto bricks = buildCellBricks(stream);
    ASSERT_TRUE(bricks);
    expectEveryCellInOneBrick(stream, *bricks);
    const double ratio = double(stream.records.size()) / double(bricks->bricks.size());
    EXPECT_GT(ratio, 8.0) << "K = " << k << ": " << stream.records.size() << " cells, " << bricks->bricks.size() << " bricks";
  }
}

TEST(CellBricks, BricksNearAPoint) {
  auto bricks = buildCellBricks(streamOf({{0, 0, 0}, {0, 0, 9}}));  // bricks (0,0,0) and (2,0,0)
  ASSERT_TRUE(bricks);
  ASSERT_EQ(bricks->bricks.size(), 2u);
  // The first brick's kept cell spans x in [0, 1], the second's [9, 10] (not the whole brick).
  EXPECT_EQ(bricksNearPoint(bricks->bricks, glm::dvec3(1.5, 0.5, 0.5), 0.6), std::vector<std::uint32_t>{0});
  EXPECT_EQ(bricksNearPoint(bricks->bricks, glm::dvec3(8.5, 0.5, 0.5), 0.6), std::vector<std::uint32_t>{1});
  EXPECT_TRUE(bricksNearPoint(bricks->bricks, glm::dvec3(5.0, 0.5, 0.5), 2.0).empty());
  EXPECT_TRUE(bricksNearPoint(bricks->bricks, glm::dvec3(0.5), std::nan("")).empty());
}

// Bad input: a grid past the 1024 bricks per axis the coordinate holds gets a clear error.
TEST(CellBricks, CoordinatesBeyondTenBitsAreAnError) {
  auto bricks = buildCellBricks(streamOf({{0, 0, 4096}}));
  ASSERT_FALSE(bricks);
  EXPECT_NE(bricks.error().message.find("1024 bricks"), std::string::npos) << bricks.error().message;
  EXPECT_TRUE(buildCellBricks(streamOf({{0, 4095, 0}})));
}

}  // namespace
}  // namespace hsdf
