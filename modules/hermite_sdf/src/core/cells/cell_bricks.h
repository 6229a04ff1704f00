#pragma once
// Bricks of kept cells (RenderMethod::CellBricks): the grid's cells in blocks of
// CELL_BRICK_SIZE^3; each block holding a kept cell is one proxy box whose fragment shader walks
// its kept cells along the ray (bricks_depth.glsl). Fewer, larger boxes than cells or runs: the
// number of proxies grows with the surface area in bricks, not in cells.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/expected.h"
#include "hermite_sdf/core/cells.h"
#include "hermite/hermite_host_device.h"

namespace hsdf {

struct CellBricks {
  std::vector<shader::CellBrickGpu> bricks;  // by brick coordinate, z slowest, x fastest
  // Stream indices of the bricks' kept cells: brick b's cells in the order of their mask bits
  // (x + 4y + 16z within the brick) from bricks[b].firstIndex on.
  std::vector<std::uint32_t> cellRecords;
};

// Every kept cell of `stream` in exactly one brick. Errors: a brick coordinate that does not fit
// in CellBrickGpu::xyz's 10 bits per axis (grids of more than 4096 cells per axis).
engine::Expected<CellBricks> buildCellBricks(const CellStream& stream);

// The brick's coordinate in bricks, and its kept cells' bounds within the brick (cells, inclusive),
// as bricks_depth.glsl decodes them.
glm::uvec3 brickCoordinate(const shader::CellBrickGpu& brick);
void brickCellBounds(const shader::CellBrickGpu& brick, glm::uvec3& lo, glm::uvec3& hi);

// Indices of the bricks whose kept cells' box comes within `radius` (grid units) of `point`.
std::vector<std::uint32_t> bricksNearPoint(const std::vector<shader::CellBrickGpu>& bricks, const glm::dvec3& point,
                                           double radius);

}  // namespace hsdf
