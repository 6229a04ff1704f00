#pragma once
// Draw order of a cell stream: records are stored x fastest, then y, then z, so every run of
// records with the same (y, z) is a row that one instanced draw can cover. Sorting rows by their
// distance to the eye gives a roughly front-to-back submission (exact across rows, x order fixed
// within a row) without reordering the records on the GPU.
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "hermite_sdf/core/cells.h"
#include "hermite/hermite_host_device.h"

namespace hsdf {

struct CellRows {
  struct Range {
    std::uint32_t first = 0;  // record index within the stream
    std::uint32_t count = 0;
  };
  struct Row {
    std::uint32_t first = 0;
    std::uint32_t count = 0;
    std::uint16_t y = 0, z = 0;
  };
  std::vector<Row> rows;                  // stream order
  std::vector<std::uint32_t> zGroups;     // index of the first row of each distinct z, then rows.size()
  // (cellKey, record) of every record, by key: a cell's record by binary search. Half the bytes of a
  // hash map and built in one pass for a stream in cell order (bakes and .hsdf files; a stream made
  // by hand in another order is sorted).
  std::vector<std::pair<std::uint64_t, std::uint32_t>> recordOfCell;
  std::uint32_t recordCount = 0;

  static std::uint64_t cellKey(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    return std::uint64_t(x) | (std::uint64_t(y) << 16) | (std::uint64_t(z) << 32);
  }
  // The record of the kept cell (x, y, z), or none.
  std::optional<std::uint32_t> recordOf(std::uint32_t x, std::uint32_t y, std::uint32_t z) const;
};

CellRows buildCellRows(const CellStream& stream);

// Ranges of records to draw: all records at once, or rows nearest to `eyeGrid` (in grid units,
// sample (i,j,k) at (i,j,k)) first; consecutive ranges are merged.
std::vector<CellRows::Range> orderedRows(const CellRows& rows, const glm::dvec3& eyeGrid, bool frontToBack);

// Records of the kept cells whose box comes within `radius` (grid units) of `point`.
std::vector<std::uint32_t> cellsNearPoint(const CellRows& rows, const CellStream& stream, const glm::dvec3& point,
                                          double radius);

// Runs of kept cells (RenderMethod::CellRuns): cells at consecutive x in one row, at most
// `maxLength` per run, in stream order (a run never crosses a row, so the records of whole rows
// are the records of consecutive runs). firstRecord is the stream index of the run's first cell.
std::vector<shader::CellRunGpu> buildCellRuns(const CellStream& stream, std::uint32_t maxLength);

// The records that buildCellRows and buildCellRuns have gone through for calls made on the calling
// thread: what shows that a thread, such as the render thread, left that work to the asset's
// derived data (cell_derived.h).
std::uint64_t cellRowsAndRunsBuiltOnThisThread();

// The runs that hold the records of `recordRanges` (each made of whole rows, as orderedRows
// gives them), in the same order; consecutive ranges are merged.
std::vector<CellRows::Range> runRanges(const std::vector<shader::CellRunGpu>& runs,
                                       const std::vector<CellRows::Range>& recordRanges);

// Indices of the runs whose box comes within `radius` (grid units) of `point`.
std::vector<std::uint32_t> runsNearPoint(const std::vector<shader::CellRunGpu>& runs, const glm::dvec3& point,
                                         double radius);

}  // namespace hsdf
