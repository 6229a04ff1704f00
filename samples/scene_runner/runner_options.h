#pragma once
// Command line of the scene runner. Parsing is separate from running so that it can be tested and
// so that every option is validated (with a message naming it) before any window or device opens.
#include <cstdint>
#include <filesystem>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/expected.h"

namespace runner {

// Sizes the camera and the shaders handle in 32-bit floats: scenes (bounding-box diagonal) and
// --camera distances in this range. Outside about 1e-19..1e19 squared distances underflow or
// overflow floats and frames come out empty; measured on lavapipe, cubes 1e-20..1e18 across draw
// correctly with every method and 1e20 draws nothing, so the range keeps a margin of 1e3 or more.
inline constexpr double kMinSceneSize = 1e-15;
inline constexpr double kMaxSceneSize = 1e15;

struct Options {
  std::filesystem::path scene;       // empty: the bundled bunny (unless --sdf is given)
  std::filesystem::path sdfFile;     // a baked .hsdf file (hsdf_bake) to draw as an SDF object
  bool headless = false;
  std::uint32_t width = 1280;
  std::uint32_t height = 720;
  std::uint32_t frames = 0;          // 0: until the window closes (headless: 1)
  std::filesystem::path screenshot;  // PNG written after the last frame
  std::string device = "auto";       // auto | gpu | lavapipe
  bool validation = false;
  bool showUi = true;                // windowed: always; headless: drawn into the screenshot with --ui
  bool headlessUi = false;
  bool groundPlane = true;

  // How the scene's meshes are drawn: "mesh" (triangles), or baked into one SDF drawn by
  // "cells" (the paper's method), "trilinear" or "hermite" (sphere-tracing baselines).
  std::string method = "mesh";
  int resolution = 64;               // K samples per axis of the baked field
  int padding = 1;                   // cells of padding around the mesh bounds
  std::uint32_t subdivisions = 3;
  std::uint32_t refine = 1;
  bool fp16 = false;
  std::string normals = "exact";     // exact | central
  std::string debugView = "none";    // none | normals | depth | cells | evals | wireframe
  bool sideBySide = false;           // keep the mesh and put the SDF copy beside it
  bool frontToBack = true;           // cells: submit rows of cells front to back
  std::optional<int> view;           // one of 8 fixed orbit views
  std::optional<std::array<float, 6>> camera;  // eye xyz, target xyz
};

// Parses argv. Returns the options, or an Error whose message names the bad option; `--help`
// yields an Error with `helpText` set and exit code 0.
struct ParseResult {
  std::optional<Options> options;
  std::string message;  // help text or error
  int exitCode = 0;
};
ParseResult parseOptions(int argc, const char* const* argv);

std::filesystem::path defaultScenePath();
std::uint32_t debugViewIndex(const std::string& name);  // DEBUG_VIEW_* of a --debug-view name

}  // namespace runner
