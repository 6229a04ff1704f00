#include "io/hsdf_contents.h"

#include <fmt/format.h>

namespace hsdf::io {

bool sameGrid(const GridSpec& a, const GridSpec& b) {
  return a.resolution == b.resolution && a.spacing == b.spacing && a.origin == b.origin;
}

std::string describeSample(const GridSpec& grid, std::size_t index) {
  const std::size_t k = std::size_t(grid.resolution);
  return fmt::format("sample {} ({}, {}, {})", index, index % k, index / k % k, index / (k * k));
}

engine::Status checkCellRecords(const CellStream& cells, int resolution) {
  const std::uint64_t n = std::uint64_t(resolution - 1);
  std::uint64_t previous = 0;
  for (std::size_t r = 0; r < cells.records.size(); ++r) {
    const CellRecord& record = cells.records[r];
    if (record.x >= n || record.y >= n || record.z >= n)
      return engine::makeError(fmt::format("cell record {} has coordinate ({}, {}, {}) outside the {}^3 cells of the grid",
                                           r, record.x, record.y, record.z, n));
    if (record.cellClass != std::uint16_t(CellClass::Crossing) && record.cellClass != std::uint16_t(CellClass::Ambiguous))
      return engine::makeError(fmt::format("cell record {} has class {}, expected 1 (crossing) or 2 (ambiguous)", r,
                                           record.cellClass));
    const std::uint64_t index = record.x + n * (record.y + n * std::uint64_t(record.z));
    if (r > 0 && index <= previous)
      return engine::makeError(fmt::format(
          "cell record {} ({}, {}, {}) is not after the previous record: records must be in strictly increasing cell "
          "index order (x fastest), without duplicates",
          r, record.x, record.y, record.z));
    previous = index;
  }
  return {};
}

engine::Status checkCellsMatchField(const CellStream& cells, const HermiteField& field) {
  for (std::size_t r = 0; r < cells.records.size(); ++r) {
    const CellRecord& record = cells.records[r];
    for (int c = 0; c < 8; ++c) {
      const HermiteSample& fromField = field.at(record.x + (c & 1), record.y + ((c >> 1) & 1), record.z + ((c >> 2) & 1));
      const HermiteSample& fromCell = record.corners[std::size_t(c)];
      if (fromField.f != fromCell.f || fromField.fx != fromCell.fx || fromField.fy != fromCell.fy ||
          fromField.fz != fromCell.fz)
        return engine::makeError(fmt::format("cell record {} ({}, {}, {}) corner {} differs from the dense field", r,
                                             record.x, record.y, record.z, c));
    }
  }
  return {};
}

}  // namespace hsdf::io
