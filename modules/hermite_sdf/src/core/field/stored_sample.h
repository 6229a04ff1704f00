#pragma once
// The conversion every bake (dense, narrow band, sparse) applies to a source sample before storing
// it, so that all of them store bit-identical floats and refuse non-finite values alike.
#include "engine/core/expected.h"
#include "hermite_sdf/core/field.h"

namespace hsdf::detail {

// s converted to float; an error naming sample (i,j,k) and its position if anything is not finite.
engine::Expected<HermiteSample> toStoredSample(const SdfSample& s, const GridSpec& grid, int i, int j, int k);

}  // namespace hsdf::detail
