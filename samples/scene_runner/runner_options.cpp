#include "runner_options.h"

#include <cstdlib>
#include <algorithm>
#include <cmath>
#include <regex>

#include <CLI/CLI.hpp>

#include "shared/host_device.h"

namespace runner {
namespace {

constexpr std::uint32_t kMaxDimension = 16384;

// "WxH" with both in [1, kMaxDimension].
bool parseSize(const std::string& text, std::uint32_t& width, std::uint32_t& height) {
  static const std::regex pattern(R"((\d{1,6})[xX](\d{1,6}))");
  std::smatch match;
  if (!std::regex_match(text, match, pattern)) return false;
  const unsigned long w = std::stoul(match[1]), h = std::stoul(match[2]);
  if (w == 0 || h == 0 || w > kMaxDimension || h > kMaxDimension) return false;
  width = std::uint32_t(w);
  height = std::uint32_t(h);
  return true;
}

}  // namespace

std::uint32_t debugViewIndex(const std::string& name) {
  if (name == "normals") return DEBUG_VIEW_NORMALS;
  if (name == "depth") return DEBUG_VIEW_DEPTH;
  if (name == "cells") return DEBUG_VIEW_CELLS;
  if (name == "evals") return DEBUG_VIEW_EVALS;
  if (name == "wireframe") return DEBUG_VIEW_WIREFRAME;
  return DEBUG_VIEW_NONE;
}

std::filesystem::path defaultScenePath() {
  if (const char* dir = std::getenv("HSDF_ASSET_DIR")) return std::filesystem::path(dir) / "bunny.glb";
  return std::filesystem::path(HSDF_DEFAULT_ASSET_DIR) / "bunny.glb";
}

ParseResult parseOptions(int argc, const char* const* argv) {
  Options options;
  std::string size;
  CLI::App app{"hermite_sdf scene runner: renders a glTF scene (default: the bundled bunny)", "scene_runner"};
  app.add_option("--scene", options.scene, "glTF/GLB scene to load")->check(CLI::ExistingFile);
  app.add_option("--sdf", options.sdfFile, "draw a .hsdf file baked by hsdf_bake (replaces the default scene)")
      ->check(CLI::ExistingFile);
  app.add_flag("--headless", options.headless, "render offscreen without a window");
  app.add_option("--size", size, "image size WxH (default 1280x720)");
  app.add_option("--frames", options.frames, "frames to render, then exit (0: until closed; headless default 1)")
      ->check(CLI::Range(0u, 1000000u));
  app.add_option("--screenshot", options.screenshot, "write the last frame to this PNG file");
  app.add_option("--device", options.device, "Vulkan device: auto, gpu or lavapipe")
      ->check(CLI::IsMember({"auto", "gpu", "lavapipe"}));
  app.add_flag("--validation", options.validation, "enable the Vulkan validation layers");
  app.add_flag("--ui", options.headlessUi, "draw the ImGui panels into headless screenshots");
  app.add_flag("!--no-ground", options.groundPlane, "do not add the ground plane");
  app.add_option("--method", options.method, "mesh, cells (Hermite cells), trilinear or hermite (sphere tracing)")
      ->check(CLI::IsMember({"mesh", "cells", "trilinear", "hermite"}));
  app.add_option("--resolution", options.resolution, "samples per axis K of the baked field (2..256)")
      ->check(CLI::Range(2, 256));
  app.add_option("--padding", options.padding, "cells of padding around the mesh (0..16)")->check(CLI::Range(0, 16));
  app.add_option("--subdivisions", options.subdivisions, "equidistant evaluations per cell (1..64)")
      ->check(CLI::Range(1u, 64u));
  app.add_option("--refine", options.refine, "root refinement steps (0..16)")->check(CLI::Range(0u, 16u));
  app.add_flag("--fp16", options.fp16, "half-precision cell records / textures");
  app.add_option("--normals", options.normals, "exact or central (differences)")
      ->check(CLI::IsMember({"exact", "central"}));
  app.add_option("--debug-view", options.debugView, "none, normals, depth, cells, evals or wireframe")
      ->check(CLI::IsMember({"none", "normals", "depth", "cells", "evals", "wireframe"}));
  app.add_flag("--side-by-side", options.sideBySide, "keep the mesh and place the SDF beside it");
  app.add_flag("!--no-front-to-back", options.frontToBack, "cells: submit in storage order, not front to back");
  app.add_option("--view", options.view, "one of 8 fixed orbit views (0..7)")->check(CLI::Range(0, 7));
  std::vector<float> camera;
  app.add_option("--camera", camera, "eye and target: ex,ey,ez,tx,ty,tz")->delimiter(',')->expected(6);

  ParseResult result;
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    result.message = app.help();
    return result;
  } catch (const CLI::ParseError& e) {
    result.message = std::string("scene_runner: ") + e.what() + "\nRun with --help for the options.";
    result.exitCode = 2;
    return result;
  }
  if (!size.empty() && !parseSize(size, options.width, options.height)) {
    result.message = "scene_runner: --size: '" + size + "' is not WxH with 1 <= W,H <= " +
                     std::to_string(kMaxDimension);
    result.exitCode = 2;
    return result;
  }
  if (!options.screenshot.empty() && options.screenshot.extension() != ".png") {
    result.message = "scene_runner: --screenshot: '" + options.screenshot.string() + "' must end in .png";
    result.exitCode = 2;
    return result;
  }
  if (!camera.empty()) {
    std::array<float, 6> values{};
    std::copy(camera.begin(), camera.end(), values.begin());
    const bool finite = std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); });
    const bool distinct = values[0] != values[3] || values[1] != values[4] || values[2] != values[5];
    if (!finite || !distinct) {
      result.message = "scene_runner: --camera: eye and target must be finite and different";
      result.exitCode = 2;
      return result;
    }
    options.camera = values;
  }
  if (options.resolution - 1 - 2 * options.padding < 1) {
    result.message = "scene_runner: --resolution " + std::to_string(options.resolution) + " leaves no cells inside --padding " +
                     std::to_string(options.padding);
    result.exitCode = 2;
    return result;
  }
  if (options.headless && options.frames == 0) options.frames = 1;
  if (options.scene.empty() && options.sdfFile.empty()) options.scene = defaultScenePath();
  if (!options.sdfFile.empty() && options.method == "mesh") options.method = "cells";
  result.options = options;
  return result;
}

}  // namespace runner
