#include "runner_options.h"

#include <cstdlib>
#include <algorithm>
#include <cmath>
#include <regex>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <glm/glm.hpp>

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

// Eye and target as given, or a message. Their distance is the orbit camera's radius, in float.
std::optional<std::string> parseCamera(const std::vector<float>& camera, Options& options) {
  if (camera.empty()) return std::nullopt;
  std::array<float, 6> values{};
  std::copy(camera.begin(), camera.end(), values.begin());
  const bool finite = std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); });
  const double distance = glm::length(glm::dvec3(values[0], values[1], values[2]) - glm::dvec3(values[3], values[4], values[5]));
  if (!finite || !(distance >= kMinSceneSize && distance <= kMaxSceneSize))
    return fmt::format("--camera: eye and target must be finite and {:g} to {:g} apart (they are {:g} apart)",
                       kMinSceneSize, kMaxSceneSize, distance);
  options.camera = values;
  return std::nullopt;
}

// Options that contradict each other (rather than one being silently ignored).
std::optional<std::string> checkCombinations(const Options& options, const CLI::App& app) {
  const bool methodGiven = app.count("--method") > 0;
  if (!options.sdfFile.empty() && methodGiven && options.method == "mesh")
    return "--method mesh: a .hsdf file (--sdf) has no triangles; draw it with --method cells, trilinear or hermite";
  if (options.sideBySide && (!options.sdfFile.empty() || options.method == "mesh"))
    return "--side-by-side: needs a scene baked into an SDF (--method cells, trilinear or hermite, without --sdf)";
  if (options.resolution - 1 - 2 * options.padding < 1)
    return "--resolution " + std::to_string(options.resolution) + " leaves no cells inside --padding " +
           std::to_string(options.padding);
  return std::nullopt;
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
  std::optional<std::string> problem;
  if (!size.empty() && !parseSize(size, options.width, options.height))
    problem = "--size: '" + size + "' is not WxH with 1 <= W,H <= " + std::to_string(kMaxDimension);
  if (!problem && !options.screenshot.empty() && options.screenshot.extension() != ".png")
    problem = "--screenshot: '" + options.screenshot.string() + "' must end in .png";
  if (!problem) problem = parseCamera(camera, options);
  if (!problem) problem = checkCombinations(options, app);
  if (problem) {
    result.message = "scene_runner: " + *problem;
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
