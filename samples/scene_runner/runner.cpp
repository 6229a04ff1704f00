#include "runner.h"

#include <fmt/format.h>

#include "engine/core/log.h"
#include "hermite_sdf/render/cell_feature.h"
#include "script.h"
#include "viewer.h"

namespace runner {
namespace {

using namespace engine;

samples::ViewerDesc viewerDesc(const Options& options) {
  samples::ViewerDesc desc;
  desc.title = "hermite_sdf scene runner";
  desc.width = options.width;
  desc.height = options.height;
  desc.headless = options.headless;
  desc.validation = options.validation;
  desc.device = options.device;
  desc.headlessUi = options.headlessUi;
  desc.uiIniFile = options.uiIni;
  desc.pipelineCacheFile = options.pipelineCache;
  desc.bakeBudget.maxBytes = options.bakeBudgetMiB << 20;
  if (options.gpuBudgetMiB > 0) desc.gpuMemoryBudget = options.gpuBudgetMiB << 20;
  return desc;
}

samples::SceneDesc sceneDesc(const Options& options) {
  samples::SceneDesc scene;
  scene.gltf = options.scene;
  scene.sdfFile = options.sdfFile;
  scene.sideBySide = options.sideBySide;
  scene.objects = options.objects;
  scene.animation = options.animation;
  scene.animationTime = options.animationTime;
  scene.groundPlane = options.groundPlane;
  return scene;
}

Status createApp(const Options& options, std::unique_ptr<samples::Viewer>& viewer) {
  ENGINE_TRY_ASSIGN(viewer, samples::Viewer::create(viewerDesc(options)));
  ENGINE_TRY(viewer->loadScene(sceneDesc(options), options.tuning));
  // A run of a fixed number of frames (headless, screenshots) shows the comparison and the levels
  // of detail asked for, not the main asset standing in while they bake (a one-frame --lod
  // screenshot drew K, not the level its view picks).
  if (options.frames > 0 && (samples::comparing(options.tuning) || options.tuning.lod))
    ENGINE_TRY(viewer->waitForBake());
  if (options.view) viewer->setOrbitView(*options.view);
  if (options.camera) {
    const auto& c = *options.camera;
    viewer->setCamera(glm::dvec3(c[0], c[1], c[2]), glm::dvec3(c[3], c[4], c[5]));
  }
  if (!options.sceneCamera.empty())
    ENGINE_TRY(viewer->lookThroughSceneCamera(options.sceneCamera).withContext(options.scene.string()));
  return {};
}

// Failed steps in a row after which a windowed run gives up (a fault that repeats every frame).
constexpr int kMaxFailedStepsInARow = 10;

// A step's error. Headless (a batch job writing images): it ends the run. Windowed (a scene left
// open for hours): it is logged and the window goes on (a skipped frame shows the last finished
// one, an object that did not fit stays undrawn), unless the device is lost or the steps keep
// failing; the run still ends with the first error, so a scripted run cannot pass over it.
Status stepFailed(samples::Viewer& viewer, Status failed, int& failedInARow, Status& firstFailure) {
  if (!viewer.windowed() || viewer.deviceLost()) return failed;
  if (++failedInARow >= kMaxFailedStepsInARow)
    return makeError(fmt::format("{} ({} steps in a row failed: the window gives up)", failed.error().message,
                                 failedInARow));
  log::error("{} (the window goes on)", failed.error().message);
  if (firstFailure) firstFailure = failed;
  return {};
}

// What the last frame's root search cost, and whether any ray gave up: a tracer that runs out of
// steps draws a miss, which would otherwise go unseen: on an NVIDIA GPU, noise).
void logWork(samples::Viewer& viewer) {
  const Expected<samples::Viewer::FrameWork> work = viewer.countWork();
  if (!work) {
    log::warn("work: not counted: {}", work.error().message);
    return;
  }
  log::info("work: {} field evaluations, {} rays ran out of steps", work->evaluations, work->raysOutOfSteps);
  if (work->tileEntries > 0)
    log::info("tiles: {} drawn, {} list entries{}; the fragments read {} mask words and {} entries, and ray-box "
              "tested {}",
              work->tilesDrawn, work->tileEntries, work->tilesOverflowed ? " (past the limit: boxes drawn)" : "",
              work->tileMaskWordsRead, work->tileEntriesWalked, work->tileEntriesTested);
  if (work->raysOutOfSteps > 0)
    log::warn("{} sphere-tracing rays reached the step limit and were drawn as misses", work->raysOutOfSteps);
  if (const auto* cells = viewer.renderer().feature<hsdf::HermiteCellFeature>()) {
    const hsdf::HermiteCellFeature::Stats& stats = cells->stats();
    if (stats.objects + stats.culledObjects > 0)
      log::info("cell objects: {} drawn ({} cells), {} outside the view{}; held for culling: kept-cell streams "
                "{:.1f} MiB, tile lists {:.1f} MiB, occlusion history {:.1f} MiB",
                stats.objects, stats.cells, stats.culledObjects,
                stats.cullingRefused ? "; cell culling refused: every cell drawn" : "",
                double(stats.keptStreamBytesHeld) / (1024.0 * 1024.0),
                double(stats.tileListBytesHeld) / (1024.0 * 1024.0), double(stats.historyBytesHeld) / (1024.0 * 1024.0));
  }
}

// Windowed: until the window closes or --frames are drawn. Headless: --frames (default 1). A
// --script's commands run before the frame they name.
Status runFrames(const Options& options, const samples::Script& script, samples::Viewer& viewer) {
  // Script frames count steps: a minimised window's steps draw nothing (framesRendered() stays) but
  // the script goes on, so it can restore the window.
  auto next = script.frames.begin();
  Status firstFailure;
  int failedInARow = 0;
  std::uint64_t failedSteps = 0;
  for (std::uint64_t step = 0; !viewer.shouldClose() && (options.frames == 0 || viewer.framesRendered() < options.frames);
       ++step) {
    for (; next != script.frames.end() && next->frame <= step; ++next)
      ENGINE_TRY(samples::runScriptFrame(script, *next, viewer));
    if (Status stepped = viewer.step(); stepped) {
      failedInARow = 0;
    } else {
      ++failedSteps;
      ENGINE_TRY(stepFailed(viewer, std::move(stepped), failedInARow, firstFailure));
    }
  }
  viewer.renderer().finish();
  if (viewer.windowed())
    log::info("window: {} frames drawn, {} step(s) failed, swapchain recreated {} time(s)", viewer.framesRendered(),
              failedSteps, viewer.swapchainRecreations());
  for (const gpu::GpuTiming& t : viewer.renderer().lastTimings())
    log::info("GPU {:>14}: {:8.3f} ms", t.name, t.milliseconds);
  if (!options.screenshot.empty()) ENGINE_TRY(viewer.writeScreenshot(options.screenshot));
  logWork(viewer);
  if (!firstFailure)
    return makeError(fmt::format("{} step(s) failed and the window went on; the first: {}", failedSteps,
                                 firstFailure.error().message));
  return {};
}

}  // namespace

Status run(const Options& options) {
  // The script is read first: a bad line is refused before the device starts and the scene bakes.
  samples::Script script;
  if (!options.script.empty()) {
    ENGINE_TRY_ASSIGN(script, samples::loadScript(options.script).withContext("--script"));
  }
  std::unique_ptr<samples::Viewer> viewer;
  Status status = createApp(options, viewer);
  // The viewer's settings, as loaded: a .hsdf file's K is the one it was baked with.
  if (status && !options.saveSettings.empty())
    status = samples::saveTuning(options.saveSettings, viewer->tuning()).withContext("--save-settings");
  if (status) status = runFrames(options, script, *viewer);
  // Validation messages during teardown count too; both errors are told (a run the window went on
  // through still ends with an error, which must not hide validation messages).
  const Status closed = viewer ? viewer->close() : Status{};
  if (status) return closed;
  if (closed) return status;
  return makeError(status.error().message + "; closing: " + closed.error().message);
}

}  // namespace runner
