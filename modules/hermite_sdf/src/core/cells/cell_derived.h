#pragma once
// What the cell renderers draw besides an asset's records, derived from its fp32 records alone:
// the normal cone of every cell (cell culling), the bricks of cells and their cones (cell bricks,
// brick culling), the rows (draw order, cell lookup) and the runs of the default length (cell
// runs). Every make*Asset derives it (SdfAsset::derived), so a bake derives it on the bake job's
// worker thread, and the frame that first draws an asset in any of these forms only copies it
// into GPU buffers: building it in that frame held the render thread for as long as the cones
// take (a few microseconds a cell: docs/perf/render-changes-session31.md), and the rows and runs
// for tens of milliseconds on a large asset (docs/perf/render-changes-session41.md).
//
// Every form for every asset, not only the forms drawn: 22 bytes a kept cell on a torus for the
// cones and bricks (16 of them the cell cones), and about 21 for the rows and runs (16 of them the
// rows' cell lookup), on top of the 212 of its fp32 and fp16 records and proxy codes, within the
// sparse bake's sparseBakeBytesPerKeptCell (made after its slabs are freed). Building only the
// form an entity asks for, on a worker, would save them for assets never drawn culled or as
// bricks, at the price of frames drawing the asset unculled, or not as bricks, meanwhile.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cells/cell_bricks.h"
#include "cells/cell_rows.h"
#include "engine/core/expected.h"
#include "engine/core/progress.h"
#include "hermite/hermite_host_device.h"
#include "hermite_sdf/core/cells.h"

namespace hsdf {

struct SdfAsset;

struct CellDerived {
  std::vector<shader::CellBrickCone> cellCones;   // cellGradientCones: one per record, in record order
  CellBricks bricks;                              // buildCellBricks; none when bricksProblem says why
  std::vector<shader::CellBrickCone> brickCones;  // brickGradientCones: one per brick
  // Why the asset has no bricks (a grid of more than 4096 cells per axis: buildCellBricks), else empty.
  std::string bricksProblem;
  CellRows rows;                         // buildCellRows
  std::vector<shader::CellRunGpu> runs;  // buildCellRuns(cells, runLength)
  std::uint32_t runLength = kDefaultMaxRunLength;

  std::uint64_t bytes() const;
};

// The derived data of `cells`, cones on worker threads (`threads`, 0: all hardware threads).
// Errors: "cancelled" (the token); a grid too large for bricks is no error (bricksProblem).
engine::Expected<std::shared_ptr<const CellDerived>> deriveCellData(const CellStream& cells, unsigned threads = 0,
                                                                    const engine::CancelToken* cancel = nullptr);

// The asset's derived data when it matches its records (one cell cone per record); null for an
// asset made without make*Asset, or whose records were replaced after it was made.
const CellDerived* matchingDerived(const SdfAsset& asset);

}  // namespace hsdf
