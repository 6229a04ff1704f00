// The cell feature's pipelines (src/render/cell_pipelines.cpp): described when the feature is
// created, each compiled when a frame first draws with it (engine/gpu/lazy_pipeline.h).
#include <algorithm>
#include <memory>

#include <gtest/gtest.h>

#include "engine/gpu/vk_check.h"
#include "hermite_sdf/render/cell_feature.h"
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

}  // namespace
}  // namespace gputest
