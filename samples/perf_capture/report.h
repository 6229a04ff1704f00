#pragma once
// The capture's outputs: results.csv (one row per method x K x setting under a fixed header),
// results.json (device, driver, command line, commit, date, and every row), results.md (the
// paper's table beside this run's, ratios, targets checked, every row, work and quality), charts.
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "capture_rows.h"
#include "engine/core/expected.h"
#include "metrics.h"

namespace capture {

struct Options;

struct RowResult {
  RowSpec spec;
  bool ok = false;
  std::string error;           // why the row failed
  double gpuMsMedian = 0.0, gpuMsP95 = 0.0;
  double prepassMs = 0.0, shadingMs = 0.0;  // medians
  // Median of every named GPU timing of the frame ("frame", "prepare" with the features' compute
  // scopes inside it, "depth prepass", "opaque" and the features' scopes inside those), in the
  // order the frame first recorded them.
  std::vector<std::pair<std::string, double>> passMs;
  // Pipeline statistics per frame, mean over views (0 without the feature).
  double fsInvocations = 0.0;  // both passes
  double prepassFsInvocations = 0.0, shadingFsInvocations = 0.0;
  double vsInvocations = 0.0, clippedPrimitives = 0.0;
  double prepassVsInvocations = 0.0;
  // Proxy boxes the cells drew per frame (instances: cells, or runs for cells-runs), mean over
  // views; 0 for the other methods.
  double boxes = 0.0;
  RowQuality quality;
  std::vector<PartQuality> parts;  // per object of a scene (empty for a single shape)
  // Storage: what the scene holds (with levels of detail every level, K, K/2, ...); cells: the kept
  // cells stored, with levels of detail those of the levels drawn, mean over views.
  std::uint64_t storedScalars = 0, storedBytes = 0, cells = 0;
  std::string image;           // first view's screenshot, relative to the output folder
};

struct RunInfo {
  std::string device, driver, commandLine, commit, date, scene;
  std::vector<std::string> partNames;  // [SceneData::nodes index] "node (mesh)", for PartQuality::part
  std::uint32_t width = 0, height = 0, views = 0, frames = 0, warmup = 0;
  std::vector<std::string> viewNames;  // --scene-cameras: the cameras, one per view; empty: orbit views
  bool pipelineStatistics = false;
  bool softwareRasterizer = false;
  // The rows the command asked for, and whether every one was run or listed as not run: the CSV and
  // JSON are saved after each row, so an interrupted capture leaves files that must say so.
  std::size_t rowsPlanned = 0;
  bool complete = false;
};

engine::Status writeCsv(const std::filesystem::path& path, const RunInfo& info, const std::vector<RowResult>& rows);
// objects.csv: one line per row and object of a scene (PartQuality); nothing when no row has two.
engine::Status writeObjectsCsv(const std::filesystem::path& path, const RunInfo& info, const std::vector<RowResult>& rows);
engine::Status writeJson(const std::filesystem::path& path, const RunInfo& info, const std::vector<RowResult>& rows);
// Writes the charts next to results.md and the Markdown that shows them.
engine::Status writeMarkdown(const std::filesystem::path& folder, const RunInfo& info, const std::vector<RowResult>& rows);

}  // namespace capture
