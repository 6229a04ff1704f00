#pragma once
// The shader statistics table (engine/gpu/shader_statistics.h) as Markdown and CSV: one row per
// stage of every pipeline, each marked with its role (production, counting only, ...), and the
// SPIR-V files no pipeline compiled. Compiler statistics, never timings.
#include <filesystem>
#include <string>
#include <vector>

#include "engine/gpu/shader_statistics.h"

namespace shader_stats {

// What a pipeline is for, from its name and shaders: "counting only" (the work counters'
// variants), "debug view" (wireframe and debug variants), "software rasterizers" (the cells' early
// depth stage, chosen on lavapipe only), else "production".
std::string pipelineRole(const engine::gpu::StageStatistics& row);

// The SPIR-V files (names without .spv) of `folder` that no row's stage was compiled from.
std::vector<std::string> uncompiledShaders(const std::vector<engine::gpu::StageStatistics>& rows,
                                           const std::filesystem::path& folder);

struct ReportHeader {
  std::string device;       // where the statistics come from
  std::string rendering;    // the device that drew the frames
  std::string commandLine;  // as run, for the first lines
  std::string commit;       // of the build
};

// Every statistic the driver reported, one column each (in the order first met), CSV-quoted.
std::string statisticsCsv(const std::vector<engine::gpu::StageStatistics>& rows);
// The header's lines, then the main statistics per stage (all of them where the driver names none
// of the usual ones), then the files never compiled.
std::string statisticsMarkdown(const std::vector<engine::gpu::StageStatistics>& rows, const ReportHeader& header,
                               const std::vector<std::string>& uncompiled);

}  // namespace shader_stats
