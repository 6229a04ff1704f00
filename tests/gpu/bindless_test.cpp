// The sphere tracers' descriptor-indexing ("bindless") path (SphereTraceFeature, Options::
// allowBindless): one array of field textures indexed per draw, one bind and one instanced draw per
// pass and method. Chosen wherever the device has descriptor indexing (Context::capabilities());
// lavapipe has not, so on CI these tests are reported as skipped (ctest: SKIP_REGULAR_EXPRESSION),
// and they run on any device that has it (HSDF_TEST_DEVICE=gpu). What they check there:
// - the bindless frame equals the per-texture-set frame of the same scene on the same device
//   (several objects, assets, both methods, fp32 and fp16 textures in one frame: a draw that read
//   another object's slot would draw another shape);
// - the bindless frame matches the CPU reference of each method's interpolant;
// - a slot freed by a released texture and reused by a new one shows the new texture.
// Only the choice itself runs everywhere: bindless exactly where the device has the feature.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "device_tolerances.h"
#include "engine/core/math.h"
#include "engine/render/renderer.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/core/reference.h"
#include "hermite_sdf/render/sphere_trace_feature.h"
#include "hermite_test_support.h"
#include "shared/host_device.h"

namespace gputest {
namespace {

using namespace engine;
using hsdf::RenderMethod;

constexpr std::uint32_t kSize = 192;

render::CameraView orbitCamera(const glm::vec3& center, float radius, int view) {
  const float yaw = 0.4f + float(view) * 1.57f;
  const float pitch = (view % 2 == 0) ? 0.35f : -0.5f;
  return render::CameraView::lookAt(math::orbitEye(center, 1.9f * radius, yaw, pitch), center, 0.9f, 0.01f * radius,
                                    1.0f);
}

struct FrameDifference {
  int coverage = 0;           // one frame hit, the other missed
  double depthRelative = 0.0; // largest |a - b| / max(a, b) over pixels both hit
  int covered = 0;            // pixels both hit
};

FrameDifference difference(const Frame& a, const Frame& b) {
  FrameDifference d;
  for (std::size_t i = 0; i < a.depth.size(); ++i) {
    const bool hitA = a.depth[i] > 0.0f, hitB = b.depth[i] > 0.0f;
    if (hitA != hitB) {
      ++d.coverage;
      continue;
    }
    if (!hitA) continue;
    ++d.covered;
    d.depthRelative = std::max(d.depthRelative, double(std::abs(a.depth[i] - b.depth[i])) /
                                                    double(std::max(a.depth[i], b.depth[i])));
  }
  return d;
}

// Ends the test as skipped, naming the device, where the bindless path cannot run.
#define SKIP_WITHOUT_DESCRIPTOR_INDEXING()                                                              \
  if (!context_->capabilities().descriptorIndexing)                                                     \
  GTEST_SKIP() << context_->capabilities().deviceName                                                   \
               << " has no descriptor indexing (runtime arrays, non-uniform sampled-image indexing): "  \
                  "the bindless path cannot run here"

class BindlessTest : public GpuTest {
 protected:
  void TearDown() override {
    perTextureSets_.reset();  // before the context the base class checks and destroys
    GpuTest::TearDown();
  }

  static std::unique_ptr<render::Renderer> traceRenderer(const gpu::Context& context, bool allowBindless) {
    auto renderer = std::make_unique<render::Renderer>(context, render::RendererDesc{}, VkExtent2D{kSize, kSize});
    hsdf::SphereTraceFeature::Options options;
    options.allowBindless = allowBindless;
    // The tracer alone, with the bindless switch under test (the cells have no such option).
    const Status added = renderer->addFeature(std::make_unique<hsdf::SphereTraceFeature>(options));
    EXPECT_TRUE(added.ok()) << added.error().message;
    return added.ok() ? std::move(renderer) : nullptr;
  }

  // renderer_ draws bindless (the default options), perTextureSets_ the same registry without.
  void createBothRenderers() {
    renderer_ = traceRenderer(*context_, true);
    ASSERT_NE(renderer_, nullptr);
    perTextureSets_ = traceRenderer(*context_, false);
    ASSERT_NE(perTextureSets_, nullptr);
    ASSERT_TRUE(stats(*renderer_).bindless) << "the device has descriptor indexing: the default must use it";
    ASSERT_FALSE(stats(*perTextureSets_).bindless) << "allowBindless = false must use per-texture sets";
  }

  static const hsdf::SphereTraceFeature::Stats& stats(render::Renderer& renderer) {
    return renderer.feature<hsdf::SphereTraceFeature>()->stats();
  }

  Frame draw(render::Renderer& renderer, const render::CameraView& camera, std::uint32_t debugView) {
    render::FrameSettings settings;
    settings.debugView = debugView;
    renderer.renderFrame(registry_, camera, settings);
    Frame frame;
    frame.width = renderer.extent().width;
    frame.height = renderer.extent().height;
    frame.rgba = renderer.readbackColor();
    frame.depth = renderer.readbackDepth();
    return frame;
  }

  // Draws the registry with both paths and expects the same image (see DeviceTolerances).
  void expectPathsAgree(const render::CameraView& camera, const std::string& label, int minCovered) {
    SCOPED_TRACE(label);
    const DeviceTolerances tolerance = tolerancesFor(*context_);
    for (const std::uint32_t view : {std::uint32_t(DEBUG_VIEW_NONE), std::uint32_t(DEBUG_VIEW_NORMALS)}) {
      const Frame bindless = draw(*renderer_, camera, view);
      const Frame sets = draw(*perTextureSets_, camera, view);
      const FrameDifference d = difference(bindless, sets);
      int colourDiffers = 0;
      for (std::size_t i = 0; i < bindless.depth.size(); ++i) {
        if (bindless.depth[i] <= 0.0f || sets.depth[i] <= 0.0f) continue;
        for (int c = 0; c < 3; ++c)
          if (std::abs(int(bindless.rgba[i * 4 + c]) - int(sets.rgba[i * 4 + c])) > 1) {
            ++colourDiffers;
            break;
          }
      }
      std::printf("[ %s, debug view %u ] covered %d, coverage differs %d, colour differs %d, depth rel %.2e\n",
                  label.c_str(), view, d.covered, d.coverage, colourDiffers, d.depthRelative);
      EXPECT_GT(d.covered, minCovered) << "too little surface in view for the comparison to mean anything";
      EXPECT_LE(d.coverage, tolerance.samePathCoverage * double(kSize * kSize));
      EXPECT_LE(colourDiffers, tolerance.samePathCoverage * double(kSize * kSize));
      EXPECT_LE(d.depthRelative, tolerance.samePathDepthRelative);
    }
  }

  std::unique_ptr<render::Renderer> perTextureSets_;
};

// Why: the choice must follow the device, not a build flag: bindless where descriptor indexing
// exists (unless refused by the options), per-texture sets elsewhere -- lavapipe included, where
// this is what keeps the tracers drawing at all. Runs on every device.
TEST_F(BindlessTest, BindlessIsChosenExactlyWhereTheDeviceHasDescriptorIndexing) {
  const bool has = context_->capabilities().descriptorIndexing;
  const auto asset = bakeAsset("sphere", 8);
  ASSERT_NE(asset, nullptr);
  addTracedSdf(registry_, asset, RenderMethod::HermiteSphereTrace);
  for (const bool allow : {true, false}) {
    renderer_ = traceRenderer(*context_, allow);
    ASSERT_NE(renderer_, nullptr);
    const Frame frame = draw(*renderer_, orbitCamera(glm::vec3(0.0f), 1.0f, 0), DEBUG_VIEW_NONE);
    EXPECT_EQ(stats(*renderer_).bindless, allow && has)
        << context_->capabilities().deviceName << (has ? " has" : " lacks") << " descriptor indexing";
    EXPECT_GT(std::count_if(frame.depth.begin(), frame.depth.end(), [](float d) { return d > 0.0f; }), 1000)
        << "the chosen path draws";
  }
}

// Why: the bindless path indexes one texture array with each draw's slot (SphereTraceDraw::
// texture, nonuniformEXT); a wrong index, a missing nonuniform qualifier (undefined across a
// subgroup drawing several objects) or a slot written with the wrong view draws another object's
// field. Six objects of three shapes, both methods, fp32 and fp16 textures, in one frame: each
// pixel must match the per-texture-set path, which binds each object's own set.
TEST_F(BindlessTest, ManyObjectsMatchThePerTextureSetPath) {
  SKIP_WITHOUT_DESCRIPTOR_INDEXING();
  createBothRenderers();
  const char* shapes[] = {"sphere", "torus", "box"};
  const int resolutions[] = {12, 16, 10};
  int placed = 0;
  for (int s = 0; s < 3; ++s) {
    const auto asset = bakeAsset(shapes[s], resolutions[s]);
    ASSERT_NE(asset, nullptr);
    for (const RenderMethod method : {RenderMethod::TrilinearSphereTrace, RenderMethod::HermiteSphereTrace}) {
      // A 3 x 2 grid of objects 2.6 units apart (each fits in about 2.4), fp16 on every other one.
      const glm::vec3 at(2.6f * float(s - 1), method == RenderMethod::TrilinearSphereTrace ? 1.3f : -1.3f, 0.0f);
      addTracedSdf(registry_, asset, method, glm::translate(glm::mat4(1.0f), at), placed % 2 == 1);
      ++placed;
    }
  }
  const render::CameraView front =
      render::CameraView::lookAt({0.4f, 0.3f, 9.0f}, glm::vec3(0.0f), 0.9f, 0.05f, 1.0f);
  const render::CameraView side =
      render::CameraView::lookAt({6.0f, -2.0f, 4.5f}, glm::vec3(0.0f), 0.9f, 0.05f, 1.0f);
  expectPathsAgree(front, "six objects, front", 3000);
  const auto& s = stats(*renderer_);
  EXPECT_EQ(s.trilinearObjects + s.hermiteObjects, 6u);
  EXPECT_EQ(s.textures, 6u) << "one texture per (asset, method, precision)";
  expectPathsAgree(side, "six objects, side", 2000);
}

// Why: the bindless variants are separate shaders (*_bindless.frag); they must reproduce the same
// interpolants as the CPU reference, with the tolerances every device is allowed
// (device_tolerances.h: the trilinear filter's weight quantization included).
TEST_F(BindlessTest, EachMethodMatchesItsReference) {
  SKIP_WITHOUT_DESCRIPTOR_INDEXING();
  renderer_ = traceRenderer(*context_, true);
  ASSERT_NE(renderer_, nullptr);
  const DeviceTolerances tolerance = tolerancesFor(*context_);
  const auto asset = bakeAsset("torus", 16);
  ASSERT_NE(asset, nullptr);
  const glm::vec3 center(asset->surfaceBounds.center());
  const float radius = 0.5f * float(glm::length(asset->surfaceBounds.size()));
  for (const RenderMethod method : {RenderMethod::TrilinearSphereTrace, RenderMethod::HermiteSphereTrace}) {
    registry_.clear();
    addTracedSdf(registry_, asset, method);
    for (int view = 0; view < 2; ++view) {
      const std::string label = std::string(hsdf::renderMethodName(method)) + " view " + std::to_string(view);
      SCOPED_TRACE(label);
      const render::CameraView camera = orbitCamera(center, radius, view);
      const Frame shaded = draw(*renderer_, camera, DEBUG_VIEW_NONE);
      const Frame normals = draw(*renderer_, camera, DEBUG_VIEW_NORMALS);
      ASSERT_TRUE(stats(*renderer_).bindless);
      const hsdf::ReferenceImage reference = referenceFor(method, asset->field, camera, {int(kSize), int(kSize)});
      const ImageComparison c =
          compareWithReference(shaded, &normals.rgba, reference, camera, asset->field.grid.spacing);
      std::printf("[ %s ] hits ref %d gpu %d, disagree %d, holes %d, extras %d, interior depth p99 %.2e cells, "
                  "normal p99 %.3f deg\n",
                  label.c_str(), c.referenceHits, c.gpuHits, c.disagreements, c.interiorHoles, c.interiorExtras,
                  c.interiorDepthErrorP99, c.normalErrorP99Degrees);
      EXPECT_GT(c.referenceHits, 500);
      EXPECT_GE(c.agreement(int(kSize * kSize)), 1.0 - tolerance.coverageDisagreement);
      EXPECT_EQ(c.interiorHoles, 0) << "a ray that missed a surface it should hit (e.g. ran out of steps)";
      EXPECT_EQ(c.interiorExtras, 0);
      // Interior pixels mostly face the camera (cos >= 0.5): twice the along-normal tolerance.
      EXPECT_LT(c.interiorDepthErrorP99, 2.0 * tolerance.traceDepthCells(method == RenderMethod::TrilinearSphereTrace));
      EXPECT_LT(c.normalErrorP99Degrees, 2.0);
    }
  }
}

// Why: a released texture frees its slot in the table and the next upload takes it, rewriting the
// descriptor. A stale descriptor (not rewritten, or rewritten while a pending frame used it) would
// draw the previous asset in the new object's place. The entity switches shape five times; each
// time the old texture is released (after framesInFlight frames unused) and its slot reused.
TEST_F(BindlessTest, ReusedSlotsShowTheNewTexture) {
  SKIP_WITHOUT_DESCRIPTOR_INDEXING();
  createBothRenderers();
  const auto sphere = bakeAsset("sphere", 12);
  const auto torus = bakeAsset("torus", 16);
  const auto box = bakeAsset("box", 10);
  ASSERT_TRUE(sphere && torus && box);
  const ecs::Entity entity = addTracedSdf(registry_, sphere, RenderMethod::HermiteSphereTrace);
  const render::CameraView camera = orbitCamera(glm::vec3(0.0f), 1.3f, 0);
  int step = 0;
  for (const auto& asset : {torus, box, sphere, torus, box}) {
    registry_.get<hsdf::HermiteSdfRenderable>(entity).asset = asset;
    // Enough frames for the previous asset's texture to be released (framesInFlight <= 3).
    for (int i = 0; i < 4; ++i) {
      draw(*renderer_, camera, DEBUG_VIEW_NONE);
      draw(*perTextureSets_, camera, DEBUG_VIEW_NONE);
    }
    EXPECT_EQ(stats(*renderer_).textures, 1u) << "the previous asset's texture was released";
    expectPathsAgree(camera, "switch " + std::to_string(++step), 1000);
  }
}

}  // namespace
}  // namespace gputest
