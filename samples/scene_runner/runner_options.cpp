#include "runner_options.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <glm/glm.hpp>

#include "options_common.h"
#include "viewer.h"

namespace runner {
namespace {

using samples::TuningState;

// Eye and target as given, or a message. Their distance is the orbit camera's radius, in float.
std::optional<std::string> parseCamera(const std::vector<float>& camera, Options& options) {
  if (camera.empty()) return std::nullopt;
  std::array<float, 6> values{};
  std::copy(camera.begin(), camera.end(), values.begin());
  const bool finite = std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); });
  const double distance = glm::length(glm::dvec3(values[0], values[1], values[2]) - glm::dvec3(values[3], values[4], values[5]));
  if (!finite || !(distance >= samples::kMinSceneSize && distance <= samples::kMaxSceneSize))
    return fmt::format("--camera: eye and target must be finite and {:g} to {:g} apart (they are {:g} apart)",
                       samples::kMinSceneSize, samples::kMaxSceneSize, distance);
  options.camera = values;
  return std::nullopt;
}

// Options that contradict each other (rather than one being silently ignored).
std::optional<std::string> checkCombinations(const Options& options, bool methodGiven) {
  const samples::Method method = options.tuning.method;
  if (!options.sdfFile.empty() && methodGiven && method == samples::Method::Mesh)
    return "--method mesh: a .hsdf file (--sdf) has no triangles; draw it with --method cells, trilinear or hermite";
  if (options.sideBySide && (!options.sdfFile.empty() || method == samples::Method::Mesh))
    return "--side-by-side: needs a scene baked into an SDF (--method cells, trilinear or hermite, without --sdf)";
  if (options.objects && (!options.sdfFile.empty() || options.sideBySide))
    return "--objects: draws a glTF scene's meshes as separate objects; it takes neither --sdf nor --side-by-side";
  // The comparison draws one baked SDF against another bake of it; --objects has one per mesh.
  if (options.objects && (options.tuning.split != samples::SplitMode::Off || options.tuning.difference))
    return "--objects: the split screen and --difference compare one baked SDF; not drawn with --objects";
  if (auto valid = samples::validateTuning(options.tuning); !valid) return valid.error().message;
  return std::nullopt;
}

// A transform for a named option: accepts exactly the names (not the numbers CLI11 would also take
// for an enum) and hands CLI11 the value of an enum, the name itself of a samples::Method (no enum:
// the option parses it); the error lists the names.
template <class T, class Values>
CLI::Validator namesOf(const Values& values, const char* (*name)(T)) {
  std::map<std::string, T> byName;
  std::string list;
  for (T v : values) {
    byName.emplace(name(v), v);
    list += (list.empty() ? "" : ", ") + std::string(name(v));
  }
  return CLI::Validator(
      [byName, list](std::string& text) -> std::string {
        const auto found = byName.find(text);
        if (found == byName.end()) return "'" + text + "' is not one of " + list;
        if constexpr (std::is_enum_v<T>) text = std::to_string(static_cast<std::underlying_type_t<T>>(found->second));
        return {};
      },
      "{" + list + "}");
}

template <class T>
CLI::Validator oneOf(std::initializer_list<T> values, const char* (*name)(T)) {
  return namesOf(values, name);
}

// --method, --compare-method: one of `methods`, by name.
template <class Values>
CLI::Option* addMethodOption(CLI::App& app, const char* option, samples::Method& out, const Values& methods,
                             const char* help) {
  return app
      .add_option_function<std::string>(
          option, [&out](const std::string& name) { out = *samples::parseMethod(name); }, help)
      ->transform(namesOf(methods, samples::methodName));
}

const char* deviceName(engine::gpu::DevicePreference device) {
  switch (device) {
    case engine::gpu::DevicePreference::Hardware: return "gpu";
    case engine::gpu::DevicePreference::Software: return "lavapipe";
    default: return "auto";
  }
}

// Options that write the TuningState. Defined after --settings, whose callback runs first, so that
// options given on the command line override the file.
void addTuningOptions(CLI::App& app, TuningState& t) {
  addMethodOption(app, "--method", t.method, samples::allMethods(),
                  "mesh, cells (Hermite cells; cells-runs, cell-bricks: fewer proxies), trilinear or hermite (sphere tracing)");
  app.add_option("--resolution", t.resolution,
                 "samples per axis K of the baked field (cells 2..2048, sparse bake past 256; trilinear, hermite 2..512)")
      ->check(CLI::Range(samples::kResolutionRange.min, samples::kResolutionRange.max));
  app.add_option("--padding", t.padding, "cells of padding around the mesh (0..16)")
      ->check(CLI::Range(samples::kPaddingRange.min, samples::kPaddingRange.max));
  app.add_option("--subdivisions", t.subdivisions, "equidistant evaluations per cell (1..64)")
      ->check(CLI::Range(samples::kSubdivisionsRange.min, samples::kSubdivisionsRange.max));
  app.add_option("--refine", t.refineSteps, "root refinement steps (0..16)")
      ->check(CLI::Range(samples::kRefineRange.min, samples::kRefineRange.max));
  app.add_flag("--fp16", t.fp16, "half-precision cell records / textures");
  app.add_option("--normals", t.normals, "exact or central (differences)")
      ->transform(oneOf({hsdf::NormalMode::Exact, hsdf::NormalMode::CentralDifferences}, samples::normalModeName));
  app.add_option("--debug-view", t.debugView, "none, normals, depth, cells, evals or wireframe")
      ->transform(namesOf(samples::allDebugViews(), samples::debugViewName));
  app.add_flag("!--no-front-to-back", t.frontToBack, "cells: submit in storage order, not front to back");
  auto* early = app.add_option("--early-depth", t.earlyDepth,
                                "cells: the early depth stage, boxes tested at their faces' depth: auto (default: on "
                                "for software rasterizers, off on GPUs), on or off")
                    ->transform(oneOf({samples::EarlyDepth::Auto, samples::EarlyDepth::On, samples::EarlyDepth::Off},
                                      samples::earlyDepthName));
  app.add_flag_callback(
         "--no-early-depth", [&t] { t.earlyDepth = samples::EarlyDepth::Off; },
         "cells: --early-depth off (every box runs its search)")
      ->excludes(early);
  app.add_flag("--certified", t.certified, "cells: certified root search (never misses the first root) instead of n samples");
  app.add_option("--cull-bricks", t.cullBricks, "cell bricks: GPU culling by frustum and normal cones (true, default, or false)");
  app.add_option("--cull-cells", t.cullCells, "cells: GPU culling of each cell by frustum and normal cone (true, default, or false)");
  app.add_option("--cull-occlusion", t.cullOcclusion,
                 "cells: two-phase occlusion culling of the cells against the depth pyramid (true, or false: default)");
  app.add_option("--proxy-boxes", t.proxyBoxes,
                 "cells, runs, bricks: draw and search each cell's part that can hold its surface (true, default), or "
                 "the whole cell, as the paper (false)");
  app.add_option("--thin-boxes", t.thinBoxes,
                 "cells: 12 bytes of varyings per box, records read by address: auto (default: on GPUs when cells "
                 "cover at most 8 pixels), on or off")
      ->transform(oneOf({samples::ThinBoxes::Auto, samples::ThinBoxes::On, samples::ThinBoxes::Off},
                        samples::earlyDepthName));
  app.add_option("--tiles", t.tiles,
                 "cells (with --cull-cells): the kept cells binned into screen tiles (--tile-size), each drawn as a "
                 "point where the device can, else a quad, whose fragments search the tile's cells, instead of a box "
                 "per cell: auto (default: on for software rasterizers), on or off")
      ->transform(oneOf({samples::TiledCells::Auto, samples::TiledCells::On, samples::TiledCells::Off},
                        samples::earlyDepthName));
  app.add_option("--tile-size", t.tileSize,
                 fmt::format("cells as tiles: the tiles' side in pixels, one of {} (default {}); smaller tiles list "
                             "fewer cells a pixel cannot see, but there are more of them to bin and draw",
                             fmt::join(samples::kTileSizes, ", "), TuningState{}.tileSize))
      ->check(CLI::IsMember(std::vector<std::uint32_t>(std::begin(samples::kTileSizes), std::end(samples::kTileSizes))));
  app.add_option("--split", t.split, "split-screen comparison: off, vertical or horizontal (divider)")
      ->transform(oneOf({samples::SplitMode::Off, samples::SplitMode::Vertical, samples::SplitMode::Horizontal},
                        samples::splitModeName));
  app.add_option("--split-position", t.splitPosition, "the divider as a fraction of the width/height (0.05..0.95)")
      ->check(CLI::Range(0.05f, 0.95f));
  addMethodOption(app, "--compare-method", t.compareMethod, hsdf::kRenderMethods,
                  "the compared side: trilinear (default), hermite or cells");
  // The check takes the widest range; validateTuning then the compared method's (its message names it).
  app.add_option("--compare-resolution", t.compareResolution,
                 fmt::format("K of the compared side ({}..{}, trilinear and hermite up to {}; default 0: 2K, at most {})",
                             samples::kResolutionRange.min, samples::kResolutionRange.max,
                             samples::kDenseResolutionRange.max, samples::kDefaultCompareResolutionMax))
      ->check(CLI::Range(0, samples::kResolutionRange.max));
  app.add_option("--compare-normals", t.compareNormals, "normals of the compared side: exact or central (default)")
      ->transform(oneOf({hsdf::NormalMode::Exact, hsdf::NormalMode::CentralDifferences}, samples::normalModeName));
  app.add_flag("--difference", t.difference, "difference view: normal angle between the two methods as a heat map");
  app.add_option("--node-draw", t.nodeDraw, "--objects: how nodes without an extras choice draw: sdf (default) or triangles")
      ->transform(oneOf({hsdf::NodeDraw::Sdf, hsdf::NodeDraw::Triangles}, hsdf::nodeDrawName));
  app.add_option("--triangle-nodes", t.triangleNodes, "--objects: names of nodes drawn as triangles (comma-separated)")
      ->delimiter(',');
  app.add_flag("--lod", t.lod, "levels of detail: bake K/2, K/4, ... too and draw each frame the level that fits the screen");
  app.add_option("--lod-pixels-per-cell", t.lodPixelsPerCell, "levels of detail: target cell size in pixels (0.25..64, default 2)")
      ->check(CLI::Range(samples::kLodPixelsPerCellRange.min, samples::kLodPixelsPerCellRange.max));
  app.add_option("--trace-epsilon", t.traceEpsilon, "sphere tracers: stop when |f| < this many grid spacings (1e-6..0.1, default 1e-4)")
      ->check(CLI::Range(samples::kTraceEpsilonRange.min, samples::kTraceEpsilonRange.max));
  app.add_option("--trace-max-steps", t.traceMaxSteps, "sphere tracers: field evaluations per ray before giving up (1..4096, default 1024)")
      ->check(CLI::Range(samples::kTraceMaxStepsRange.min, samples::kTraceMaxStepsRange.max));
  app.add_option("--central-difference-step", t.centralDifferenceStep,
                 "central-difference normals: step in grid spacings (0.01..1, default 0.5)")
      ->check(CLI::Range(samples::kCentralDifferenceStepRange.min, samples::kCentralDifferenceStepRange.max));
  app.add_option("--max-run-length", t.maxRunLength, "cells-runs: the most cells one run's box covers (1..64, default 8)")
      ->check(CLI::Range(samples::kMaxRunLengthRange.min, samples::kMaxRunLengthRange.max));
}

ParseResult failure(const std::string& message) {
  return samples::stoppedWith<Options>(samples::parseError("scene_runner", message));
}

}  // namespace

ParseResult parseOptions(int argc, const char* const* argv) {
  Options options;
  std::string size;
  CLI::App app{"hermite_sdf scene runner: renders a glTF scene (default: the bundled bunny)", "scene_runner"};
  app.add_option_function<std::string>(
         "--settings",
         [&options](const std::string& file) {
           auto loaded = samples::loadTuning(file, options.tuning);
           if (!loaded) throw CLI::ValidationError("--settings", loaded.error().message);
           options.tuning = *loaded;
         },
         "load method, resolution, ... from a JSON settings file (options given here override it)")
      ->check(CLI::ExistingFile);
  app.add_option("--save-settings", options.saveSettings, "write the resulting settings to this JSON file");
  app.add_option("--scene", options.scene, "glTF/GLB scene to load")->check(CLI::ExistingFile);
  app.add_option("--sdf", options.sdfFile, "draw a .hsdf file baked by hsdf_bake (replaces the default scene)")
      ->check(CLI::ExistingFile);
  app.add_flag("--headless", options.headless, "render offscreen without a window");
  app.add_option("--size", size, "image size WxH (default 1280x720)");
  app.add_option("--frames", options.frames, "frames to render, then exit (0: until closed; headless default 1)")
      ->check(CLI::Range(0u, 1000000u));
  app.add_option("--screenshot", options.screenshot, "write the last frame to this PNG file");
  using engine::gpu::DevicePreference;
  app.add_option("--device", options.device, "Vulkan device: auto, gpu or lavapipe")
      ->transform(oneOf({DevicePreference::Auto, DevicePreference::Hardware, DevicePreference::Software}, deviceName));
  app.add_flag("--validation", options.validation, "enable the Vulkan validation layers");
  app.add_flag("--ui", options.headlessUi, "draw the ImGui panels into headless screenshots");
  app.add_flag("!--no-ground", options.groundPlane, "do not add the ground plane");
  addTuningOptions(app, options.tuning);
  app.add_flag("--side-by-side", options.sideBySide, "keep the mesh and place the SDF beside it");
  app.add_flag("--objects", options.objects,
               "each glTF mesh baked once into its own SDF, drawn at every node that places it (per node: "
               "extras hermite_sdf.draw, --node-draw, --triangle-nodes)");
  app.add_option("--script", options.script,
                 "apply 'frame N: key=value ...' lines (settings and actions, see the README) while running")
      ->check(CLI::ExistingFile);
  app.add_option("--bake-budget-mib", options.bakeBudgetMiB, "refuse bakes needing more memory (MiB, default 4096)")
      ->check(CLI::Range(std::uint64_t(1), std::uint64_t(1) << 20));
  app.add_option("--gpu-budget-mib", options.gpuBudgetMiB,
                 "cap the GPU memory the renderer may allocate (MiB, default 0: no cap); past it the frame fails "
                 "with an error naming the resource")
      ->check(CLI::Range(std::uint64_t(0), std::uint64_t(1) << 30));
  app.add_option("--ui-ini", options.uiIni, "ImGui window layout file (windowed default: imgui.ini; '' : none)");
  CLI::Option* view = app.add_option("--view", options.view, "one of 8 fixed orbit views (0..7)")->check(CLI::Range(0, 7));
  std::vector<float> camera;
  CLI::Option* eye =
      app.add_option("--camera", camera, "eye and target: ex,ey,ez,tx,ty,tz")->delimiter(',')->expected(6);
  app.add_option("--scene-camera", options.sceneCamera,
                 "look through a camera node of the glTF scene, by name or index (its pose, yfov and znear; "
                 "orbit or fly take over when the camera is moved)")
      ->excludes(view)
      ->excludes(eye);

  if (auto stop = samples::parseCommandLine(app, "scene_runner", argc, argv)) return samples::stoppedWith<Options>(*stop);
  std::optional<std::string> problem;
  if (!size.empty()) problem = samples::parseSize(size, options.width, options.height);
  if (!problem && !options.screenshot.empty() && options.screenshot.extension() != ".png")
    problem = "--screenshot: '" + options.screenshot.string() + "' must end in .png";
  if (!problem) problem = parseCamera(camera, options);
  if (!problem) problem = checkCombinations(options, app.count("--method") > 0);
  if (!problem && app.count("--scene-camera") > 0 && options.sceneCamera.empty())
    problem = "--scene-camera: needs a camera's node name or index (it was empty)";
  if (!problem && !options.sceneCamera.empty() && options.scene.empty())
    problem = "--scene-camera: looks through a camera of a glTF scene; add --scene FILE";
  if (!problem && !options.objects && app.count("--node-draw") + app.count("--triangle-nodes") > 0)
    problem = "--node-draw and --triangle-nodes choose per node of a scene loaded with --objects; add --objects";
  // A .hsdf file is drawn as it was baked: there is no source to bake again (both were ignored).
  if (!problem && !options.sdfFile.empty() && app.count("--resolution") + app.count("--padding") > 0)
    problem = "--resolution / --padding: a .hsdf file (--sdf) is drawn at the K and padding it was baked with "
              "(hsdf_bake -r K --padding P makes another)";
  if (!problem && !options.sdfFile.empty() && options.tuning.lod)
    problem = "--lod: levels of detail bake the source again at K/2, K/4, ...; a .hsdf file (--sdf) has no source";
  if (problem) return failure(*problem);
  if (options.headless && options.frames == 0) options.frames = 1;
  if (!options.headless && app.count("--ui-ini") == 0) options.uiIni = "imgui.ini";
  if (options.scene.empty() && options.sdfFile.empty()) options.scene = samples::defaultScenePath();
  if (!options.sdfFile.empty() && options.tuning.method == samples::Method::Mesh) options.tuning.method = hsdf::RenderMethod::Cells;
  ParseResult result;
  result.options = options;
  return result;
}

}  // namespace runner
