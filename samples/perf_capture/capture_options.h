#pragma once
// Command line of the perf capture:
//   perf_capture --out DIR [--scene FILE [--objects] | --shape NAME] [--size WxH] [--resolutions 16,32,64,128]
//                [--methods mesh,trilinear,hermite,cells,cells-runs,cell-bricks] [--settings "n=3 r=1,..."]
//                [--views N | --scene-cameras all|NAME,...]
//                [--frames N] [--warmup N] [--quick] [--lod] [--distance F] [--time-limit SECONDS]
// Every value is checked before a device opens; a bad one is refused naming its option.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "options_common.h"

namespace capture {

struct Options {
  std::filesystem::path out;
  std::filesystem::path scene;   // glTF/GLB; empty with a shape
  std::string shape;             // analytic shape (torus, sphere, capsule, box); empty with a scene
  // The scene's meshes as separate SDF objects, one bake per mesh drawn by every node that places
  // it (samples::SceneDesc::objects): the scene row set. Each K loads the scene anew.
  bool objects = false;
  std::uint32_t width = 1920;
  std::uint32_t height = 1080;
  std::vector<int> resolutions{16, 32, 64, 128};
  std::vector<std::string> methods{"mesh", "trilinear", "hermite", "cells", "cells-runs", "cell-bricks"};
  // Settings of the cell methods to capture (capture_rows.cpp labels, e.g. "n=3 r=1"); empty: all.
  std::vector<std::string> cellSettings;
  std::uint32_t views = 8;
  // The views are these perspective cameras of the --scene (glTF camera nodes, by name or index;
  // "all": every one, in node order) instead of the orbit views: a scene measured from where its
  // author looks at it. Empty: the orbit views.
  std::vector<std::string> sceneCameras;
  std::uint32_t frames = 5;      // timed frames per view
  std::uint32_t warmup = 2;      // untimed frames per view before them
  bool quick = false;
  // Levels of detail: each cell row also with TuningState::lod on (label "... lod K=..."),
  // and the orbit views `distance` times farther than the framing (1..64): the same object near
  // (1) and far (e.g. 8) in two runs, its prepass work per row in results.json.
  bool lod = false;
  float distance = 1.0f;
  engine::gpu::DevicePreference device = engine::gpu::DevicePreference::Auto;  // --device
  // No row starts after this many seconds from the start (0: no limit; the first row always runs):
  // the rest are listed as not run and the outputs written, within a device call's time limit.
  double timeLimitSeconds = 0.0;
  std::string commandLine;       // as given, for results.json
};

using ParseResult = samples::ParseResult<Options>;
ParseResult parseOptions(int argc, const char* const* argv);

}  // namespace capture
