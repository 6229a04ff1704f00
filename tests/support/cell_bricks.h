#pragma once
// Cell bricks built from a cell stream for the brick culling tests (issue 20): the layout
// hermite_host_device.h's CellBrickGpu describes (4x4x4 cells a brick, the brick's kept cells
// listed in mask-bit order from firstIndex). A stand-in for the renderer's own brick builder (the
// cell bricks work), which the tests should call instead once it is in the module.
#include <cstdint>
#include <map>
#include <vector>

#include "hermite/hermite_host_device.h"
#include "hermite_sdf/cells.h"

namespace testbricks {

struct CellBricks {
  std::vector<shader::CellBrickGpu> bricks;  // in brick index order (x fastest)
  std::vector<std::uint32_t> indices;        // record indices, per brick in mask-bit order
};

inline CellBricks buildCellBricks(const hsdf::CellStream& stream) {
  constexpr std::uint32_t kSize = CELL_BRICK_SIZE;
  // brick key (z, y, x packed as xyz) -> record index of each of its 64 cells (or none)
  std::map<std::uint64_t, std::vector<std::int64_t>> cells;
  for (std::uint32_t r = 0; r < stream.records.size(); ++r) {
    const hsdf::CellRecord& record = stream.records[r];
    const std::uint32_t bx = record.x / kSize, by = record.y / kSize, bz = record.z / kSize;
    const std::uint64_t key = (std::uint64_t(bz) << 40) | (std::uint64_t(by) << 20) | bx;
    auto& slots = cells.try_emplace(key, std::vector<std::int64_t>(64, -1)).first->second;
    slots[(record.x % kSize) + kSize * (record.y % kSize) + kSize * kSize * (record.z % kSize)] = r;
  }
  CellBricks out;
  for (const auto& [key, slots] : cells) {
    shader::CellBrickGpu brick{};
    const std::uint32_t bx = std::uint32_t(key & 0xFFFFF), by = std::uint32_t((key >> 20) & 0xFFFFF),
                        bz = std::uint32_t(key >> 40);
    brick.xyz = bx | (by << 10) | (bz << 20);
    brick.firstIndex = std::uint32_t(out.indices.size());
    for (std::uint32_t bit = 0; bit < 64; ++bit) {
      if (slots[bit] < 0) continue;
      (bit < 32 ? brick.maskLo : brick.maskHi) |= 1u << (bit % 32);
      out.indices.push_back(std::uint32_t(slots[bit]));
    }
    out.bricks.push_back(brick);
  }
  return out;
}

}  // namespace testbricks
