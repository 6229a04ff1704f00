// The cell feature's pipelines (src/render/cell_pipelines.cpp): described when the feature is
// created, each compiled when a frame first draws with it (engine/gpu/lazy_pipeline.h).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "engine/gpu/vk_check.h"
#include "hermite_sdf/core/bake_job.h"
#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/render/features.h"
#include "cell_test_support.h"
#include "shared/host_device.h"
#include "hermite_test_support.h"

namespace gputest {
namespace {

using namespace engine;

std::size_t coveredPixels(const Frame& frame) {
  return std::size_t(std::count_if(frame.depth.begin(), frame.depth.end(), [](float d) { return d > 0.0f; }));
}

// Why: the feature has dozens of pipeline variants (per record precision, proxy form, counting,
// early depth, near cells, debug views) and compiling them all made every program that creates it
// wait seconds on lavapipe; a frame must compile the few it draws with, and compiling them all
// ahead (createAllPipelines, a load screen) must draw exactly the same image.
TEST_F(HermiteCellsTest, AFrameCompilesOnlyThePipelinesItDrawsWith) {
  createCellRenderer(kSize, kSize);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  const gpu::PipelineCounts atStart = feature->pipelineCounts();
  EXPECT_GE(atStart.described, 30u);
  EXPECT_EQ(atStart.compiled, 0u) << "compiled before any frame needed one";
  const auto asset = bakeAsset("torus", 24);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  const render::CameraView camera = orbitCamera(*asset, 0);
  const Frame lazy = renderWith(camera, DEBUG_VIEW_NONE);
  ASSERT_GT(coveredPixels(lazy), 500u);
  const gpu::PipelineCounts drawn = feature->pipelineCounts();
  EXPECT_GE(drawn.compiled, 2u) << "a prepass and the shading resolve at least";
  EXPECT_LE(drawn.compiled, 6u) << "one object in one form";

  ASSERT_TRUE(renderer_->createAllPipelines().ok());
  EXPECT_EQ(feature->pipelineCounts().compiled, atStart.described);
  const Frame prewarmed = renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_TRUE(prewarmed.depth == lazy.depth);
  EXPECT_TRUE(prewarmed.rgba == lazy.rgba);
}

// Why: compiling now happens inside a frame, between draws; a pipeline that cannot be compiled
// (here the driver refuses the first one, out of host memory) must skip its draws, keep the frame
// going with no validation message, and not be retried every frame, and a shader reload must
// describe it again so that the next frame draws.
TEST_F(HermiteCellsTest, APipelineThatCannotBeCompiledSkipsItsDrawsUntilAReload) {
  createCellRenderer(kSize, kSize);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  const auto asset = bakeAsset("torus", 24);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  const render::CameraView camera = orbitCamera(*asset, 0);
  gpu::injectFault({"vkCreateGraphicsPipelines", VK_ERROR_OUT_OF_HOST_MEMORY, 0});
  const Frame refused = renderWith(camera, DEBUG_VIEW_NONE);
  gpu::clearInjectedFaults();
  EXPECT_EQ(coveredPixels(refused), 0u) << "the prepass drew without its pipeline";
  const Frame next = renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_EQ(coveredPixels(next), 0u) << "the failed pipeline was compiled again";
  ASSERT_TRUE(feature->reloadShaders().ok());
  const Frame reloaded = renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_GT(coveredPixels(reloaded), 500u);
}

// Why: a switch of method in the tuning panel used to compile its pipelines inside the next frame
// (hundreds of milliseconds on lavapipe). Once the warmer (started by the second frame) is done,
// the frames after switches to bricks and to runs must compile nothing more, and draw the same
// pixels as a feature that never warmed and compiled them in the frame.
TEST_F(HermiteCellsTest, AMethodSwitchAfterWarmingCompilesNothingInTheFrame) {
  const auto asset = bakeAsset("torus", 24);
  ASSERT_NE(asset, nullptr);
  constexpr hsdf::RenderMethod kSwitches[] = {hsdf::RenderMethod::CellBricks, hsdf::RenderMethod::CellRuns};
  expectSwitchesAfterWarmingCompileNothing([&] { createCellRenderer(kSize, kSize); }, asset, orbitCamera(*asset, 0),
                                           hsdf::RenderMethod::Cells, kSwitches);
}

// Why: the cells warmed only from their own second frame, so a session whose objects were all
// traced (--method trilinear, the split screen's traced side) compiled the cells' pipelines in the
// frame that switched to them (100-250 ms on lavapipe, docs/perf/render-changes-session35.md). The
// cells must warm while only a tracer draws (the module's one rule, hsdf::hasSdfObjects), what a
// first frame of cells binds included (the resolve, the tiles); once that is done the switch frames
// to cells and to bricks compile nothing, and draw the pixels of features that never warmed.
TEST_F(HermiteCellsTest, ASwitchFromATracerToCellsAfterWarmingCompilesNothingInTheFrame) {
  const auto asset = bakeAsset("torus", 24);
  ASSERT_NE(asset, nullptr);
  constexpr hsdf::RenderMethod kSwitches[] = {hsdf::RenderMethod::Cells, hsdf::RenderMethod::CellBricks};
  const auto bothFeatures = [&] {
    createRenderer(kSize, kSize);
    const Status added = hsdf::addRenderFeatures(*renderer_);
    ASSERT_TRUE(added.ok()) << added.error().message;
  };
  const WarmedPipelines warmed = expectSwitchesAfterWarmingCompileNothing(
      bothFeatures, asset, orbitCamera(*asset, 0), hsdf::RenderMethod::TrilinearSphereTrace, kSwitches);
  EXPECT_GT(warmed.cells.compiled, 0u) << "the cells warmed nothing while the tracer drew";
}

// Why: one object alone draws its cells in the early depth stage, whose variants the warmer
// compiled; a second object that overlaps it on screen turns the stage off, and the frame that adds
// it draws every cell with the variants without the stage, which that frame compiled on the render
// thread (a large asset added beside a small one: most of that frame's time on lavapipe). Tricky:
// neither the method nor the precision changes, only which objects share pixels. Once the warmer
// is done, that frame must compile nothing, and draw the pixels of a feature that never warmed.
TEST_F(HermiteCellsTest, AnOverlappingObjectAddedAfterWarmingCompilesNothingInTheFrame) {
  const auto asset = bakeAsset("torus", 24);
  ASSERT_NE(asset, nullptr);
  const render::CameraView camera = orbitCamera(*asset, 0);
  const glm::mat4 overlapping = glm::translate(glm::mat4(1.0f), glm::vec3(0.5f, 0.3f, -0.5f));
  const auto frameOf = [&](bool warm) {
    createCellRenderer(kSize, kSize);
    registry_ = ecs::Registry();
    auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
    feature->settings().warmPipelines = warm;
    feature->settings().earlyDepth = hsdf::HermiteCellFeature::EarlyDepth::On;
    feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;  // a tiled frame has no early stage
    addSdf(registry_, asset, hsdf::RenderMethod::Cells);
    (void)renderWith(camera, DEBUG_VIEW_NONE);
    (void)renderWith(camera, DEBUG_VIEW_NONE);
    EXPECT_TRUE(feature->stats().earlyDepth) << "one object alone: the early stage";
    feature->waitForWarmPipelines();
    const std::uint32_t warmed = feature->pipelineCounts().compiled;
    addSdf(registry_, asset, hsdf::RenderMethod::Cells, overlapping);
    Frame added = renderWith(camera, DEBUG_VIEW_NONE);
    EXPECT_FALSE(feature->stats().earlyDepth) << "overlapping objects: no early stage";
    if (warm) {
      EXPECT_EQ(feature->pipelineCounts().compiled, warmed) << "the frame adding the object compiled a pipeline";
    } else {
      EXPECT_GT(feature->pipelineCounts().compiled, warmed) << "the frame should have compiled its own";
    }
    return added;
  };
  const Frame warmed = frameOf(true);
  const Frame cold = frameOf(false);
  EXPECT_GT(coveredPixels(warmed), 500u);
  EXPECT_TRUE(warmed.depth == cold.depth);
  EXPECT_TRUE(warmed.rgba == cold.rgba);
}

// Why: the worker compiles into the pipelines a reload replaces; the reload must stop it first (a
// worker left running would compile into moved-from pipelines: ThreadSanitizer sees that race,
// docs/reliability.md) and compile on the reloading thread only what the frames bound (the first
// frame compiled only that), not what the worker had warmed; the next frames warm the fresh set,
// the frame after a switch then still compiling nothing.
TEST_F(HermiteCellsTest, AReloadWhileWarmingWarmsTheFreshPipelines) {
  createCellRenderer(kSize, kSize);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  const auto asset = bakeAsset("torus", 24);
  ASSERT_NE(asset, nullptr);
  const ecs::Entity entity = addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  const render::CameraView camera = orbitCamera(*asset, 0);
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  const std::uint32_t bound = feature->pipelineCounts().compiled;
  (void)renderWith(camera, DEBUG_VIEW_NONE);  // the warmer starts here
  ASSERT_TRUE(feature->reloadShaders().ok());  // while it compiles
  EXPECT_EQ(feature->pipelineCounts().compiled, bound) << "the reload compiled more than the frames bind";
  const Frame before = renderWith(camera, DEBUG_VIEW_NONE);
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  feature->waitForWarmPipelines();
  const std::uint32_t warmed = feature->pipelineCounts().compiled;
  registry_.get<hsdf::HermiteSdfRenderable>(entity).method = hsdf::RenderMethod::CellBricks;
  const Frame bricks = renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_EQ(feature->pipelineCounts().compiled, warmed);
  EXPECT_GT(coveredPixels(before), 500u);
  EXPECT_GT(coveredPixels(bricks), 500u);
}

// Not a check, a measurement (docs/perf/render-changes-session34.md): the render-thread time of the
// frames that switch the bunny (K = 128, culled cells, tiles off) to bricks, to runs and back to
// cells, each followed by a frame of the same form, without and with the warmer; and the time the
// warmer took after the second frame (waited for, as a user's seconds before a switch would be).
// Run by hand:
//   hermite_cells_gpu_tests --gtest_also_run_disabled_tests --gtest_filter='*SwitchFrameTimes'
TEST_F(HermiteCellsTest, DISABLED_SwitchFrameTimes) {
  auto source = hsdf::BakeSource::fromPathOrShape(sampleAsset("bunny.glb").string());
  ASSERT_TRUE(source.ok());
  hsdf::BakeSettings bake;
  bake.resolution = 128;
  bake.band = hsdf::BakeBand::Sparse;
  hsdf::BakeJob job(std::move(*source), bake);
  hsdf::BakeJob::Result asset = job.wait();
  ASSERT_TRUE(asset.ok()) << asset.error().message;
  const render::CameraView camera = orbitCamera(**asset, 0);
  const auto milliseconds = [&] {
    const auto start = std::chrono::steady_clock::now();
    EXPECT_TRUE(renderer_->renderFrame(registry_, camera, render::FrameSettings{}));
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    (void)renderer_->readbackDepth();
    return ms;
  };
  for (const bool warm : {false, true}) {
    createCellRenderer(kSize, kSize);
    registry_ = ecs::Registry();
    auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
    feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;
    feature->settings().warmPipelines = warm;
    const ecs::Entity entity = addSdf(registry_, *asset, hsdf::RenderMethod::Cells);
    const double first = milliseconds();
    const double second = milliseconds();
    const auto start = std::chrono::steady_clock::now();
    feature->waitForWarmPipelines();
    const double wait = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    std::printf("[ warm %-3s ] first frame %7.1f ms, second %6.1f ms, warmer done %7.1f ms later\n", warm ? "on" : "off",
                first, second, wait);
    for (const hsdf::RenderMethod method :
         {hsdf::RenderMethod::CellBricks, hsdf::RenderMethod::CellRuns, hsdf::RenderMethod::Cells}) {
      registry_.get<hsdf::HermiteSdfRenderable>(entity).method = method;
      const double switched = milliseconds();
      const double next = milliseconds();
      std::printf("[ warm %-3s ] switch to %-6s frame %7.1f ms, next frame %6.1f ms\n", warm ? "on" : "off",
                  method == hsdf::RenderMethod::CellBricks ? "bricks" : method == hsdf::RenderMethod::CellRuns ? "runs" : "cells",
                  switched, next);
    }
  }
}

}  // namespace
}  // namespace gputest
