#pragma once
// Command line of the perf capture (issue 10):
//   perf_capture --out DIR [--scene FILE | --shape NAME] [--size WxH] [--resolutions 16,32,64,128]
//                [--methods mesh,trilinear,hermite,cells,cells-runs,cell-bricks] [--settings "n=3 r=1,..."] [--views N]
//                [--frames N] [--warmup N] [--quick]
// Every value is checked before a device opens; a bad one is refused naming its option.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace capture {

struct Options {
  std::filesystem::path out;
  std::filesystem::path scene;   // glTF/GLB; empty with a shape
  std::string shape;             // analytic shape (torus, sphere, capsule, box); empty with a scene
  std::uint32_t width = 1920;
  std::uint32_t height = 1080;
  std::vector<int> resolutions{16, 32, 64, 128};
  std::vector<std::string> methods{"mesh", "trilinear", "hermite", "cells", "cells-runs", "cell-bricks"};
  // Settings of the cell methods to capture (capture_rows.cpp labels, e.g. "n=3 r=1"); empty: all.
  std::vector<std::string> cellSettings;
  std::uint32_t views = 8;
  std::uint32_t frames = 5;      // timed frames per view
  std::uint32_t warmup = 2;      // untimed frames per view before them
  bool quick = false;
  std::string device = "auto";   // auto | gpu | lavapipe
  std::string commandLine;       // as given, for results.json
};

struct ParseResult {
  std::optional<Options> options;
  std::string message;  // help text or error
  int exitCode = 0;
};
ParseResult parseOptions(int argc, const char* const* argv);

std::filesystem::path defaultScenePath();

}  // namespace capture
