#include "cells/cell_derived.h"

#include "hermite_sdf/core/normal_cone.h"
#include "hermite_sdf/core/sdf_asset.h"

namespace hsdf {

std::uint64_t CellDerived::bytes() const {
  return (cellCones.size() + brickCones.size()) * sizeof(shader::CellBrickCone) +
         bricks.bricks.size() * sizeof(shader::CellBrickGpu) + bricks.cellRecords.size() * sizeof(std::uint32_t) +
         rows.rows.size() * sizeof(CellRows::Row) + rows.zGroups.size() * sizeof(std::uint32_t) +
         rows.recordOfCell.size() * sizeof(rows.recordOfCell[0]) + runs.size() * sizeof(shader::CellRunGpu);
}

engine::Expected<std::shared_ptr<const CellDerived>> deriveCellData(const CellStream& cells, unsigned threads,
                                                                    const engine::CancelToken* cancel) {
  auto derived = std::make_shared<CellDerived>();
  ENGINE_TRY_ASSIGN(derived->cellCones, cellGradientCones(cells, threads, cancel).withContext("cell cones"));
  derived->rows = buildCellRows(cells);
  derived->runs = buildCellRuns(cells, derived->runLength);
  engine::Expected<CellBricks> bricks = buildCellBricks(cells);
  if (!bricks) {
    derived->bricksProblem = bricks.error().message;
    return std::shared_ptr<const CellDerived>(std::move(derived));
  }
  derived->bricks = std::move(*bricks);
  ENGINE_TRY_ASSIGN(derived->brickCones,
                    brickGradientCones(cells, derived->bricks.bricks, derived->bricks.cellRecords, threads, cancel)
                        .withContext("brick cones"));
  return std::shared_ptr<const CellDerived>(std::move(derived));
}

const CellDerived* matchingDerived(const SdfAsset& asset) {
  const CellDerived* derived = asset.derived.get();
  return derived && derived->cellCones.size() == asset.cells.records.size() ? derived : nullptr;
}

}  // namespace hsdf
