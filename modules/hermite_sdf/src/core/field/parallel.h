#pragma once
// Runs independent work items on worker threads while the calling thread reports progress and
// watches for cancellation, so progress callbacks (UI, terminal) never run on a worker.
#include <cstddef>
#include <functional>

#include "engine/core/expected.h"
#include "hermite_sdf/core/field.h"

namespace hsdf::detail {

// Calls work(i) for every i in [0, count), items claimed in increasing order. Stops at the first
// item error (returned), on cancellation ("cancelled"), or when the progress callback returns false;
// the callback is called with 0 before any work, then every 20 ms or so, and with 1 at the end.
engine::Status runParallel(std::size_t count, const BakeOptions& options,
                           const std::function<engine::Status(std::size_t)>& work);

}  // namespace hsdf::detail
