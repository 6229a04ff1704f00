#include "runner_options.h"

#include <algorithm>
#include <cmath>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <glm/glm.hpp>

#include "options_common.h"
#include "tuning_fields.h"
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
  // The difference view compares two SDF methods' normals: with the mesh method the frame showed
  // the triangles alone, after baking both sides for nothing.
  if (options.tuning.difference && method == samples::Method::Mesh)
    return "--difference: compares the normals of two SDF methods; --method mesh draws triangles (pick an SDF "
           "method, or --split to show the mesh beside one)";
  if (auto valid = samples::validateTuning(options.tuning); !valid) return valid.error().message;
  return std::nullopt;
}

// A named setting's option (tuningNames): exactly its names, set through the table's parser.
CLI::Option* addNamedOption(CLI::App& app, const samples::TuningField& field, TuningState& t) {
  const std::vector<std::string> names = samples::tuningNames(field);
  const std::string list = fmt::format("{}", fmt::join(names, ", "));
  const CLI::Validator onlyNames(
      [names, list](std::string& text) -> std::string {
        if (std::find(names.begin(), names.end(), text) != names.end()) return {};
        return "'" + text + "' is not one of " + list;
      },
      "{" + list + "}");
  const auto set = [&field, &t](const std::string& text) {
    if (auto done = samples::setTuningFromText(field, text, t); !done) throw CLI::ValidationError(field.option, done.error().message);
  };
  return app.add_option_function<std::string>(field.option, set, samples::tuningHelp(field))->check(onlyNames);
}

// A number's option: its range (or its only values) from the table.
template <class T>
CLI::Option* addNumberOption(CLI::App& app, const samples::TuningField& field, T& value) {
  CLI::Option* option = app.add_option(field.option, value, samples::tuningHelp(field));
  if (!field.choices.empty())
    return option->check(CLI::IsMember(std::vector<std::uint32_t>(field.choices.begin(), field.choices.end())));
  return option->check(CLI::Range(field.zeroIsDerived ? T(0) : T(field.range.min), T(field.range.max)));
}

CLI::Option* addBoolOption(CLI::App& app, const samples::TuningField& field, bool& value) {
  const std::string help = samples::tuningHelp(field);
  switch (field.boolOption) {
    case samples::BoolOption::Flag: return app.add_flag(field.option, value, help);
    case samples::BoolOption::NegatedFlag: return app.add_flag(std::string("!") + field.option, value, help);
    case samples::BoolOption::Value: break;
  }
  return app.add_option(field.option, value, help);
}

// The option of one row of the tuning table (tuning_fields.h), by the kind of its member.
CLI::Option* addTuningOption(CLI::App& app, const samples::TuningField& field, TuningState& t) {
  if (samples::tuningKind(field) == samples::TuningKind::Name) return addNamedOption(app, field, t);
  return std::visit(
      [&](auto member) -> CLI::Option* {
        auto& value = t.*member;
        using T = std::remove_reference_t<decltype(value)>;
        if constexpr (std::is_same_v<T, bool>) return addBoolOption(app, field, value);
        else if constexpr (std::is_arithmetic_v<T>) return addNumberOption(app, field, value);
        else if constexpr (std::is_same_v<T, std::vector<std::string>>)
          return app.add_option(field.option, value, samples::tuningHelp(field))->delimiter(',');
        else return nullptr;  // a name: addNamedOption
      },
      field.member);
}

// Options that write the TuningState, one per row of the table. Defined after --settings, whose
// callback runs first, so that options given on the command line override the file.
void addTuningOptions(CLI::App& app, TuningState& t) {
  for (const samples::TuningField& field : samples::tuningFields()) addTuningOption(app, field, t);
  // The older spelling of --early-depth off, which scripts and docs still use.
  app.add_flag_callback(
         "--no-early-depth", [&t] { t.earlyDepth = samples::AutoSwitch::Off; },
         "cells: --early-depth off (every box runs its search)")
      ->excludes(app.get_option("--early-depth"));
}

ParseResult failure(const std::string& message) {
  return samples::stoppedWith<Options>(samples::parseError("scene_runner", message));
}

// --settings loads a file into the tuning (before the options that override it) and --save-settings
// writes the result.
void addSettingsFileOptions(CLI::App& app, Options& options) {
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
}

// What is drawn, where to (a window or offscreen) and for how many frames.
void addRunOptions(CLI::App& app, Options& options) {
  app.add_option("--scene", options.scene, "glTF/GLB scene to load")->check(CLI::ExistingFile);
  app.add_option("--sdf", options.sdfFile, "draw a .hsdf file baked by hsdf_bake (replaces the default scene; with --scene G, drawn among G's "
                 "triangle meshes, from G's cameras)")
      ->check(CLI::ExistingFile);
  app.add_flag("--headless", options.headless, "render offscreen without a window");
  samples::addSizeOption(app, options.width, options.height, "image size WxH (default 1280x720)");
  app.add_option("--frames", options.frames, "frames to render, then exit (0: until closed; headless default 1)")
      ->check(CLI::Range(0u, 1000000u));
  app.add_option("--screenshot", options.screenshot, "write the last frame to this PNG file");
  samples::addDeviceOption(app, options.device);
  app.add_flag("--validation", options.validation, "enable the Vulkan validation layers");
  app.add_flag("--ui", options.headlessUi, "draw the ImGui panels into headless screenshots");
  app.add_flag("!--no-ground", options.groundPlane, "do not add the ground plane");
}

// How the scene's meshes become objects, and the script that changes settings while running.
void addSceneOptions(CLI::App& app, Options& options) {
  app.add_flag("--side-by-side", options.sideBySide, "keep the mesh and place the SDF beside it");
  app.add_flag("--objects", options.objects,
               "each glTF mesh baked once into its own SDF, drawn at every node that places it (per node: "
               "extras hermite_sdf.draw, --node-draw, --triangle-nodes; its mesh's shell: extras hermite_sdf.shell, else --shell)");
  app.add_option("--animation", options.animation,
                 "the glTF animation played, by index or name, or 'none' (default: the first; played with --objects, "
                 "else drawn still at --animation-time)");
  app.add_option("--animation-time", options.animationTime,
                 "seconds into the animation at the first frame (looped; default 0); each frame moves it on by the "
                 "frame's time, 1/60 s headless")
      ->check(CLI::Range(0.0f, 1.0e6f));
  app.add_option("--script", options.script,
                 "apply 'frame N: key=value ...' lines (settings and actions, see the README) while running")
      ->check(CLI::ExistingFile);
}

// Memory budgets and the files kept across runs.
void addResourceOptions(CLI::App& app, Options& options) {
  app.add_option("--bake-budget-mib", options.bakeBudgetMiB, "refuse bakes needing more memory (MiB, default 4096)")
      ->check(CLI::Range(std::uint64_t(1), std::uint64_t(1) << 20));
  app.add_option("--gpu-budget-mib", options.gpuBudgetMiB,
                 "cap the GPU memory the renderer may allocate (MiB, default 0: no cap); past it the frame fails "
                 "with an error naming the resource")
      ->check(CLI::Range(std::uint64_t(0), std::uint64_t(1) << 30));
  app.add_option("--pipeline-cache", options.pipelineCache,
                 "keep compiled pipelines in this file across runs (read at start when made by this device and "
                 "driver, written at exit; default: not kept)");
  app.add_option("--ui-ini", options.uiIni, "ImGui window layout file (windowed default: imgui.ini; '' : none)");
}

// The first view: a fixed orbit view, an eye and target (`camera`, parseCamera) or a scene's camera.
void addCameraOptions(CLI::App& app, Options& options, std::vector<float>& camera) {
  CLI::Option* view = app.add_option("--view", options.view, "one of 8 fixed orbit views (0..7)")->check(CLI::Range(0, 7));
  CLI::Option* eye =
      app.add_option("--camera", camera, "eye and target: ex,ey,ez,tx,ty,tz")->delimiter(',')->expected(6);
  app.add_option("--scene-camera", options.sceneCamera,
                 "look through a camera of the glTF scene, given by its node's name, the camera's own name (the "
                 "first node showing it) or its index (its pose, yfov and znear; orbit or fly take over when the "
                 "camera is moved)")
      ->excludes(view)
      ->excludes(eye);
}

// Options that need another one, or that a .hsdf file (--sdf) cannot honour.
std::optional<std::string> checkDependencies(const CLI::App& app, const Options& options) {
  if (app.count("--scene-camera") > 0 && options.sceneCamera.empty())
    return "--scene-camera: needs a camera's node name, own name or index (it was empty)";
  if (!options.sceneCamera.empty() && options.scene.empty())
    return "--scene-camera: looks through a camera of a glTF scene; add --scene FILE";
  if (app.count("--animation") + app.count("--animation-time") > 0 && options.scene.empty())
    return "--animation / --animation-time: play a glTF scene's animation; add --scene FILE";
  if (!options.objects && app.count("--node-draw") + app.count("--triangle-nodes") > 0)
    return "--node-draw and --triangle-nodes choose per node of a scene loaded with --objects; add --objects";
  // A .hsdf file is drawn as it was baked: there is no source to bake again (both were ignored).
  if (!options.sdfFile.empty() && app.count("--resolution") + app.count("--padding") + app.count("--shell") > 0)
    return "--resolution / --padding / --shell: a .hsdf file (--sdf) is drawn as it was baked "
           "(hsdf_bake -r K --padding P --shell T makes another)";
  if (!options.sdfFile.empty() && options.tuning.lod)
    return "--lod: levels of detail bake the source again at K/2, K/4, ...; a .hsdf file (--sdf) has no source";
  return std::nullopt;
}

// The parsed options checked (and the camera read into them): the first problem, if any.
std::optional<std::string> checkOptions(const CLI::App& app, const std::vector<float>& camera, Options& options) {
  if (!options.screenshot.empty() && options.screenshot.extension() != ".png")
    return "--screenshot: '" + options.screenshot.string() + "' must end in .png";
  if (auto problem = parseCamera(camera, options)) return problem;
  if (auto problem = checkCombinations(options, app.count("--method") > 0)) return problem;
  return checkDependencies(app, options);
}

// The defaults that depend on other options.
void applyDefaults(const CLI::App& app, Options& options) {
  if (options.headless && options.frames == 0) options.frames = 1;
  if (!options.headless && app.count("--ui-ini") == 0) options.uiIni = "imgui.ini";
  if (options.scene.empty() && options.sdfFile.empty()) options.scene = samples::defaultScenePath();
  if (!options.sdfFile.empty() && options.tuning.method == samples::Method::Mesh) options.tuning.method = hsdf::RenderMethod::Cells;
}

}  // namespace

ParseResult parseOptions(int argc, const char* const* argv) {
  Options options;
  std::vector<float> camera;
  CLI::App app{"hermite_sdf scene runner: renders a glTF scene (default: the bundled bunny)", "scene_runner"};
  addSettingsFileOptions(app, options);
  addRunOptions(app, options);
  addTuningOptions(app, options.tuning);
  addSceneOptions(app, options);
  addResourceOptions(app, options);
  addCameraOptions(app, options, camera);

  if (auto stop = samples::parseCommandLine(app, "scene_runner", argc, argv)) return samples::stoppedWith<Options>(*stop);
  if (auto problem = checkOptions(app, camera, options)) return failure(*problem);
  applyDefaults(app, options);
  ParseResult result;
  result.options = options;
  return result;
}

}  // namespace runner
