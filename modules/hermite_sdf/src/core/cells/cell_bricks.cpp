#include "cells/cell_bricks.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>
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

engine::Expected<CellBricks> buildCellBricks(const CellStream& stream) {
  // Ordered by brick (z, y, x), then by mask bit: the map's key is the brick's packed coordinate
  // with z in the high bits, the inner key the bit.
  std::map<std::uint32_t, std::map<std::uint32_t, std::uint32_t>> cellsOfBrick;
  for (std::uint32_t i = 0; i < stream.records.size(); ++i) {
    const CellRecord& r = stream.records[i];
    const glm::uvec3 cell(r.x, r.y, r.z);
    const glm::uvec3 brick = cell / kBrick;
    if (glm::any(glm::greaterThan(brick, glm::uvec3(kMaxBrickCoordinate))))
      return engine::makeError("cell bricks: cell (" + std::to_string(cell.x) + ", " + std::to_string(cell.y) + ", " +
                               std::to_string(cell.z) + ") lies beyond the 1024 bricks per axis a brick coordinate holds");
    const glm::uvec3 inBrick = cell % kBrick;
    const std::uint32_t bit = inBrick.x + kBrick * inBrick.y + kBrick * kBrick * inBrick.z;
    cellsOfBrick[brick.x | (brick.y << 10) | (brick.z << 20)][bit] = i;
  }
  CellBricks result;
  result.bricks.reserve(cellsOfBrick.size());
  result.cellRecords.reserve(stream.records.size());
  for (const auto& [xyz, cells] : cellsOfBrick) {
    std::uint64_t mask = 0;
    for (const auto& [bit, record] : cells) mask |= std::uint64_t(1) << bit;
    result.bricks.push_back({xyz, static_cast<std::uint32_t>(result.cellRecords.size()), std::uint32_t(mask),
                             std::uint32_t(mask >> 32)});
    for (const auto& [bit, record] : cells) result.cellRecords.push_back(record);
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
