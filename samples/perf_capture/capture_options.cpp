#include "capture_options.h"

#include <algorithm>
#include <cmath>
#include <regex>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "capture_rows.h"

namespace capture {
namespace {

const std::vector<std::string> kShapes{"torus", "sphere", "capsule", "box"};

// Comma-separated items, none empty.
std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    items.push_back(text.substr(start, comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return items;
}

// The cells' range (tuning.h; the dense tracers' rows stop at their own, capture_rows.cpp), from the
// smallest K that leaves a cell inside the rows' padding of 1 (K - 1 - 2 >= 1).
constexpr samples::IntRange kCaptureResolutions{4, samples::kResolutionRange.max};

std::optional<std::string> parseResolutions(const std::string& text, Options& options) {
  std::vector<int> values;
  for (const std::string& item : splitList(text)) {
    static const std::regex number(R"(\d{1,4})");
    const int k = std::regex_match(item, number) ? std::stoi(item) : -1;
    if (k < kCaptureResolutions.min || k > kCaptureResolutions.max)
      return fmt::format("--resolutions: '{}' is not a resolution K in {}..{} (e.g. --resolutions 16,32,64,128)", item,
                         kCaptureResolutions.min, kCaptureResolutions.max);
    if (std::find(values.begin(), values.end(), k) == values.end()) values.push_back(k);
  }
  std::sort(values.begin(), values.end());
  options.resolutions = values;
  return std::nullopt;
}

std::optional<std::string> parseMethods(const std::string& text, Options& options) {
  std::vector<std::string> methods;
  for (const std::string& item : splitList(text)) {
    if (!samples::parseMethod(item)) return "--methods: '" + item + "' is not one of " + samples::allMethodNames();
    if (std::find(methods.begin(), methods.end(), item) == methods.end()) methods.push_back(item);
  }
  options.methods = methods;
  return std::nullopt;
}

std::optional<std::string> parseSettings(const std::string& text, Options& options) {
  const std::vector<std::string> known = cellSettingNames();
  std::vector<std::string> settings;
  for (const std::string& item : splitList(text)) {
    if (std::find(known.begin(), known.end(), item) == known.end())
      return "--settings: '" + item + "' is not a setting of the cell methods (" + fmt::format("{}", fmt::join(known, ", ")) + ")";
    if (std::find(settings.begin(), settings.end(), item) == settings.end()) settings.push_back(item);
  }
  options.cellSettings = settings;
  return std::nullopt;
}

std::string joinArguments(int argc, const char* const* argv) {
  std::string line;
  for (int i = 0; i < argc; ++i) line += (i ? " " : "") + std::string(argv[i]);
  return line;
}

// The comma-separated lists as given, parsed once the command line is read (parseLists).
struct ListTexts {
  std::string resolutions;
  std::string methods;
  std::string settings;
};

// The options of the scene or shape drawn.
void addSourceOptions(CLI::App& app, Options& options) {
  auto* scene = app.add_option("--scene", options.scene, "glTF/GLB scene (default: the bundled bunny)")
                    ->check(CLI::ExistingFile);
  auto* shape = app.add_option("--shape", options.shape, "analytic shape instead of a scene: torus, sphere, capsule, box")
                    ->check(CLI::IsMember(kShapes));
  scene->excludes(shape);
  app.add_flag("--objects", options.objects,
               "each mesh of --scene its own SDF object (one bake per mesh, drawn at every node that places it; "
               "nodes marked as triangles in extras stay meshes)")
      ->excludes(shape);
}

// The options of the rows (methods x resolutions x settings) and of their image size.
void addRowOptions(CLI::App& app, Options& options, ListTexts& lists) {
  samples::addSizeOption(app, options.width, options.height, "image size WxH (default 1920x1080; --quick 320x180)");
  app.add_option("--resolutions", lists.resolutions, "field resolutions K (default 16,32,64,128; --quick 16,32)");
  app.add_option("--methods", lists.methods, "methods to capture (default mesh,trilinear,hermite,cells,cells-runs,cell-bricks)");
  app.add_option("--settings", lists.settings,
                 "only these settings of the cell methods, e.g. \"n=3 r=1,certified\" (default: every one; the "
                 "settings are those of the rows' labels)");
}

// The options of each row's views and frames, and of how long the capture may take. After
// addSourceOptions: the scene's cameras exclude --shape.
void addViewOptions(CLI::App& app, Options& options) {
  auto* views = app.add_option("--views", options.views, "orbit views 1..8 (default 8; --quick 2)")->check(CLI::Range(1u, 8u));
  app.add_option("--frames", options.frames, "timed frames per view 1..1000 (default 5; --quick 2)")
      ->check(CLI::Range(1u, 1000u));
  app.add_option("--warmup", options.warmup, "untimed frames per view before the timed ones 0..1000 (default 2; --quick 1)")
      ->check(CLI::Range(0u, 1000u));
  app.add_flag("--quick", options.quick, "small CI preset: 320x180, K 16,32, 2 views, 2 frames, 1 warm-up");
  app.add_flag("--lod", options.lod, "each cell row also with levels of detail on (rows labelled 'lod')");
  auto* distance =
      app.add_option("--distance", options.distance, "orbit views this many times farther than the framing (1..64, default 1)")
          ->check(CLI::Range(1.0f, 64.0f));
  app.add_option("--scene-cameras", options.sceneCameras,
                 "the views are these cameras of the --scene (glTF camera nodes, by name or index, comma-separated; "
                 "all: every perspective camera, in node order, skipping with a warning one that cannot be a camera, such as a "
                 "zero scale) instead of the orbit views")
      ->delimiter(',')
      ->excludes(views)
      ->excludes(distance)
      ->excludes(app.get_option("--shape"));
  app.add_option("--time-limit", options.timeLimitSeconds,
                 "no row starts after this many seconds (0: none, the default; the first row always runs): the "
                 "others are listed as not run (the exit code is non-zero) and every output is written")
      ->check(CLI::Range(0.0, 1e7));
}

// The preset first, then whatever was given explicitly overrides it.
void applyQuickPreset(const CLI::App& app, Options& options) {
  if (!options.quick) return;
  if (app.count("--size") == 0) {
    options.width = 320;
    options.height = 180;
  }
  options.resolutions = {16, 32};
  if (app.count("--views") == 0) options.views = 2;
  if (app.count("--frames") == 0) options.frames = 2;
  if (app.count("--warmup") == 0) options.warmup = 1;
}

// The lists into `options`, or what is wrong with one of them.
std::optional<std::string> parseLists(const CLI::App& app, const ListTexts& lists, Options& options) {
  // Given but empty (--resolutions ""): an error, not the default list run in its place.
  if (app.count("--resolutions") > 0 && lists.resolutions.empty())
    return "--resolutions: an empty list (e.g. --resolutions 16,32,64,128)";
  if (app.count("--methods") > 0 && lists.methods.empty()) return "--methods: an empty list (e.g. --methods cells,hermite)";
  std::optional<std::string> problem;
  if (!lists.resolutions.empty()) problem = parseResolutions(lists.resolutions, options);
  if (!problem && !lists.methods.empty()) problem = parseMethods(lists.methods, options);
  if (!problem && !lists.settings.empty()) problem = parseSettings(lists.settings, options);
  return problem;
}

// Options that contradict each other or name what cannot be captured.
std::optional<std::string> checkCombinations(const Options& options, bool methodsGiven) {
  if (!options.shape.empty() && std::find(options.methods.begin(), options.methods.end(), "mesh") != options.methods.end() &&
      methodsGiven)
    return "--methods mesh: an analytic --shape has no triangle mesh to draw";
  if (!options.sceneCameras.empty() && options.scene.empty())
    return "--scene-cameras: the views are a glTF scene's cameras; give the --scene that holds them";
  if (options.scene.extension() == ".hsdf")
    return "--scene: '" + options.scene.string() +
           "' is a baked .hsdf file; the capture re-bakes its source at every K and casts the ground truth from "
           "it: give the glTF (or --shape) it was baked from";
  if (std::filesystem::exists(options.out) && !std::filesystem::is_directory(options.out))
    return "--out: '" + options.out.string() + "' exists and is not a directory";
  return std::nullopt;
}

std::optional<std::string> checkOptions(const CLI::App& app, const ListTexts& lists, Options& options) {
  if (!std::isfinite(options.timeLimitSeconds))  // CLI::Range lets NaN through
    return "--time-limit: not a number of seconds in 0..1e7";
  if (auto problem = parseLists(app, lists, options)) return problem;
  return checkCombinations(options, !lists.methods.empty());
}

}  // namespace

ParseResult parseOptions(int argc, const char* const* argv) {
  Options options;
  ListTexts lists;
  CLI::App app{"hermite_sdf perf capture: the paper's results table (methods x resolutions) with quality and "
               "work metrics, written as CSV/JSON/Markdown/PNG",
               "perf_capture"};
  app.add_option("--out", options.out, "output folder (created)")->required();
  addSourceOptions(app, options);
  addRowOptions(app, options, lists);
  addViewOptions(app, options);
  samples::addDeviceOption(app, options.device);

  if (auto stop = samples::parseCommandLine(app, "perf_capture", argc, argv)) return samples::stoppedWith<Options>(*stop);
  applyQuickPreset(app, options);
  if (auto problem = checkOptions(app, lists, options))
    return samples::stoppedWith<Options>(samples::parseError("perf_capture", *problem));
  if (options.scene.empty() && options.shape.empty()) options.scene = samples::defaultScenePath();
  if (!options.shape.empty()) std::erase(options.methods, std::string("mesh"));  // no triangles to draw
  // Rows past a method's K range are left out (capture_rows.cpp); when that leaves none, the capture
  // opened its device and then blamed --methods, exit 1.
  if (buildRows(options).empty())
    return samples::stoppedWith<Options>(samples::parseError(
        "perf_capture", fmt::format("--resolutions / --methods: no row to capture: the sphere tracers (trilinear, "
                                    "hermite) draw K up to {}, the cell methods and the mesh any K",
                                    samples::kDenseResolutionRange.max)));
  options.commandLine = joinArguments(argc, argv);
  ParseResult result;
  result.options = options;
  return result;
}

}  // namespace capture
