// What every asset carries for the cell renderers (cell_derived.h): the cones, bricks, rows and
// runs the cell feature built in the frame before, now made with the asset, compared with the core
// functions that build them; cancellation; grids too large for bricks; assets whose data do not
// match.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cells/cell_bricks.h"
#include "cells/cell_derived.h"
#include "cells/cell_rows.h"
#include "hermite_sdf/core/bake_job.h"
#include "hermite_sdf/core/normal_cone.h"
#include "hermite_sdf/core/sdf_asset.h"

namespace hsdf {
namespace {

std::shared_ptr<const SdfAsset> baked(const std::string& shape, int resolution, BakeBand band) {
  BakeSettings settings;
  settings.resolution = resolution;
  settings.band = band;
  auto asset = bakeAsset(BakeSource::fromShape(shape), settings);
  EXPECT_TRUE(asset.ok()) << asset.error().message;
  return asset ? *asset : nullptr;
}

void expectSameCones(const std::vector<shader::CellBrickCone>& carried, const std::vector<shader::CellBrickCone>& built,
                     const char* what) {
  ASSERT_EQ(carried.size(), built.size()) << what;
  for (std::size_t i = 0; i < built.size(); ++i)
    ASSERT_EQ(carried[i].axisCutoff, built[i].axisCutoff) << what << " " << i;
}

// The asset's derived data against the core functions the cell feature called in the frame: the
// cones of every cell on one thread, the bricks, the bricks' cones on one thread.
void expectDerivedAsBuiltNow(const SdfAsset& asset) {
  const CellDerived* derived = matchingDerived(asset);
  ASSERT_NE(derived, nullptr) << asset.name;
  expectSameCones(derived->cellCones, cellGradientCones(asset.cells, 1).value(), "cell cone");
  const CellBricks bricks = buildCellBricks(asset.cells).value();
  EXPECT_TRUE(derived->bricksProblem.empty()) << derived->bricksProblem;
  ASSERT_EQ(derived->bricks.bricks.size(), bricks.bricks.size());
  for (std::size_t b = 0; b < bricks.bricks.size(); ++b) {
    const shader::CellBrickGpu& carried = derived->bricks.bricks[b];
    const shader::CellBrickGpu& built = bricks.bricks[b];
    ASSERT_TRUE(carried.xyz == built.xyz && carried.firstIndex == built.firstIndex && carried.maskLo == built.maskLo &&
                carried.maskHi == built.maskHi)
        << "brick " << b;
  }
  EXPECT_EQ(derived->bricks.cellRecords, bricks.cellRecords);
  expectSameCones(derived->brickCones, brickGradientCones(asset.cells, bricks.bricks, bricks.cellRecords, 1).value(),
                  "brick cone");
  std::printf("[ %s ] %zu cells, %zu bricks: derived %.1f bytes a cell\n", asset.name.c_str(),
              asset.cells.records.size(), bricks.bricks.size(),
              double(derived->bytes()) / double(asset.cells.records.size()));
}

// Why: every way an asset is made must carry them (the dense bake, the sparse bake, cells read
// from a file), or the feature draws that asset unculled and not as bricks; and made on all
// threads in chunks (more than two chunks of 4096 records here), they must be each record's and
// each brick's own cone in order, exactly what one thread builds.
TEST(CellDerived, EveryMadeAssetCarriesTheConesAndBricksTheFeatureBuiltBefore) {
  const auto dense = baked("torus", 48, BakeBand::Dense);
  const auto sparse = baked("torus", 112, BakeBand::Sparse);
  ASSERT_NE(dense, nullptr);
  ASSERT_NE(sparse, nullptr);
  ASSERT_GT(sparse->cells.records.size(), 2u * 4096u) << "several chunks";
  expectDerivedAsBuiltNow(*dense);
  expectDerivedAsBuiltNow(*sparse);
  const auto fromCells = makeSdfAssetFromCells("torus cells", sparse->cells);
  ASSERT_TRUE(fromCells.ok()) << fromCells.error().message;
  expectDerivedAsBuiltNow(**fromCells);
}

// The asset's rows and runs against what the cell feature built in the frame before: buildCellRows,
// and buildCellRuns at the feature's default run length.
void expectRowsAndRunsAsBuiltNow(const SdfAsset& asset) {
  const CellDerived* derived = matchingDerived(asset);
  ASSERT_NE(derived, nullptr) << asset.name;
  const CellRows rows = buildCellRows(asset.cells);
  const CellRows& carried = derived->rows;
  EXPECT_EQ(carried.recordCount, rows.recordCount) << asset.name;
  ASSERT_EQ(carried.rows.size(), rows.rows.size()) << asset.name;
  for (std::size_t r = 0; r < rows.rows.size(); ++r)
    ASSERT_TRUE(carried.rows[r].first == rows.rows[r].first && carried.rows[r].count == rows.rows[r].count &&
                carried.rows[r].y == rows.rows[r].y && carried.rows[r].z == rows.rows[r].z)
        << asset.name << " row " << r;
  EXPECT_EQ(carried.zGroups, rows.zGroups) << asset.name;
  EXPECT_EQ(carried.recordOfCell, rows.recordOfCell) << asset.name;
  EXPECT_EQ(derived->runLength, kDefaultMaxRunLength);
  const std::vector<shader::CellRunGpu> runs = buildCellRuns(asset.cells, kDefaultMaxRunLength);
  ASSERT_EQ(derived->runs.size(), runs.size()) << asset.name;
  for (std::size_t r = 0; r < runs.size(); ++r)
    ASSERT_TRUE(derived->runs[r].xy == runs[r].xy && derived->runs[r].zLength == runs[r].zLength &&
                derived->runs[r].firstRecord == runs[r].firstRecord)
        << asset.name << " run " << r;
  const double rowBytes = double(rows.rows.size() * sizeof(CellRows::Row) + rows.zGroups.size() * sizeof(std::uint32_t) +
                                 rows.recordOfCell.size() * sizeof(rows.recordOfCell[0]));
  std::printf("[ %s ] %zu cells, %zu rows, %zu runs: rows %.1f, runs %.1f bytes a cell\n", asset.name.c_str(),
              asset.cells.records.size(), rows.rows.size(), runs.size(), rowBytes / double(asset.cells.records.size()),
              double(runs.size() * sizeof(shader::CellRunGpu)) / double(asset.cells.records.size()));
}

// Why: the frame that first drew an asset built its rows (draw order, cell lookup) and runs on the
// render thread, tens of milliseconds for a large asset; every way an asset is made must now carry
// exactly those (or the feature draws other rows and runs than a fresh build), including a stream
// made by hand in another order than a bake's (the lookup table sorted).
TEST(CellDerived, EveryMadeAssetCarriesTheRowsAndRunsTheFeatureBuiltBefore) {
  const auto dense = baked("torus", 48, BakeBand::Dense);
  const auto sparse = baked("torus", 112, BakeBand::Sparse);
  ASSERT_NE(dense, nullptr);
  ASSERT_NE(sparse, nullptr);
  expectRowsAndRunsAsBuiltNow(*dense);
  expectRowsAndRunsAsBuiltNow(*sparse);
  const auto fromCells = makeSdfAssetFromCells("torus cells", sparse->cells);
  ASSERT_TRUE(fromCells.ok()) << fromCells.error().message;
  expectRowsAndRunsAsBuiltNow(**fromCells);
  CellStream reversed = sparse->cells;
  std::reverse(reversed.records.begin(), reversed.records.end());
  const auto byHand = makeSdfAssetFromCells("torus cells reversed", std::move(reversed));
  ASSERT_TRUE(byHand.ok()) << byHand.error().message;
  expectRowsAndRunsAsBuiltNow(**byHand);
}

// Why: the bake job's cancel token must stop the cones too (seconds at K >= 1024), with the
// bake's "cancelled", not an asset without cones.
TEST(CellDerived, ACancelledTokenStopsTheDerivationWithCancelled) {
  const auto sparse = baked("sphere", 48, BakeBand::Sparse);
  ASSERT_NE(sparse, nullptr);
  engine::CancelToken cancel;
  cancel.cancel();
  const auto derived = deriveCellData(sparse->cells, 0, &cancel);
  ASSERT_FALSE(derived.ok());
  EXPECT_NE(derived.error().message.find("cancelled"), std::string::npos) << derived.error().message;
  const auto asset = makeSdfAssetFromSparseBake("sphere", sparse->cells, sparse->classification.stats, 0,
                                                sparse->surfaceBounds, {}, 0, &cancel);
  ASSERT_FALSE(asset.ok());
  EXPECT_NE(asset.error().message.find("cancelled"), std::string::npos) << asset.error().message;
}

// Why: a grid of more than 4096 cells per axis has no brick coordinates; that is no reason to
// refuse the asset (cells and runs draw it, with their cones), only to name why it has no bricks.
TEST(CellDerived, AGridTooLargeForBricksKeepsItsCellConesAndNamesWhy) {
  CellStream cells;
  cells.grid.resolution = 4100;
  cells.grid.spacing = 1.0;
  for (const std::uint16_t x : {std::uint16_t(3), std::uint16_t(4097)}) {
    CellRecord record;
    record.x = x;
    for (std::size_t c = 0; c < record.corners.size(); ++c)
      record.corners[c] = {float(c & 1) - 0.5f, 1.0f, 0.0f, 0.0f};  // a plane x = 0.5 in the cell
    cells.records.push_back(record);
  }
  const auto derived = deriveCellData(cells);
  ASSERT_TRUE(derived.ok()) << derived.error().message;
  EXPECT_NE((*derived)->bricksProblem.find("beyond the 1024 bricks"), std::string::npos) << (*derived)->bricksProblem;
  EXPECT_TRUE((*derived)->bricks.bricks.empty());
  expectSameCones((*derived)->cellCones, cellGradientCones(cells, 1).value(), "cell cone");
  EXPECT_LT((*derived)->cellCones[0].axisCutoff.w, 1.0f) << "a plane's cell has a cone that culls";
}

// Why: an asset copied and given other records (or made by hand) must not hand the feature cones
// of other cells: those would cull cells that can be seen.
TEST(CellDerived, DataOfOtherRecordsIsNotMatched) {
  const auto sparse = baked("sphere", 32, BakeBand::Sparse);
  ASSERT_NE(sparse, nullptr);
  EXPECT_NE(matchingDerived(*sparse), nullptr);
  SdfAsset fewer = *sparse;
  fewer.cells.records.pop_back();
  EXPECT_EQ(matchingDerived(fewer), nullptr);
  SdfAsset byHand;
  byHand.cells = sparse->cells;
  EXPECT_EQ(matchingDerived(byHand), nullptr);
}

}  // namespace
}  // namespace hsdf
