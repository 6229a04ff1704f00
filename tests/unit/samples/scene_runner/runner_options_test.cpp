// The scene runner's command line (samples/scene_runner/runner_options.h): every option's good
// value reaches Options, every bad one is refused naming the option, --help, and --settings
// files merged under the command line. Each case says what it would catch.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "../common/tuning_table_values.h"
#include "engine/core/files.h"
#include "runner_options.h"

namespace runner {
namespace {

using samples::DebugView;
using samples::Method;

const std::string kBunny = std::string(HSDF_ASSET_DIR) + "/bunny.glb";
const std::string kHsdf = std::string(HSDF_TEST_DATA_DIR) + "/fuzz/hsdf_load_fuzz/sphere_k4_fp32.hsdf";

ParseResult parse(std::vector<std::string> args) {
  args.insert(args.begin(), "scene_runner");
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  return parseOptions(int(argv.size()), argv.data());
}

Options parseOk(const std::vector<std::string>& args) {
  const ParseResult result = parse(args);
  EXPECT_TRUE(result.options.has_value()) << result.message;
  return result.options.value_or(Options{});
}

std::filesystem::path tempFile(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("hsdf_runner_options_test_" + name);
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Tricky: the defaults are what scripts/run.sh shows; the bunny must be filled in only when
// neither --scene nor --sdf is given.
TEST(RunnerOptions, Defaults) {
  const Options o = parseOk({});
  EXPECT_EQ(o.scene, samples::defaultScenePath());
  EXPECT_FALSE(o.headless);
  EXPECT_EQ(o.frames, 0u);
  EXPECT_EQ(o.width, 1280u);
  EXPECT_EQ(o.height, 720u);
  EXPECT_EQ(o.device, engine::gpu::DevicePreference::Auto);
  EXPECT_TRUE(o.tuning == samples::TuningState{});
  // What a new user sees first is the paper's method, not the triangle mesh.
  EXPECT_EQ(o.tuning.method, hsdf::RenderMethod::Cells);
  EXPECT_TRUE(o.script.empty());
  EXPECT_EQ(o.uiIni, "imgui.ini") << "a window keeps its panel layout";
  EXPECT_TRUE(parseOk({"--headless"}).uiIni.empty()) << "headless runs write no ImGui layout";
  EXPECT_TRUE(o.groundPlane);
  EXPECT_FALSE(o.view.has_value());
  EXPECT_FALSE(o.camera.has_value());
}

// Tricky: every option, each set away from its default, so an option bound to the wrong field or
// a name table entry mapped to the wrong value shows up.
TEST(RunnerOptions, EveryOptionsGoodValue) {
  const Options o = parseOk({"--scene", kBunny, "--headless", "--size", "96x64", "--frames", "5", "--screenshot",
                             "out/x.png", "--device", "lavapipe", "--validation", "--ui", "--no-ground", "--method",
                             "trilinear", "--resolution", "32", "--padding", "2", "--subdivisions", "5", "--refine", "0",
                             "--fp16", "--normals", "central", "--debug-view", "evals", "--side-by-side",
                             "--no-front-to-back", "--no-early-depth", "--certified", "--view", "3", "--camera", "1,2,3,4,5,6", "--save-settings", "s.json",
                             "--script", kBunny, "--bake-budget-mib", "64", "--ui-ini", "layout.ini", "--split",
                             "horizontal", "--split-position", "0.25", "--compare-method", "hermite",
                             "--compare-resolution", "48", "--compare-normals", "exact", "--difference"});
  EXPECT_EQ(o.scene, kBunny);
  EXPECT_TRUE(o.headless);
  EXPECT_EQ(o.width, 96u);
  EXPECT_EQ(o.height, 64u);
  EXPECT_EQ(o.frames, 5u);
  EXPECT_EQ(o.screenshot, "out/x.png");
  EXPECT_EQ(o.device, engine::gpu::DevicePreference::Software);
  EXPECT_TRUE(o.validation);
  EXPECT_TRUE(o.headlessUi);
  EXPECT_FALSE(o.groundPlane);
  EXPECT_EQ(o.tuning.method, hsdf::RenderMethod::TrilinearSphereTrace);
  EXPECT_EQ(o.tuning.resolution, 32);
  EXPECT_EQ(o.tuning.padding, 2);
  EXPECT_EQ(o.tuning.subdivisions, 5u);
  EXPECT_EQ(o.tuning.refineSteps, 0u);
  EXPECT_TRUE(o.tuning.fp16);
  EXPECT_EQ(o.tuning.normals, hsdf::NormalMode::CentralDifferences);
  EXPECT_EQ(o.tuning.debugView, DebugView(DEBUG_VIEW_EVALS));
  EXPECT_TRUE(o.sideBySide);
  EXPECT_FALSE(o.tuning.frontToBack);
  EXPECT_EQ(o.tuning.earlyDepth, samples::AutoSwitch::Off);
  EXPECT_TRUE(o.tuning.certified);
  EXPECT_EQ(o.view, 3);
  ASSERT_TRUE(o.camera.has_value());
  EXPECT_EQ((*o.camera)[0], 1.0f);
  EXPECT_EQ((*o.camera)[5], 6.0f);
  EXPECT_EQ(o.saveSettings, "s.json");
  EXPECT_EQ(o.script, kBunny);  // parsed when the run starts; here only its existence is checked
  EXPECT_EQ(o.bakeBudgetMiB, 64u);
  EXPECT_EQ(o.uiIni, "layout.ini");
  EXPECT_EQ(o.tuning.split, samples::SplitMode::Horizontal);
  EXPECT_EQ(o.tuning.splitPosition, 0.25f);
  EXPECT_EQ(o.tuning.compareMethod, hsdf::RenderMethod::HermiteSphereTrace);
  EXPECT_EQ(o.tuning.compareResolution, 48);
  EXPECT_EQ(o.tuning.compareNormals, hsdf::NormalMode::Exact);
  EXPECT_TRUE(o.tuning.difference);
  EXPECT_EQ(parseOk({"--split", "vertical"}).tuning.split, samples::SplitMode::Vertical);
  EXPECT_EQ(parseOk({"--split", "off"}).tuning.split, samples::SplitMode::Off);
  EXPECT_EQ(parseOk({"--compare-method", "cells"}).tuning.compareMethod, hsdf::RenderMethod::Cells);

  // Every remaining name of the typed options.
  EXPECT_EQ(parseOk({"--method", "mesh"}).tuning.method, Method::Mesh);
  EXPECT_EQ(parseOk({"--method", "cells"}).tuning.method, hsdf::RenderMethod::Cells);
  EXPECT_EQ(parseOk({"--method", "hermite"}).tuning.method, hsdf::RenderMethod::HermiteSphereTrace);
  EXPECT_EQ(parseOk({"--normals", "exact"}).tuning.normals, hsdf::NormalMode::Exact);
  EXPECT_EQ(parseOk({"--device", "gpu"}).device, engine::gpu::DevicePreference::Hardware);
  EXPECT_EQ(parseOk({"--device", "auto"}).device, engine::gpu::DevicePreference::Auto);
  EXPECT_EQ(parseOk({"--debug-view", "none"}).tuning.debugView, DebugView(DEBUG_VIEW_NONE));
  EXPECT_EQ(parseOk({"--debug-view", "normals"}).tuning.debugView, DebugView(DEBUG_VIEW_NORMALS));
  EXPECT_EQ(parseOk({"--debug-view", "depth"}).tuning.debugView, DebugView(DEBUG_VIEW_DEPTH));
  EXPECT_EQ(parseOk({"--debug-view", "cells"}).tuning.debugView, DebugView(DEBUG_VIEW_CELLS));
  EXPECT_EQ(parseOk({"--debug-view", "wireframe"}).tuning.debugView, DebugView(DEBUG_VIEW_WIREFRAME));
  // Range ends are inclusive.
  EXPECT_EQ(parseOk({"--resolution", "2048"}).tuning.resolution, 2048);  // cells: the sparse bake's range
  EXPECT_EQ(parseOk({"--method", "trilinear", "--resolution", "512"}).tuning.resolution, 512);
  EXPECT_TRUE(parseOk({"--lod"}).tuning.lod);
  EXPECT_FALSE(parseOk({}).tuning.lod);
  EXPECT_EQ(parseOk({"--lod-pixels-per-cell", "64"}).tuning.lodPixelsPerCell, 64.0f);
  EXPECT_EQ(parseOk({"--subdivisions", "64"}).tuning.subdivisions, 64u);
  EXPECT_EQ(parseOk({"--tile-size", "4"}).tuning.tileSize, 4u);
  EXPECT_EQ(parseOk({"--size", "16384x1"}).width, 16384u);
  // The name or index is looked up once the scene is loaded (samples::Viewer::lookThroughSceneCamera).
  EXPECT_EQ(parseOk({"--scene", kBunny, "--scene-camera", "front"}).sceneCamera, "front");
  EXPECT_EQ(parseOk({"--scene", kBunny, "--animation", "swing"}).animation, "swing");
  EXPECT_EQ(parseOk({"--scene", kBunny, "--animation-time", "0.5"}).animationTime, 0.5f);
  EXPECT_EQ(parseOk({}).sceneCamera, "");
}

// Tricky: derived defaults: headless draws one frame; a .hsdf file alone replaces the bunny and
// is drawn with cells (it has no triangles).
TEST(RunnerOptions, DerivedDefaults) {
  EXPECT_EQ(parseOk({"--headless"}).frames, 1u);
  EXPECT_EQ(parseOk({"--headless", "--frames", "3"}).frames, 3u);
  const Options sdf = parseOk({"--sdf", kHsdf});
  EXPECT_TRUE(sdf.scene.empty());
  EXPECT_EQ(sdf.tuning.method, hsdf::RenderMethod::Cells);
  EXPECT_EQ(parseOk({"--sdf", kHsdf, "--method", "hermite"}).tuning.method, hsdf::RenderMethod::HermiteSphereTrace);
}

// Tricky: each message must name the option the user has to fix; CLI11's own errors and the
// runner's checks after parsing both count. Exit code 2 (usage), not 1 (run failure).
TEST(RunnerOptions, BadValuesNameTheOption) {
  struct Case {
    std::vector<std::string> args;
    const char* expected;
  };
  const std::vector<Case> cases = {
      {{"--size", "0x100"}, "--size: '0x100' is out of range: width and height must be 1..16384"},
      {{"--size", "100000x100000"}, "--size: '100000x100000' is out of range: width and height must be 1..16384"},
      {{"--size", "wide"}, "--size: 'wide' is not WxH"},
      {{"--frames", "-1"}, "--frames"},
      {{"--frames", "many"}, "--frames"},
      {{"--screenshot", "a.jpg"}, "--screenshot: 'a.jpg' must end in .png"},
      {{"--device", "vulkan"}, "--device: 'vulkan' is not one of auto, gpu, lavapipe"},
      {{"--method", "phong"}, "--method: 'phong' is not one of mesh, cells, trilinear, hermite"},
      // The enum's number would pass CLI11's own enum parsing: only names are accepted.
      {{"--method", "1"}, "--method: '1' is not one of"},
      {{"--resolution", "1"}, "--resolution"},
      {{"--resolution", "2049"}, "--resolution"},
      {{"--method", "hermite", "--resolution", "1024"}, "--resolution 1024 is outside 2..512 for --method hermite"},
      {{"--lod-pixels-per-cell", "0.1"}, "--lod-pixels-per-cell"},
      {{"--padding", "17"}, "--padding"},
      {{"--subdivisions", "0"}, "--subdivisions"},
      {{"--refine", "17"}, "--refine"},
      {{"--normals", "forward"}, "--normals: 'forward' is not one of exact, central"},
      {{"--debug-view", "shaded"}, "--debug-view: 'shaded' is not one of none, normals, depth, cells, evals, wireframe"},
      {{"--view", "8"}, "--view"},
      {{"--camera", "1,2,3"}, "--camera"},
      {{"--camera", "1,2,3,1,2,3"}, "--camera: eye and target must be finite and 1e-15 to 1e+15 apart (they are 0 apart)"},
      {{"--camera", "0,0,0,0,0,1e-30"}, "(they are 1e-30 apart)"},
      {{"--camera", "3e38,0,0,-3e38,0,0"}, "(they are 6e+38 apart)"},
      {{"--scene", "no_such_scene.glb"}, "--scene"},
      // A camera to look through needs a glTF scene holding it, and one camera placement, not two.
      {{"--scene-camera", "front"}, "--scene-camera: looks through a camera of a glTF scene; add --scene FILE"},
      {{"--animation", "0"}, "--animation / --animation-time: play a glTF scene's animation; add --scene FILE"},
      {{"--scene", kBunny, "--animation-time", "-1"}, "--animation-time"},
      {{"--scene", kBunny, "--scene-camera", ""}, "--scene-camera: needs a camera's node name, own name or index"},
      {{"--scene", kBunny, "--scene-camera", "front", "--view", "2"}, "excludes"},
      {{"--scene", kBunny, "--scene-camera", "front", "--camera", "1,2,3,4,5,6"}, "excludes"},
      {{"--sdf", "no_such_file.hsdf"}, "--sdf"},
      {{"--settings", "no_such_settings.json"}, "--settings"},
      {{"--resolution", "3", "--padding", "1"}, "--resolution 3 leaves no cells inside --padding 1"},
      // The K drawn is named, not the automatic compared K (2K) of a comparison nobody asked for.
      {{"--resolution", "16", "--padding", "16"}, "--resolution 16 leaves no cells inside --padding 16"},
      // The comparison is of one baked SDF: with --objects it drew nothing and the log said split.
      {{"--scene", kBunny, "--objects", "--split", "vertical"}, "--objects: the split screen and --difference"},
      {{"--scene", kBunny, "--objects", "--difference"}, "--objects: the split screen and --difference"},
      {{"--method", "mesh", "--side-by-side"}, "--side-by-side: needs a scene baked into an SDF"},
      // The frame was the mesh alone, exit 0, with both compared sides baked: the view asked for was never drawn.
      {{"--method", "mesh", "--difference"}, "--difference: compares the normals of two SDF methods; --method mesh"},
      {{"--script", "no_such_script.txt"}, "--script"},
      {{"--bake-budget-mib", "0"}, "--bake-budget-mib"},
      {{"--sdf", kHsdf, "--method", "mesh"}, "--method mesh: a .hsdf file (--sdf) has no triangles"},
      // A .hsdf file has no source to bake again: these were silently ignored.
      {{"--sdf", kHsdf, "--resolution", "16"}, "--resolution / --padding / --shell: a .hsdf file (--sdf) is drawn as"},
      {{"--sdf", kHsdf, "--padding", "2"}, "--resolution / --padding / --shell: a .hsdf file (--sdf) is drawn as"},
      {{"--sdf", kHsdf, "--shell", "0.1"}, "--resolution / --padding / --shell: a .hsdf file (--sdf) is drawn as"},
      {{"--sdf", kHsdf, "--lod"}, "--lod: levels of detail bake the source again"},
      {{"--no-such-option"}, "--no-such-option"},
      {{"--split", "diagonal"}, "--split: 'diagonal' is not one of off, vertical, horizontal"},
      {{"--split-position", "0.99"}, "--split-position"},
      {{"--compare-method", "mesh"}, "--compare-method: 'mesh' is not one of cells, trilinear, hermite"},
      {{"--compare-resolution", "600"}, "--compare-resolution 600 is outside 2..512"},
      {{"--compare-resolution", "3", "--padding", "1"}, "--compare-resolution 3 leaves no cells inside --padding 1"},
      {{"--compare-normals", "forward"}, "--compare-normals: 'forward' is not one of exact, central"},
      {{"--early-depth", "yes"}, "--early-depth: 'yes' is not one of auto, on, off"},
      {{"--early-depth", "on", "--no-early-depth"}, "excludes"},
      {{"--tile-size", "6"}, "--tile-size"},
  };
  for (const Case& c : cases) {
    const ParseResult result = parse(c.args);
    EXPECT_FALSE(result.options.has_value()) << c.args.front();
    EXPECT_EQ(result.exitCode, 2) << c.args.front();
    EXPECT_TRUE(contains(result.message, c.expected)) << "expected '" << c.expected << "' in: " << result.message;
  }
}

// Tricky: the early depth stage has three values; --no-early-depth (older scripts) must stay --early-depth
// off, and the default must be auto (the device decides), not on.
TEST(RunnerOptions, EarlyDepthModes) {
  EXPECT_EQ(parseOk({}).tuning.earlyDepth, samples::AutoSwitch::Auto);
  EXPECT_EQ(parseOk({"--no-early-depth"}).tuning.earlyDepth, samples::AutoSwitch::Off);
  EXPECT_EQ(parseOk({"--early-depth", "off"}).tuning.earlyDepth, samples::AutoSwitch::Off);
  EXPECT_EQ(parseOk({"--early-depth", "on"}).tuning.earlyDepth, samples::AutoSwitch::On);
  EXPECT_EQ(parseOk({"--early-depth", "auto"}).tuning.earlyDepth, samples::AutoSwitch::Auto);
}

// Tricky: --help is not an error (exit 0) and its text lists the options, new ones included.
TEST(RunnerOptions, Help) {
  const ParseResult result = parse({"--help"});
  EXPECT_FALSE(result.options.has_value());
  EXPECT_EQ(result.exitCode, 0);
  for (const char* option : {"--method", "--resolution", "--settings", "--save-settings", "--camera", "--debug-view",
                             "--script", "--bake-budget-mib", "--ui-ini", "--device", "--size"})
    EXPECT_TRUE(contains(result.message, option)) << option;
  // --scene-camera takes what Viewer::findSceneCamera takes: a camera's own name too, not only its
  // node's name or index.
  EXPECT_TRUE(contains(result.message, "the camera's own name")) << result.message;
  EXPECT_TRUE(contains(result.message, "Vulkan device: auto, gpu, lavapipe")) << result.message;
}

// Tricky: command line -> TuningState -> file -> --settings must give the same state (every field
// away from its default), and options given on the command line win over the file wherever they
// stand.
TEST(RunnerOptions, SettingsFileRoundTripAndOverride) {
  const samples::TuningState t =
      parseOk({"--method", "hermite", "--resolution", "48", "--padding", "2", "--subdivisions", "6", "--refine", "3",
               "--normals", "central", "--fp16", "--debug-view", "depth", "--no-front-to-back", "--no-early-depth", "--certified"})
          .tuning;
  EXPECT_FALSE(t == samples::TuningState{});
  const auto file = tempFile("round_trip.json");
  ASSERT_TRUE(samples::saveTuning(file, t).ok());
  EXPECT_TRUE(parseOk({"--settings", file.string()}).tuning == t);

  samples::TuningState overridden = t;
  overridden.resolution = 20;
  overridden.method = hsdf::RenderMethod::Cells;
  EXPECT_TRUE(parseOk({"--settings", file.string(), "--resolution", "20", "--method", "cells"}).tuning == overridden);
  EXPECT_TRUE(parseOk({"--resolution", "20", "--method", "cells", "--settings", file.string()}).tuning == overridden);
}

// Tricky: a bad value inside the file is reported as the file's problem (key and file named),
// through the same exit path as a bad option.
TEST(RunnerOptions, BadSettingsFileIsRefused) {
  const auto file = tempFile("bad.json");
  ASSERT_TRUE(engine::writeTextFile(file, R"({"subdivisions": 100})").ok());
  const ParseResult result = parse({"--settings", file.string()});
  EXPECT_FALSE(result.options.has_value());
  EXPECT_EQ(result.exitCode, 2);
  EXPECT_TRUE(contains(result.message, "--settings")) << result.message;
  EXPECT_TRUE(contains(result.message, file.string() + ": setting 'subdivisions': 100 is outside 1..64"))
      << result.message;
}

// Tricky: the mesh method may come from a settings file and the difference view from the command
// line (or the other way round): the check must see the merged tuning, not the options given.
TEST(RunnerOptions, DifferenceWithTheMeshMethodIsRefusedWhereverEachComesFrom) {
  const auto meshFile = tempFile("mesh_method.json");
  ASSERT_TRUE(engine::writeTextFile(meshFile, R"({"method": "mesh"})").ok());
  const auto differenceFile = tempFile("difference.json");
  ASSERT_TRUE(engine::writeTextFile(differenceFile, R"({"difference": true})").ok());
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"--settings", meshFile.string(), "--difference"}, {"--settings", differenceFile.string(), "--method", "mesh"}}) {
    const ParseResult result = parse(args);
    EXPECT_FALSE(result.options.has_value()) << args.back();
    EXPECT_EQ(result.exitCode, 2) << args.back();
    EXPECT_TRUE(contains(result.message, "--difference: compares the normals of two SDF methods")) << result.message;
  }
  // An SDF method from the file keeps the difference view: only the mesh has no SDF normals.
  EXPECT_TRUE(parseOk({"--settings", differenceFile.string(), "--method", "hermite"}).tuning.difference);
}

// Tricky: the per-node choice reaches the TuningState (the settings struct the panel and scripts
// write too), and choosing per node without --objects, or an unknown draw name, is refused.
TEST(RunnerOptions, SceneObjectsPerNodeChoice) {
  const Options o = parseOk({"--objects", "--node-draw", "triangles", "--triangle-nodes", "box_0_2,rock_1_1"});
  EXPECT_TRUE(o.objects);
  EXPECT_EQ(o.tuning.nodeDraw, hsdf::NodeDraw::Triangles);
  EXPECT_EQ(o.tuning.triangleNodes, (std::vector<std::string>{"box_0_2", "rock_1_1"}));
  EXPECT_FALSE(parseOk({}).objects);
  EXPECT_EQ(parseOk({}).tuning.nodeDraw, hsdf::NodeDraw::Sdf);

  const ParseResult without = parse({"--triangle-nodes", "box_0_2"});
  EXPECT_EQ(without.exitCode, 2);
  EXPECT_TRUE(contains(without.message, "add --objects")) << without.message;
  const ParseResult badName = parse({"--objects", "--node-draw", "mesh"});
  EXPECT_EQ(badName.exitCode, 2);
  EXPECT_TRUE(contains(badName.message, "'mesh' is not one of sdf, triangles")) << badName.message;
  const ParseResult withSdf = parse({"--objects", "--sdf", kHsdf});
  EXPECT_EQ(withSdf.exitCode, 2);
  EXPECT_TRUE(contains(withSdf.message, "--objects")) << withSdf.message;
}

// The command line of one row's value: its option (a flag alone for a flag's other value), after
// what the walk's base state needs (tuning_table_values.h) and, for the per-node choices, --objects.
std::vector<std::string> walkArgs(const samples::TuningField& field, const std::string& value) {
  std::vector<std::string> args;
  if (std::string_view(field.key) != "compare_method") args = {"--compare-method", "cells"};
  if (std::string_view(field.key) == "node_draw" || std::string_view(field.key) == "triangle_nodes")
    args.push_back("--objects");
  args.push_back(field.option);
  if (samples::tuningKind(field) != samples::TuningKind::Bool || field.boolOption == samples::BoolOption::Value)
    args.push_back(value);
  return args;
}

// Tricky: every row of the tuning table has an option, made from the row, that sets its member to
// the value given (and only a flag's other value for a flag); --help lists it with the range and
// default the row gives. The value is derived from the row: a new row is tested without an edit.
TEST(RunnerOptions, EveryTuningFieldHasAnOptionThatSetsIt) {
  const std::string help = parse({"--help"}).message;
  for (const samples::TuningField& field : samples::tuningFields()) {
    const samples::TuningState base = samples::testing::walkBase();
    const std::string value = samples::testing::otherValueText(field, base);
    const ParseResult result = parse(walkArgs(field, value));
    ASSERT_TRUE(result.options.has_value()) << field.option << " " << value << ": " << result.message;
    const samples::TuningState& t = result.options->tuning;
    EXPECT_FALSE(samples::sameTuningValue(field, t, base)) << field.option << " " << value << " did not set it";
    EXPECT_EQ(samples::tuningValueText(field, t), value) << field.option;
    EXPECT_TRUE(contains(help, field.option)) << field.option;
    EXPECT_TRUE(contains(help, samples::tuningHelp(field).substr(0, 30))) << field.option;
  }
}

// Tricky: every number's option refuses the values just past both ends of the row's range, and
// every named one a name it does not have, naming the option (the help's ranges are the ranges
// checked: --compare-resolution's help said 2..512 while 2048 passed).
TEST(RunnerOptions, EveryTuningFieldsOptionRefusesValuesOutsideItsRange) {
  for (const samples::TuningField& field : samples::tuningFields()) {
    std::vector<std::string> refused;
    if (samples::tuningKind(field) == samples::TuningKind::Number)
      refused = {samples::testing::belowRangeText(field), samples::testing::aboveRangeText(field)};
    if (samples::tuningKind(field) == samples::TuningKind::Name) refused = {"no-such-name"};
    for (const std::string& value : refused) {
      const ParseResult result = parse(walkArgs(field, value));
      EXPECT_FALSE(result.options.has_value()) << field.option << " " << value << " was taken";
      EXPECT_EQ(result.exitCode, 2) << field.option << " " << value;
      EXPECT_TRUE(contains(result.message, field.option)) << field.option << " " << value << ": " << result.message;
    }
  }
}

}  // namespace
}  // namespace runner
