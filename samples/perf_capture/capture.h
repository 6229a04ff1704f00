#pragma once
// The perf capture: every row (method x K x setting, capture_rows.h) rendered from the
// same fixed orbit views, timed, measured against the ground truth and written to the output folder.
#include "capture_options.h"
#include "engine/core/expected.h"

namespace capture {

// Runs every row. Errors stop the capture (no device, bad scene, unwritable folder); a row that
// fails to render is recorded as failed and counted in `failedRows`, and the others go on.
engine::Status run(const Options& options, int& failedRows);

}  // namespace capture
