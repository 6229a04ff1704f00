#pragma once
// Command line of the scene runner. Parsing is separate from running so that it can be tested and
// so that every option is validated (with a message naming it) before any window or device opens.
// What a user tunes lands in a samples::TuningState (the same struct a --settings file writes).
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "engine/gpu/context.h"
#include "options_common.h"
#include "tuning.h"

namespace runner {

struct Options {
  std::filesystem::path scene;       // empty: the bundled bunny (unless --sdf is given)
  std::filesystem::path sdfFile;     // a baked .hsdf file (hsdf_bake) to draw as an SDF object
  bool headless = false;
  std::uint32_t width = 1280;
  std::uint32_t height = 720;
  std::uint32_t frames = 0;          // 0: until the window closes (headless: 1)
  std::filesystem::path screenshot;  // PNG written after the last frame
  engine::gpu::DevicePreference device = engine::gpu::DevicePreference::Auto;
  bool validation = false;
  bool headlessUi = false;           // draw the UI panels into headless screenshots
  bool groundPlane = true;
  bool sideBySide = false;           // keep the mesh and put the SDF copy beside it
  bool objects = false;              // each glTF mesh its own SDF object, drawn per node (--objects)
  std::optional<int> view;           // one of 8 fixed orbit views
  std::optional<std::array<float, 6>> camera;  // eye xyz, target xyz
  std::string animation;             // a glTF animation to play: index, name or none (--animation; default: the first)
  float animationTime = 0.0f;        // seconds into it at the first frame (--animation-time)
  std::string sceneCamera;           // a glTF camera node to look through: its name or index (--scene-camera)
  std::filesystem::path saveSettings;  // write the final tuning to this file (--save-settings)
  std::filesystem::path script;        // "frame N: key=value ..." lines (samples/common/script.h)
  std::uint64_t bakeBudgetMiB = 4096;  // bakes needing more memory are refused (--bake-budget-mib)
  std::uint64_t gpuBudgetMiB = 0;      // device memory cap, 0: none (--gpu-budget-mib)
  std::filesystem::path uiIni;         // ImGui window layout (windowed default: imgui.ini)
  std::filesystem::path pipelineCache;  // compiled pipelines kept across runs (--pipeline-cache; empty: not kept)

  // Method, K, padding, n, refinement, normals, fp16, debug view, front to back: defaults, then a
  // --settings file, then the options given on the command line.
  samples::TuningState tuning;
};

// Parses argv. Returns the options, or a message naming the bad option (exit code 2); `--help`
// yields the help text with exit code 0.
using ParseResult = samples::ParseResult<Options>;
ParseResult parseOptions(int argc, const char* const* argv);

}  // namespace runner
