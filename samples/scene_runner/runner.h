#pragma once
// The scene runner application: loads the scene, builds the renderer with its features and runs
// the frame loop in a window or headless.
#include "engine/core/expected.h"
#include "runner_options.h"

namespace runner {

// Runs to completion; returns an Error naming what failed (bad scene file, no Vulkan device, ...).
engine::Status run(const Options& options);

}  // namespace runner
