#include "cells/cell_bricks.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

namespace hsdf {
namespace {

constexpr std::uint32_t kBrick = CELL_BRICK_SIZE;
constexpr std::uint32_t kMaxBrickCoordinate = 1023;  // 10 bits per axis in CellBrickGpu::xyz

std::uint64_t maskOf(const shader::CellBrickGpu& brick) {
  return std::uint64_t(brick.maskLo) | (std::uint64_t(brick.maskHi) << 32);
}

// Which of the 4 slices along one axis hold a kept cell, as 4 bits, for the brick's mask.
std::uint32_t occupiedSlices(std::uint64_t mask, int axis) {
  std::uint32_t bits = 0;
  for (std::uint32_t bit = 0; bit < kBrick * kBrick * kBrick; ++bit)
    if ((mask >> bit) & 1u) bits |= 1u << ((bit >> (2 * axis)) & 3u);
  return bits;
}

}  // namespace

namespace {

// A kept cell's place: its brick's packed coordinate (z in the high bits), then its mask bit.
struct BrickedCell {
  std::uint64_t key = 0;  // xyz << 6 | bit: sorting by it orders by brick (z, y, x), then by bit
  std::uint32_t record = 0;
};

engine::Expected<std::vector<BrickedCell>> brickedCells(const CellStream& stream) {
  std::vector<BrickedCell> cells(stream.records.size());
  for (std::uint32_t i = 0; i < stream.records.size(); ++i) {
    const CellRecord& r = stream.records[i];
    const glm::uvec3 cell(r.x, r.y, r.z);
    const glm::uvec3 brick = cell / kBrick;
    if (glm::any(glm::greaterThan(brick, glm::uvec3(kMaxBrickCoordinate))))
      return engine::makeError("cell bricks: cell (" + std::to_string(cell.x) + ", " + std::to_string(cell.y) + ", " +
                               std::to_string(cell.z) + ") lies beyond the 1024 bricks per axis a brick coordinate holds");
    const glm::uvec3 inBrick = cell % kBrick;
    const std::uint32_t bit = inBrick.x + kBrick * inBrick.y + kBrick * kBrick * inBrick.z;
    cells[i] = {(std::uint64_t(brick.x | (brick.y << 10) | (brick.z << 20)) << 6) | bit, i};
  }
  return cells;
}

}  // namespace

// A sort of 16 bytes a cell, not a tree node per cell: the bake job builds the bricks of every
// asset, up to its budget's kept cells.
engine::Expected<CellBricks> buildCellBricks(const CellStream& stream) {
  ENGINE_TRY_ASSIGN(std::vector<BrickedCell> cells, brickedCells(stream));
  std::sort(cells.begin(), cells.end(), [](const BrickedCell& a, const BrickedCell& b) {
    return a.key < b.key || (a.key == b.key && a.record < b.record);
  });
  CellBricks result;
  result.cellRecords.reserve(cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const BrickedCell& cell = cells[i];
    if (i > 0 && cells[i - 1].key == cell.key) {  // a cell listed twice: its last record stands for it
      result.cellRecords.back() = cell.record;
      continue;
    }
    const auto xyz = std::uint32_t(cell.key >> 6);
    if (result.bricks.empty() || result.bricks.back().xyz != xyz)
      result.bricks.push_back({xyz, static_cast<std::uint32_t>(result.cellRecords.size()), 0u, 0u});
    const std::uint32_t bit = std::uint32_t(cell.key & 63u);
    (bit < 32 ? result.bricks.back().maskLo : result.bricks.back().maskHi) |= 1u << (bit & 31u);
    result.cellRecords.push_back(cell.record);
  }
  return result;
}

glm::uvec3 brickCoordinate(const shader::CellBrickGpu& brick) {
  return {brick.xyz & 0x3ffu, (brick.xyz >> 10) & 0x3ffu, brick.xyz >> 20};
}

void brickCellBounds(const shader::CellBrickGpu& brick, glm::uvec3& lo, glm::uvec3& hi) {
  const std::uint64_t mask = maskOf(brick);
  for (int axis = 0; axis < 3; ++axis) {
    const std::uint32_t slices = occupiedSlices(mask, axis);
    lo[axis] = slices == 0 ? 0u : std::uint32_t(std::countr_zero(slices));
    hi[axis] = slices == 0 ? 0u : 31u - std::uint32_t(std::countl_zero(slices));
  }
}

std::vector<std::uint32_t> bricksNearPoint(const std::vector<shader::CellBrickGpu>& bricks, const glm::dvec3& point,
                                           double radius) {
  std::vector<std::uint32_t> result;
  if (!std::isfinite(radius) || radius < 0.0) return result;
  const double r2 = radius * radius;
  for (std::uint32_t i = 0; i < bricks.size(); ++i) {
    glm::uvec3 lo, hi;
    brickCellBounds(bricks[i], lo, hi);
    const glm::dvec3 origin = glm::dvec3(brickCoordinate(bricks[i]) * kBrick);
    const glm::dvec3 boxLo = origin + glm::dvec3(lo), boxHi = origin + glm::dvec3(hi) + 1.0;
    const glm::dvec3 d = glm::max(glm::max(boxLo - point, point - boxHi), glm::dvec3(0.0));
    if (glm::dot(d, d) <= r2) result.push_back(i);
  }
  return result;
}

}  // namespace hsdf
