// shader_stats: the shader compiler's statistics of every pipeline the engine and the module build
// (engine/gpu/shader_statistics.h), written as shader_stats.md and shader_stats.csv. It draws a
// few tiny headless frames through the samples' Viewer, one per method and form, so that the
// features create every pipeline they create lazily too; each pipeline is compiled again on the
// statistics device (by default RADV's null NAVI10 device: RADV_FORCE_FAMILY=navi10, see
// scripts/perf/shader_stats.sh) or read on the rendering device itself (--native). Compiler
// statistics, not timings.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "engine/core/log.h"
#include "engine/gpu/pipeline.h"
#include "options_common.h"
#include "report.h"
#include "viewer.h"

namespace {

using engine::Status;

struct Options {
  std::filesystem::path out = "out/shader_stats";
  std::string statisticsDevice = "NAVI10";
  bool native = false;
  engine::gpu::DevicePreference device = engine::gpu::DevicePreference::Auto;
  std::uint32_t width = 64;
  std::uint32_t height = 48;
  std::string commandLine;
};

samples::ParseResult<Options> parseOptions(int argc, char** argv) {
  Options options;
  CLI::App app{"shader_stats: the shader compiler's statistics (registers, spills, instructions, occupancy) of "
               "every pipeline, per stage, as shader_stats.md and shader_stats.csv. Not timings."};
  app.add_option("--out", options.out, "folder for shader_stats.md and shader_stats.csv (default out/shader_stats)");
  app.add_option("--statistics-device", options.statisticsDevice,
                 "compile every pipeline again on the device whose name holds this (default NAVI10: RADV's null "
                 "device, which needs RADV_FORCE_FAMILY=navi10)");
  app.add_flag("--native", options.native, "read the statistics on the rendering device instead "
                                           "(VK_KHR_pipeline_executable_properties)");
  samples::addDeviceOption(app, options.device);
  samples::addSizeOption(app, options.width, options.height, "the frames' size (default 64x48)");
  if (auto stop = samples::parseCommandLine(app, "shader_stats", argc, argv)) return samples::stoppedWith<Options>(*stop);
  // The driver variable that makes RADV's null device, as given: part of what ran.
  if (const char* family = std::getenv("RADV_FORCE_FAMILY"); family && *family)
    options.commandLine = "RADV_FORCE_FAMILY=" + std::string(family) + " ";
  options.commandLine += "shader_stats";
  for (int i = 1; i < argc; ++i) options.commandLine.append(" ").append(argv[i]);
  return {options, {}, 0};
}

// One tuning per method and form whose pipelines a feature creates only when a frame asks for them
// and Renderer::createAllPipelines() does not make (the depth pyramid, the brick culler, ...).
std::vector<samples::TuningState> tour() {
  using hsdf::AutoSwitch;
  using hsdf::RenderMethod;
  samples::TuningState cells;
  cells.resolution = 16;
  std::vector<samples::TuningState> tunings;
  const auto add = [&](auto change) {
    samples::TuningState tuning = cells;
    change(tuning);
    tunings.push_back(tuning);
  };
  add([](samples::TuningState&) {});
  add([](samples::TuningState& t) { t.tiles = AutoSwitch::On; });
  add([](samples::TuningState& t) { t.tiles = AutoSwitch::Off; t.thinBoxes = AutoSwitch::Off; t.earlyDepth = AutoSwitch::On; });
  add([](samples::TuningState& t) { t.tiles = AutoSwitch::Off; t.thinBoxes = AutoSwitch::On; t.earlyDepth = AutoSwitch::Off; });
  add([](samples::TuningState& t) { t.cullOcclusion = true; t.tiles = AutoSwitch::Off; t.fp16 = true; });  // occlusion: boxes only
  add([](samples::TuningState& t) { t.debugView = samples::DebugView(DEBUG_VIEW_WIREFRAME); });
  for (const RenderMethod method : {RenderMethod::CellRuns, RenderMethod::CellBricks, RenderMethod::TrilinearSphereTrace,
                                    RenderMethod::HermiteSphereTrace})
    add([&](samples::TuningState& t) { t.method = method; });
  add([](samples::TuningState& t) { t.method = samples::Method::Mesh; });
  return tunings;
}

Status drawTour(samples::Viewer& viewer) {
  for (const samples::TuningState& tuning : tour()) {
    ENGINE_TRY(viewer.checkTuning(tuning));
    viewer.setTuning(tuning);
    ENGINE_TRY(viewer.waitForBake());
    for (int frame = 0; frame < 2; ++frame) ENGINE_TRY(viewer.step());
  }
  return {};
}

Status writeFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream file(path, std::ios::binary);
  file << text;
  file.close();
  if (!file) return engine::makeError("cannot write " + path.string());
  return {};
}

Status run(const Options& options) {
  samples::ViewerDesc desc;
  desc.width = options.width;
  desc.height = options.height;
  desc.headless = true;
  desc.device = options.device;
  desc.shaderStatistics = options.native
                              ? engine::gpu::ShaderStatisticsDesc{engine::gpu::StatisticsTarget::Native, {}}
                              : engine::gpu::ShaderStatisticsDesc{engine::gpu::StatisticsTarget::Device, options.statisticsDevice};
  ENGINE_TRY_ASSIGN(std::unique_ptr<samples::Viewer> viewer, samples::Viewer::create(desc));
  samples::SceneDesc scene;
  scene.gltf = samples::defaultScenePath();
  scene.sideBySide = true;  // the bunny's triangles beside its SDF: the mesh pipelines draw too
  ENGINE_TRY(viewer->renderer().createAllPipelines());  // those no frame of the tour draws with too
  ENGINE_TRY(viewer->loadScene(scene, tour().front()));
  ENGINE_TRY(drawTour(*viewer));
  const engine::gpu::ShaderStatistics& statistics = *viewer->context().shaderStatistics();
  const std::vector<engine::gpu::StageStatistics> rows = statistics.stages();
  const char* commit = std::getenv("HSDF_COMMIT");
  const shader_stats::ReportHeader header{statistics.deviceName(), viewer->context().capabilities().deviceName,
                                          options.commandLine, commit && *commit ? commit : "unknown"};
  std::error_code ec;
  std::filesystem::create_directories(options.out, ec);
  ENGINE_TRY(writeFile(options.out / "shader_stats.csv", shader_stats::statisticsCsv(rows)));
  ENGINE_TRY(writeFile(options.out / "shader_stats.md",
                       shader_stats::statisticsMarkdown(rows, header, shader_stats::uncompiledShaders(rows, engine::gpu::shaderDirectory()))));
  std::printf("%zu pipeline stages from %s: %s\n", rows.size(), statistics.deviceName().c_str(),
              (options.out / "shader_stats.md").string().c_str());
  return viewer->close();
}

}  // namespace

int main(int argc, char** argv) {
  const samples::ParseResult<Options> parsed = parseOptions(argc, argv);
  if (!parsed.options) {
    std::fprintf(parsed.exitCode ? stderr : stdout, "%s\n", parsed.message.c_str());
    return parsed.exitCode;
  }
  try {
    if (const Status status = run(*parsed.options); !status) {
      std::fprintf(stderr, "shader_stats: error: %s\n", status.error().message.c_str());
      return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "shader_stats: fatal: %s\n", e.what());
    return 1;
  }
  return 0;
}
