// The renderer's depth pyramid (engine/render/depth_pyramid.h) and its occlusion-culling hook
// (RenderFeature::usesOcclusionCulling): what a culling pass reads must be the farthest depth of
// exactly the pixels each texel covers, or it culls visible things.
#include <algorithm>
#include <memory>

#include <gtest/gtest.h>

#include "engine/render/depth_pyramid.h"
#include "engine/render/render_feature.h"
#include "gpu_test_support.h"

namespace gputest {
namespace {

using namespace engine;

// A feature that asks for occlusion culling and draws nothing: the frames then build the pyramid
// from what the mesh feature drew; it records what the renderer handed it.
class OcclusionProbe final : public render::RenderFeature {
 public:
  std::string_view name() const override { return "occlusion probe"; }
  Status initialize(const gpu::Context&, const render::RendererFormats&, std::uint32_t) override { return {}; }
  void prepare(render::FrameContext&) override {}
  void recordPass(render::PassContext& pass) override {
    if (pass.pass == render::Pass::DepthPrepass && pass.occlusionLate) latePasses++;
  }
  bool usesOcclusionCulling() const override { return true; }
  void recordLateCulling(render::PassContext& pass, const render::DepthPyramidView& pyramid) override {
    EXPECT_EQ(pass.pass, render::Pass::DepthPrepass);
    EXPECT_FALSE(pass.occlusionLate);
    view = pyramid;
    lateCullings++;
  }
  render::DepthPyramidView view;
  int lateCullings = 0;
  int latePasses = 0;
};

class DepthPyramidTest : public GpuTest {
  bool useSynchronizationValidation() const override { return true; }
};

render::CameraView frontCamera(float distance, std::uint32_t w, std::uint32_t h) {
  return render::CameraView::lookAt({0.0f, 0.0f, distance}, {0.0f, 0.0f, 0.0f}, 0.8f, 0.1f, float(w) / float(h));
}

// The CPU reference: the minimum (reverse-Z: farthest) depth over the pixels [x 2^k, (x+1) 2^k)
// x [y 2^k, (y+1) 2^k) clipped to the frame.
float farthestOver(const Frame& frame, std::uint32_t level, std::uint32_t x, std::uint32_t y) {
  float farthest = 1.0f;
  const std::uint32_t side = 1u << level;
  for (std::uint32_t py = y * side; py < std::min((y + 1) * side, frame.height); ++py)
    for (std::uint32_t px = x * side; px < std::min((x + 1) * side, frame.width); ++px)
      farthest = std::min(farthest, frame.depthAt(px, py));
  return farthest;
}

// Why: every texel of every level must equal the CPU min-reduction of the depth pixels it covers
// (odd sizes included: a texel on the edge covers the pixels that exist); the features get the
// pyramid's address and size once per frame, and their phase-2 draws are asked for once.
TEST_F(DepthPyramidTest, EveryTexelIsTheFarthestDepthOfItsPixels) {
  constexpr std::uint32_t kWidth = 67, kHeight = 45;  // odd: every level has an edge texel
  createRenderer(kWidth, kHeight);
  auto probe = std::make_unique<OcclusionProbe>();
  OcclusionProbe* p = probe.get();
  ASSERT_TRUE(renderer_->addFeature(std::move(probe)).ok());
  addQuad({0.0f, 0.0f, 0.0f}, 1.3f, {1.0f, 0.0f, 0.0f, 1.0f});
  addQuad({0.35f, 0.25f, 0.8f}, 0.7f, {0.0f, 1.0f, 0.0f, 1.0f});
  const Frame frame = render(frontCamera(3.0f, kWidth, kHeight), 3);
  EXPECT_EQ(p->lateCullings, 3);
  EXPECT_EQ(p->latePasses, 3);
  const render::DepthPyramidView view = renderer_->depthPyramidView();
  EXPECT_EQ(p->view.address, view.address);
  EXPECT_NE(view.address, 0u);
  ASSERT_EQ(view.levels, render::DepthPyramid::levelCount({kWidth, kHeight}));
  EXPECT_EQ(view.levels, 8u);  // 67 -> 34 -> 17 -> 9 -> 5 -> 3 -> 2 -> 1: the larger side decides
  const std::vector<float> pyramid = renderer_->readbackDepthPyramid();
  ASSERT_EQ(pyramid.size(), render::DepthPyramid::levelOffset({kWidth, kHeight}, view.levels));
  int near = 0, far = 0;
  for (std::uint32_t level = 0; level < view.levels; ++level) {
    const VkExtent2D size = render::DepthPyramid::levelExtent({kWidth, kHeight}, level);
    const std::uint32_t offset = render::DepthPyramid::levelOffset({kWidth, kHeight}, level);
    for (std::uint32_t y = 0; y < size.height; ++y)
      for (std::uint32_t x = 0; x < size.width; ++x) {
        const float expected = farthestOver(frame, level, x, y);
        ASSERT_EQ(pyramid[offset + y * size.width + x], expected) << "level " << level << " texel " << x << ", " << y;
        (expected > 0.0f ? near : far)++;
      }
  }
  EXPECT_GT(near, 100) << "the quads cover texels of the pyramid";
  EXPECT_GT(far, 100) << "the background shows around them";
}

// Why: frames without a feature that asks for occlusion culling are recorded as before: no pyramid.
TEST_F(DepthPyramidTest, NoPyramidWithoutOcclusionCulling) {
  createRenderer(32, 32);
  addQuad({0.0f, 0.0f, 0.0f}, 1.0f, {1.0f, 0.0f, 0.0f, 1.0f});
  render(frontCamera(3.0f, 32, 32), 2);
  EXPECT_EQ(renderer_->depthPyramidView().levels, 0u);
  EXPECT_TRUE(renderer_->readbackDepthPyramid().empty());
}

}  // namespace
}  // namespace gputest
