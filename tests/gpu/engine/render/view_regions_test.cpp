// View regions of the renderer (engine/render/renderer.h, FrameSettings::regions): one frame, one
// camera, each rectangle drawn with its own override of the scene's components. Real pixels read
// back from lavapipe, validation on.
#include <gtest/gtest.h>

#include "engine/render/components.h"
#include "engine/scene/transform.h"
#include "gpu_test_support.h"

namespace gputest {
namespace {

using namespace engine;

constexpr std::uint32_t kWidth = 96, kHeight = 64;

render::CameraView frontCamera() {
  return render::CameraView::lookAt({0.0f, 0.0f, 3.0f}, {0.0f, 0.0f, 0.0f}, 0.8f, 0.1f, float(kWidth) / float(kHeight));
}

bool redDominant(glm::u8vec4 c) { return c.r > 2 * c.g && c.r > 2 * c.b; }
bool greenDominant(glm::u8vec4 c) { return c.g > 2 * c.r && c.g > 2 * c.b; }

class ViewRegionTest : public GpuTest {
 protected:
  Frame renderRegions(std::vector<render::ViewRegion> regions) {
    scene::updateWorldTransforms(registry_);
    render::FrameSettings settings;
    settings.regions = std::move(regions);
    renderer_->renderFrame(registry_, frontCamera(), settings);
    Frame frame;
    frame.width = kWidth;
    frame.height = kHeight;
    frame.rgba = renderer_->readbackColor();
    frame.depth = renderer_->readbackDepth();
    return frame;
  }
  // A region whose override paints the quad `color`.
  render::ViewRegion painted(VkRect2D rect, ecs::Entity quad, glm::vec4 color) {
    return {rect, [this, quad, color] { registry_.get<render::MeshRenderable>(quad).color = color; }};
  }
  bool useSynchronizationValidation() const override { return true; }
};

// Tricky: the override of each region must reach exactly its pixels (the frame slots keep the
// first region's objects alive while the second is prepared), the projection must be the whole
// frame's in both (depth equal to the frame without regions, pixel for pixel), and a gap between
// regions must stay background although the quad lies behind it (the first region clears the whole
// frame, every region's scissor clips its draws). Synchronization validation checks the barriers
// between the regions' passes.
TEST_F(ViewRegionTest, EachRegionDrawsItsOverrideWithTheFramesCamera) {
  createRenderer(kWidth, kHeight);
  const ecs::Entity quad = addQuad({0.0f, 0.0f, 0.0f}, 2.0f, {1.0f, 1.0f, 1.0f, 1.0f});
  const Frame whole = render(frontCamera());
  ASSERT_GT(whole.depthAt(48, 32), 0.0f);

  const Frame split = renderRegions({painted({{0, 0}, {40, kHeight}}, quad, {1.0f, 0.0f, 0.0f, 1.0f}),
                                     painted({{56, 0}, {kWidth - 56, kHeight}}, quad, {0.0f, 1.0f, 0.0f, 1.0f})});
  std::size_t red = 0, green = 0, coveredLeft = 0, coveredRight = 0;
  for (std::uint32_t y = 0; y < kHeight; ++y)
    for (std::uint32_t x = 0; x < kWidth; ++x) {
      if (x >= 40 && x < 56) {
        EXPECT_EQ(split.depthAt(x, y), 0.0f) << "gap pixel " << x << "," << y;
        EXPECT_EQ(split.pixel(x, y), whole.pixel(0, 0)) << "gap pixel " << x << "," << y << " is background";
        continue;
      }
      ASSERT_EQ(split.depthAt(x, y), whole.depthAt(x, y)) << "pixel " << x << "," << y;
      if (whole.depthAt(x, y) == 0.0f) continue;
      if (x < 40) {
        ++coveredLeft;
        red += redDominant(split.pixel(x, y)) ? 1 : 0;
      } else {
        ++coveredRight;
        green += greenDominant(split.pixel(x, y)) ? 1 : 0;
      }
    }
  // The quad spans the gap: both sides have covered pixels, all in their region's colour.
  EXPECT_GT(coveredLeft, 200u);
  EXPECT_GT(coveredRight, 200u);
  EXPECT_EQ(red, coveredLeft);
  EXPECT_EQ(green, coveredRight);
}

// Tricky: rectangles partly outside the frame are clipped (not a Vulkan error), empty ones are
// skipped (their override never runs), and regions past RendererDesc::maxViewRegions are not drawn
// (logged once) instead of overrunning the per-region frame slots.
TEST_F(ViewRegionTest, OutOfFrameEmptyAndSurplusRegions) {
  createRenderer(kWidth, kHeight);
  const ecs::Entity quad = addQuad({0.0f, 0.0f, 0.0f}, 2.0f, {1.0f, 1.0f, 1.0f, 1.0f});
  int applied = 0;
  std::vector<render::ViewRegion> regions;
  regions.push_back(painted({{-50, -50}, {1000, 1000}}, quad, {1.0f, 0.0f, 0.0f, 1.0f}));  // the whole frame
  regions.push_back({{{200, 0}, {10, 10}}, [&applied] { ++applied; }});                       // outside: empty
  for (int i = 0; i < 3; ++i) regions.push_back({{{0, 0}, {1, 1}}, [&applied] { applied += 10; }});
  const Frame frame = renderRegions(std::move(regions));
  EXPECT_EQ(applied, 20) << "the empty region is skipped; the 5th region (over the limit of 4) is not drawn";
  EXPECT_TRUE(redDominant(frame.pixel(48, 32)));
  for (int i = 0; i < 3; ++i) renderRegions({painted({{0, 0}, {48, kHeight}}, quad, {0.0f, 1.0f, 0.0f, 1.0f})});
  EXPECT_TRUE(greenDominant(renderRegions({painted({{0, 0}, {48, kHeight}}, quad, {0.0f, 1.0f, 0.0f, 1.0f})}).pixel(30, 32)));
}

}  // namespace
}  // namespace gputest
