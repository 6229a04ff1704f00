#pragma once
// Checks shared by the writer and the reader: what makes a set of .hsdf contents consistent.
#include <string>

#include "engine/core/expected.h"
#include "hermite_sdf/core/hsdf_file.h"

namespace hsdf::io {

bool sameGrid(const GridSpec& a, const GridSpec& b);

// Records inside the grid, of a kept class, in strictly increasing cell index order.
engine::Status checkCellRecords(const CellStream& cells, int resolution);

// Every corner of every record equals the dense field's sample there.
engine::Status checkCellsMatchField(const CellStream& cells, const HermiteField& field);

// "sample 12 (i, j, k)" / "cell record 3 (x, y, z)" for error messages.
std::string describeSample(const GridSpec& grid, std::size_t index);

}  // namespace hsdf::io
