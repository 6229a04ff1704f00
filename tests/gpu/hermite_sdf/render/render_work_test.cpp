// The renderer's measurement outputs the perf capture reads: per-pixel work counters
// (FrameSettings::countWork), pipeline-statistics queries per pass, and the float colour read-back,
// on lavapipe with the validation layers on.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "engine/gpu/pipeline_statistics.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/render/features.h"
#include "hermite_sdf/render/sphere_trace_feature.h"
#include "hermite/hermite_host_device.h"
#include "hermite_test_support.h"
#include "shared/host_device.h"

namespace gputest {
namespace {

using namespace engine;
using hsdf::RenderMethod;

constexpr std::uint32_t kSize = 96;

class RenderWorkTest : public GpuTest {
 protected:
  // A renderer with every SDF feature, optionally with a float colour target.
  void createSdfRenderer(VkFormat color = VK_FORMAT_R8G8B8A8_SRGB) {
    render::RendererDesc desc;
    desc.formats.color = color;
    renderer_ = std::make_unique<render::Renderer>(*context_, desc, VkExtent2D{kSize, kSize});
    const Status added = hsdf::addSceneFeatures(*renderer_, *pool_);
    ASSERT_TRUE(added.ok()) << added.error().message;
  }

  // The sphere (K = 16) seen from one side, filling the middle of the image: the image corners
  // lie outside the grid box's projection, so no fragment of any method runs there.
  render::CameraView sphereCamera() const {
    return render::CameraView::lookAt({0.7f, 0.9f, 6.2f}, {0.0f, 0.0f, 0.0f}, 0.8f, 0.05f, 1.0f);
  }

  void countFrame(const render::CameraView& camera, std::uint32_t debugView = 0) {
    render::FrameSettings settings;
    settings.debugView = debugView;
    settings.countWork = true;
    renderer_->renderFrame(registry_, camera, settings);
  }
};

// Tricky: the tracers' counters must agree with what they report through another channel. The
// visibility buffer's y of a sphere-traced pixel is the evaluation count of the fragment that won
// (one box front face per pixel, so the only fragment): the counters must hold exactly that where
// covered, count misses inside the box too (non-zero where uncovered but inside the box's
// projection is allowed), and stay 0 in the corners where nothing is drawn.
TEST_F(RenderWorkTest, SphereTracerStepsAreCountedPerPixel) {
  createSdfRenderer();
  auto asset = bakeAsset("sphere", 16);
  ASSERT_NE(asset, nullptr);
  for (RenderMethod method : {RenderMethod::TrilinearSphereTrace, RenderMethod::HermiteSphereTrace}) {
    registry_.clear();
    addSdf(registry_, asset, method);
    countFrame(sphereCamera());
    const auto counts = renderer_->readbackWorkCounters();
    const auto visibility = renderer_->readbackVisibility();
    ASSERT_EQ(counts.size(), std::size_t(kSize) * kSize);
    int covered = 0;
    for (std::size_t i = 0; i < counts.size(); ++i) {
      if (visibility[i].x == 0) continue;
      ++covered;
      ASSERT_EQ(counts[i], visibility[i].y & ~SPHERE_TRACE_STARTED_INSIDE) << hsdf::renderMethodName(method) << " pixel " << i;
      ASSERT_GT(counts[i], 0u);
    }
    EXPECT_GT(covered, int(kSize * kSize / 16)) << "the sphere should fill the middle of the image";
    for (std::size_t corner : {std::size_t(0), std::size_t(kSize - 1), std::size_t(kSize) * (kSize - 1),
                               std::size_t(kSize) * kSize - 1})
      EXPECT_EQ(counts[corner], 0u) << hsdf::renderMethodName(method) << " corner " << corner;
  }
}

// Tricky: the cells draw many box fragments per pixel and the counter sums all of them; a frame
// without countWork must not touch the counts of the last counting frame (the capture times frames
// with counting off and reads the counts of a separate frame).
TEST_F(RenderWorkTest, CellEvaluationsAreCountedAndKeptAcrossUncountedFrames) {
  createSdfRenderer();
  EXPECT_TRUE(renderer_->readbackWorkCounters().empty()) << "nothing counted yet";
  auto asset = bakeAsset("sphere", 16);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, RenderMethod::Cells);
  countFrame(sphereCamera());
  const auto counts = renderer_->readbackWorkCounters();
  const auto visibility = renderer_->readbackVisibility();
  ASSERT_EQ(counts.size(), std::size_t(kSize) * kSize);
  int covered = 0;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    if (visibility[i].x == 0) continue;
    ++covered;
    ASSERT_GT(counts[i], 0u) << "covered pixel " << i << " without evaluations";
  }
  EXPECT_GT(covered, int(kSize * kSize / 16));
  EXPECT_EQ(counts[0], 0u);
  EXPECT_EQ(counts.back(), 0u);

  registry_.clear();  // an uncounted frame of nothing
  renderer_->renderFrame(registry_, sphereCamera());
  EXPECT_EQ(renderer_->readbackWorkCounters(), counts);
}

// Tricky: statistics are per pass and must separate the passes. A quad (2 triangles) drawn by the
// mesh feature: the prepass assembles exactly 2 primitives and runs at least one fragment per
// covered pixel (helper invocations may add a few at the edges); an empty frame counts no
// fragments in the prepass. The query results arrive as named data, not log lines.
TEST_F(RenderWorkTest, PipelineStatisticsArePerPassAndMatchTheDrawnGeometry) {
  if (!context_->capabilities().pipelineStatistics) GTEST_SKIP() << "no pipelineStatisticsQuery on this device";
  createSdfRenderer();
  renderer_->renderFrame(registry_, sphereCamera());
  renderer_->finish();
  const auto* empty = gpu::findStatistics(renderer_->lastPipelineStatistics(), "depth prepass");
  ASSERT_NE(empty, nullptr);
  EXPECT_EQ(empty->fragmentShaderInvocations, 0u);
  EXPECT_EQ(empty->inputAssemblyPrimitives, 0u);

  addQuad({0.0f, 0.0f, 0.0f}, 1.0f, glm::vec4(1.0f));
  scene::updateWorldTransforms(registry_);
  const render::CameraView camera = render::CameraView::lookAt({0.0f, 0.0f, 2.0f}, {0.0f, 0.0f, 0.0f}, 0.8f, 0.05f, 1.0f);
  renderer_->renderFrame(registry_, camera);
  const auto depth = renderer_->readbackDepth();
  const auto covered = std::count_if(depth.begin(), depth.end(), [](float d) { return d > 0.0f; });
  ASSERT_GT(covered, 0);
  const auto& stats = renderer_->lastPipelineStatistics();
  const auto* prepass = gpu::findStatistics(stats, "depth prepass");
  const auto* opaque = gpu::findStatistics(stats, "opaque");
  ASSERT_NE(prepass, nullptr);
  ASSERT_NE(opaque, nullptr);
  EXPECT_EQ(prepass->inputAssemblyPrimitives, 2u);
  EXPECT_GE(prepass->vertexShaderInvocations, 4u);
  EXPECT_GE(prepass->fragmentShaderInvocations, std::uint64_t(covered));
  EXPECT_LE(prepass->fragmentShaderInvocations, std::uint64_t(2 * covered));
  EXPECT_EQ(opaque->inputAssemblyPrimitives, 2u);
}

// Tricky: the point of the float target is precision below 8 bits. Decoded normals (2c - 1) of a
// DEBUG_VIEW_NORMALS frame must be unit length to 1e-4 (8-bit sRGB is off by up to ~1e-2) and
// agree with the CPU reference's exact normals of the same interpolant. An 8-bit renderer refuses
// the float read-back by name.
TEST_F(RenderWorkTest, FloatColourReadbackGivesUnquantizedNormals) {
  createSdfRenderer();
  auto refused = renderer_->readbackColorFloat();
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("not a float format"), std::string::npos) << refused.error().message;

  createSdfRenderer(VK_FORMAT_R32G32B32A32_SFLOAT);
  auto asset = bakeAsset("sphere", 16);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, RenderMethod::Cells);
  const render::CameraView camera = sphereCamera();
  renderer_->renderFrame(registry_, camera, {DEBUG_VIEW_NORMALS});
  auto colour = renderer_->readbackColorFloat();
  ASSERT_TRUE(colour.ok()) << colour.error().message;
  const auto visibility = renderer_->readbackVisibility();
  auto reference = hsdf::renderReference(asset->field, camera.view, camera.proj, {int(kSize), int(kSize)},
                                         &asset->classification);
  ASSERT_TRUE(reference.ok()) << reference.error().message;
  double worstLength = 0.0;
  std::vector<double> angles;
  for (std::size_t i = 0; i < visibility.size(); ++i) {
    if (visibility[i].x == 0 || !reference->hit[i]) continue;
    const glm::dvec3 n = glm::dvec3(glm::vec3((*colour)[i])) * 2.0 - 1.0;
    worstLength = std::max(worstLength, std::abs(glm::length(n) - 1.0));
    const double c = std::clamp(glm::dot(glm::normalize(n), glm::dvec3(reference->normal[i])), -1.0, 1.0);
    angles.push_back(std::acos(c) * 180.0 / 3.14159265358979);
  }
  ASSERT_GT(angles.size(), std::size_t(kSize * kSize / 16));
  EXPECT_LT(worstLength, 1e-4);
  std::sort(angles.begin(), angles.end());
  EXPECT_LT(angles[angles.size() / 2], 0.05) << "median normal error against the reference, degrees";
}

}  // namespace
}  // namespace gputest
