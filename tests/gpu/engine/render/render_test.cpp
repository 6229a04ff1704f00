// Headless rendering on the test device (HSDF_TEST_DEVICE, lavapipe unless set): real pixels read
// back and compared with values computed independently of the GPU (the camera maths, analytic depths, a CPU ray cast of the triangles).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "engine/core/log.h"
#include "engine/core/math.h"
#include "engine/render/components.h"
#include "engine/scene/transform.h"
#include "device_tolerances.h"
#include "gpu_test_support.h"
#include "log_capture.h"

namespace gputest {
namespace {

using namespace engine;

constexpr float kZNear = 0.1f;

render::CameraView frontCamera(float distance, std::uint32_t w, std::uint32_t h) {
  return render::CameraView::lookAt({0.0f, 0.0f, distance}, {0.0f, 0.0f, 0.0f}, 0.8f, kZNear, float(w) / float(h));
}

bool isRedDominant(glm::u8vec4 c) { return c.r > 2 * c.g && c.r > 2 * c.b; }
bool isGreenDominant(glm::u8vec4 c) { return c.g > 2 * c.r && c.g > 2 * c.b; }

// Why: the depth written must follow the reverse-Z convention the CPU side assumes
// (depth = znear / view distance); a wrong projection, clear value or compare op shows here.
TEST_F(GpuTest, KnownDepthAtKnownPixels) {
  createRenderer(64, 48);
  addQuad({0.0f, 0.0f, 0.0f}, 2.0f, {1.0f, 0.0f, 0.0f, 1.0f});
  const Frame frame = render(frontCamera(5.0f, 64, 48));
  const float expected = float(math::viewDistanceToDepth(5.0, kZNear));
  const float tolerance = float(DeviceTolerances{}.meshDepthAbsolute);
  EXPECT_NEAR(frame.depthAt(32, 24), expected, tolerance);
  // The quad is perpendicular to the view axis: every covered pixel has the same view distance.
  EXPECT_NEAR(frame.depthAt(26, 28), expected, tolerance);
  EXPECT_EQ(frame.depthAt(0, 0), 0.0f) << "background keeps the clear depth (infinitely far)";
}

// Why: coverage must match the projection of the geometry computed on the CPU; a y flip, an
// off-by-one viewport or a culled quad (wrong winding) changes which pixels are covered.
TEST_F(GpuTest, CoverageMatchesCpuProjection) {
  const std::uint32_t w = 96, h = 64;
  createRenderer(w, h);
  // Off-centre and above the axis so that a vertical flip would move it.
  const glm::vec3 center(0.4f, 0.5f, 0.0f);
  const float size = 1.2f;
  addQuad(center, size, {0.2f, 0.6f, 1.0f, 1.0f});
  const render::CameraView camera = frontCamera(4.0f, w, h);
  const Frame frame = render(camera);

  const glm::mat4 viewProj = camera.proj * camera.view;
  auto toPixel = [&](glm::vec3 p) {
    const glm::vec4 clip = viewProj * glm::vec4(p, 1.0f);
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    return glm::vec2((ndc.x * 0.5f + 0.5f) * float(w), (ndc.y * 0.5f + 0.5f) * float(h));
  };
  const glm::vec2 lo = toPixel(center - glm::vec3(size / 2, -size / 2, 0.0f));  // top-left in the image
  const glm::vec2 hi = toPixel(center + glm::vec3(size / 2, -size / 2, 0.0f));
  ASSERT_LT(lo.y, hi.y) << "world-up must be image-up";
  int checked = 0, wrong = 0;
  for (std::uint32_t y = 0; y < h; ++y) {
    for (std::uint32_t x = 0; x < w; ++x) {
      const glm::vec2 p(float(x) + 0.5f, float(y) + 0.5f);
      const float inside = std::min({p.x - lo.x, hi.x - p.x, p.y - lo.y, hi.y - p.y});
      if (std::abs(inside) < 0.5f) continue;  // pixel centre too close to an edge to call
      ++checked;
      const bool covered = frame.depthAt(x, y) > 0.0f;
      if (covered != (inside > 0.0f)) ++wrong;
    }
  }
  EXPECT_GT(checked, int(w * h) / 2);
  EXPECT_EQ(wrong, 0);
}

// Why: the shading pass tests depth EQUAL against the prepass; the nearer mesh must win in the
// overlap whatever the draw order, and the farther one must still show where it is not covered.
TEST_F(GpuTest, OverlappingMeshesOccludeThroughDepthPrepass) {
  for (const bool nearFirst : {true, false}) {
    SCOPED_TRACE(nearFirst ? "near mesh created first" : "far mesh created first");
    registry_.clear();
    createRenderer(80, 60);
    const glm::vec4 red(1.0f, 0.0f, 0.0f, 1.0f), green(0.0f, 1.0f, 0.0f, 1.0f);
    if (nearFirst) addQuad({0.4f, 0.0f, 1.0f}, 1.0f, green);
    addQuad({-0.2f, 0.0f, 0.0f}, 1.6f, red);
    if (!nearFirst) addQuad({0.4f, 0.0f, 1.0f}, 1.0f, green);
    const render::CameraView camera = frontCamera(5.0f, 80, 60);
    const Frame frame = render(camera);
    const std::vector<glm::uvec2> visibility = renderer_->readbackVisibility();
    std::uint32_t greenId = 0, redId = 0;

    // Pixels whose ray hits both quads show green; those hitting only the red one show red.
    int overlap = 0, redOnly = 0;
    for (std::uint32_t y = 0; y < 60; ++y) {
      for (std::uint32_t x = 0; x < 80; ++x) {
        const math::Ray ray = math::pixelRay(camera.view, camera.proj, {float(x) + 0.5f, float(y) + 0.5f}, {80, 60});
        auto hits = [&](double z, glm::dvec2 c, double half) {
          const double t = (z - ray.origin.z) / ray.direction.z;
          const glm::dvec3 p = ray.origin + t * ray.direction;
          return std::abs(p.x - c.x) < half - 0.02 && std::abs(p.y - c.y) < half - 0.02;
        };
        const bool hitsGreen = hits(1.0, {0.4, 0.0}, 0.5);
        const bool hitsRed = hits(0.0, {-0.2, 0.0}, 0.8);
        if (hitsGreen && hitsRed) {
          ++overlap;
          EXPECT_TRUE(isGreenDominant(frame.pixel(x, y))) << "pixel " << x << "," << y;
          EXPECT_NEAR(frame.depthAt(x, y), math::viewDistanceToDepth(4.0, kZNear), DeviceTolerances{}.meshDepthAbsolute);
          // The visibility id names one object, the same across the overlap.
          const std::uint32_t id = visibility[y * 80 + x].x;
          EXPECT_NE(id, 0u);
          if (greenId == 0) greenId = id;
          EXPECT_EQ(id, greenId);
        } else if (hitsRed && !hitsGreen) {
          const double tGreen = (1.0 - ray.origin.z) / ray.direction.z;
          const glm::dvec3 p = ray.origin + tGreen * ray.direction;
          if (std::abs(p.x - 0.4) < 0.55 && std::abs(p.y) < 0.55) continue;  // near the green edge
          ++redOnly;
          EXPECT_TRUE(isRedDominant(frame.pixel(x, y))) << "pixel " << x << "," << y;
          const std::uint32_t id = visibility[y * 80 + x].x;
          if (redId == 0) redId = id;
          EXPECT_EQ(id, redId);
        }
      }
    }
    EXPECT_GT(overlap, 50);
    EXPECT_GT(redOnly, 50);
    EXPECT_NE(redId, 0u);
    EXPECT_NE(redId, greenId);
    EXPECT_EQ(visibility[0].x, 0u) << "background pixels have no object";
  }
}

// Why: objects outside the view must be culled without disturbing the others, and an empty frame
// (nothing visible) must still be a valid frame.
TEST_F(GpuTest, CulledAndEmptyFramesStayValid) {
  createRenderer(32, 32);
  addQuad({0.0f, 0.0f, 10.0f}, 1.0f, {1.0f, 1.0f, 1.0f, 1.0f});  // behind the camera
  const Frame frame = render(frontCamera(5.0f, 32, 32), 3);
  EXPECT_TRUE(std::all_of(frame.depth.begin(), frame.depth.end(), [](float d) { return d == 0.0f; }));
  EXPECT_EQ(renderer_->feature<render::MeshFeature>()->drawnLastFrame(), 0u);
}

// Why: resizing recreates the targets while frames are in flight.
TEST_F(GpuTest, ResizeKeepsRendering) {
  createRenderer(32, 32);
  addQuad({0.0f, 0.0f, 0.0f}, 2.0f, {1.0f, 0.0f, 0.0f, 1.0f});
  render(frontCamera(5.0f, 32, 32), 2);
  renderer_->resize({48, 40});
  const Frame frame = render(frontCamera(5.0f, 48, 40), 2);
  ASSERT_EQ(frame.width, 48u);
  EXPECT_GT(frame.depthAt(24, 20), 0.0f);
}

// Tricky: a renderer made with no frame in flight divided by zero at its first frame (SIGFPE),
// and one made with an empty extent or one past the device's largest image called Vulkan with
// invalid arguments (8 validation errors, then "Buffer 'readback': size 0"); found by a helper's
// program against the installed package. Each must be refused by name before anything is made; a
// resize past the limits too, while a resize to a side of 0 (a minimised window) keeps the targets.
TEST_F(GpuTest, ARendererRefusesNoFramesInFlightAndExtentsPastTheDevice) {
  const auto refusal = [&](const render::RendererDesc& desc, VkExtent2D extent) -> std::string {
    try {
      render::Renderer renderer(*context_, desc, extent);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "accepted";
  };
  render::RendererDesc none;
  none.framesInFlight = 0;
  EXPECT_NE(refusal(none, {32, 32}).find("RendererDesc::framesInFlight 0"), std::string::npos) << refusal(none, {32, 32});
  EXPECT_NE(refusal({}, {0, 0}).find("extent 0x0"), std::string::npos) << refusal({}, {0, 0});
  EXPECT_NE(refusal({}, {32, 0}).find("extent 32x0"), std::string::npos);
  VkPhysicalDeviceProperties properties;
  vkGetPhysicalDeviceProperties(context_->physicalDevice(), &properties);
  const std::uint32_t past = properties.limits.maxImageDimension2D + 1;
  EXPECT_NE(refusal({}, {past, 8}).find("extent " + std::to_string(past) + "x8"), std::string::npos) << refusal({}, {past, 8});

  createRenderer(32, 32);
  addQuad({0.0f, 0.0f, 0.0f}, 2.0f, {1.0f, 0.0f, 0.0f, 1.0f});
  EXPECT_THROW(renderer_->resize({8, past}), std::invalid_argument);
  renderer_->resize({0, 40});
  EXPECT_EQ(renderer_->extent().width, 32u);
  const Frame frame = render(frontCamera(5.0f, 32, 32), 2);
  EXPECT_GT(frame.depthAt(16, 16), 0.0f);
  EXPECT_EQ(context_->validationMessageCount(), 0u);
}

// Tricky: a program that places its entities by Transform and never runs updateWorldTransforms
// drew an empty frame without a word (found by a newcomer helper following the docs): said once,
// as a warning naming the call, and not again every frame; an updated registry says nothing.
TEST_F(GpuTest, ARegistryWithoutWorldTransformsIsSaidOnce) {
  createRenderer(32, 32);
  addQuad({0.0f, 0.0f, 0.0f}, 2.0f, {1.0f, 0.0f, 0.0f, 1.0f});
  hsdftest::LogCapture capture;
  for (int frame = 0; frame < 3; ++frame) renderer_->renderFrame(registry_, frontCamera(5.0f, 32, 32));
  const std::vector<float> empty = renderer_->readbackDepth();
  scene::updateWorldTransforms(registry_);
  renderer_->renderFrame(registry_, frontCamera(5.0f, 32, 32));
  const std::vector<float> drawn = renderer_->readbackDepth();
  const std::vector<std::string> warnings = capture.messages();
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("updateWorldTransforms"), std::string::npos) << warnings[0];
  EXPECT_TRUE(std::all_of(empty.begin(), empty.end(), [](float d) { return d == 0.0f; }));
  EXPECT_GT(drawn[16 * 32 + 16], 0.0f);
}

// A feature that times many parts of its pass, as the module's features do (culling, prepass,
// shading per method).
class ManyScopesFeature final : public render::RenderFeature {
 public:
  static constexpr int kScopes = 20;
  std::string_view name() const override { return "many scopes"; }
  Status initialize(const gpu::Context&, const render::RendererFormats&, std::uint32_t) override { return {}; }
  void prepare(render::FrameContext&) override {}
  void recordPass(render::PassContext& pass) override {
    for (int i = 0; i < kScopes; ++i) {
      pass.timer.begin(pass.cmd, "scope " + std::to_string(i));
      pass.timer.end(pass.cmd);
    }
  }
};

// Tricky: the GPU timer held 64 scopes per frame for all view regions together, though meant per
// region: a four-region split screen of every method lost the fourth region's timings and warned
// five times a frame (found by a helper). Each region's scopes must all be timed, and under names
// of their own: a feature's scopes carried no region suffix, so a split screen drawing one method
// on both sides had two "cells prepass" timings, merged into one history by the panel.
TEST_F(GpuTest, EveryViewRegionIsTimed) {
  createRenderer(64, 64);
  ASSERT_TRUE(renderer_->addFeature(std::make_unique<ManyScopesFeature>()).ok());
  addQuad({0.0f, 0.0f, 0.0f}, 2.0f, {1.0f, 0.0f, 0.0f, 1.0f});
  hsdftest::LogCapture capture;
  render::FrameSettings settings;
  const std::uint32_t regions = renderer_->desc().maxViewRegions;
  for (std::uint32_t r = 0; r < regions; ++r) settings.regions.push_back({{{std::int32_t(16 * r), 0}, {16, 64}}, {}});
  scene::updateWorldTransforms(registry_);
  for (int frame = 0; frame < 4; ++frame) renderer_->renderFrame(registry_, frontCamera(5.0f, 64, 64), settings);
  renderer_->finish();
  const std::vector<std::string> warnings = capture.messages();
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  std::size_t timed = 0;
  std::set<std::string> names;
  for (const gpu::GpuTiming& timing : renderer_->lastTimings()) {
    if (!timing.name.starts_with("scope ")) continue;
    ++timed;
    names.insert(timing.name);
  }
  // Each region's passes (prepass, opaque) call recordPass: every call's scopes.
  EXPECT_GE(timed, std::size_t(ManyScopesFeature::kScopes) * regions * 2);
  EXPECT_EQ(names.size(), std::size_t(ManyScopesFeature::kScopes) * regions) << "a name per scope and region";
  EXPECT_NE(gpu::findTiming(renderer_->lastTimings(), "scope 0 [view 2]"), nullptr);
  EXPECT_NE(gpu::findTiming(renderer_->lastTimings(), "depth prepass [view 2]"), nullptr);
  EXPECT_NE(gpu::findTiming(renderer_->lastTimings(), "depth prepass"), nullptr);
  EXPECT_EQ(gpu::findTiming(renderer_->lastTimings(), "depth prepass [view 1]"), nullptr) << "the first region is unmarked";
  EXPECT_EQ(context_->validationMessageCount(), 0u);
}

// Why: a smooth mesh's vertex normals lean over its silhouette, so the normal interpolated over a
// front-facing triangle there faces a little away from the eye (here a coarse sphere, whose rim
// triangles' far vertices lie behind the outline). The shading turned such a normal round, and
// the pixel was lit as the sphere's far side: dark specks along the lit rim, bright ones along the
// unlit rim (found in the bunny's images, 61-123 pixels a 640x360 view). The light comes from the
// side so that the two sides of the rim differ; every pixel is compared with the analytic
// sphere's shading (lighting.glsl written again on the CPU), and a CPU cast of the triangles
// confirms the case is there: pixels whose interpolated normal faces away.
TEST_F(GpuTest, SilhouettePixelsOfASmoothMeshAreLitAsTheirOwnSide) {
  const std::uint32_t size = 160;
  render::RendererDesc desc;
  desc.lightDirection = {1.0f, 0.15f, 0.0f};
  renderer_ = std::make_unique<render::Renderer>(*context_, desc, VkExtent2D{size, size});
  ASSERT_TRUE(renderer_->addFeature(std::make_unique<render::MeshFeature>(*pool_)).ok());

  // A UV sphere of radius 1, 16 segments x 8 rings, each vertex's normal its exact sphere normal.
  const int segments = 16, rings = 8;
  std::vector<glm::vec3> positions, normals;
  for (int i = 0; i <= rings; ++i) {
    for (int j = 0; j <= segments; ++j) {
      const float theta = 3.14159265f * float(i) / float(rings), phi = 6.28318531f * float(j) / float(segments);
      positions.emplace_back(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      normals.push_back(positions.back());
    }
  }
  std::vector<std::uint32_t> indices;
  auto addTriangle = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const glm::vec3 normal = glm::cross(positions[b] - positions[a], positions[c] - positions[a]);
    if (glm::length(normal) < 1e-6f) return;  // the poles' degenerate triangles
    if (glm::dot(normal, positions[a] + positions[b] + positions[c]) < 0.0f) std::swap(b, c);  // outwards
    indices.insert(indices.end(), {a, b, c});
  };
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      const std::uint32_t a = std::uint32_t(i * (segments + 1) + j), b = a + 1, c = a + std::uint32_t(segments + 1), d = c + 1;
      addTriangle(a, b, c);
      addTriangle(b, d, c);
    }
  }
  const ecs::Entity sphere = registry_.create();
  registry_.emplace<scene::Transform>(sphere, scene::Transform{});
  render::MeshRenderable renderable;
  renderable.mesh = pool_->add(positions, normals, indices);
  renderable.roughness = 0.6f;
  registry_.emplace<render::MeshRenderable>(sphere, renderable);
  // Slightly above the equator, so that the rim runs across triangles of several rings.
  const glm::vec3 eye(0.3f, 0.7f, 3.4f);
  const render::CameraView camera = render::CameraView::lookAt(eye, {0.0f, 0.0f, 0.0f}, 0.8f, kZNear, 1.0f);
  const Frame frame = render(camera);

  int covered = 0, facingAway = 0, wrong = 0;
  double worst = 0.0;
  for (std::uint32_t y = 0; y < size; ++y) {
    for (std::uint32_t x = 0; x < size; ++x) {
      if (frame.depthAt(x, y) <= 0.0f) continue;
      const math::Ray ray = math::pixelRay(camera.view, camera.proj, {float(x) + 0.5f, float(y) + 0.5f},
                                           {int(size), int(size)});
      const glm::dvec3 o(ray.origin), d = glm::normalize(glm::dvec3(ray.direction));
      // The analytic sphere: the mesh is inscribed in it, so every ray that hits the mesh hits it.
      const double b = glm::dot(o, d), disc = b * b - (glm::dot(o, o) - 1.0);
      if (disc < 0.0) continue;
      ++covered;
      const glm::dvec3 hit = o + (-b - std::sqrt(disc)) * d;
      const glm::dvec3 expected =
          referenceShading(desc, glm::dvec3(renderable.color), renderable.roughness, glm::dvec3(eye), hit, hit);
      const double error = glm::length(linearColor(frame.pixel(x, y)) - expected);
      worst = std::max(worst, error);
      wrong += error > 0.25;
      // The CPU cast of the triangles: the interpolated normal where the ray meets the mesh.
      double nearest = 1e30;
      glm::dvec3 interpolated(0.0);
      for (std::size_t t = 0; t < indices.size(); t += 3) {
        const glm::dvec3 p0(positions[indices[t]]), p1(positions[indices[t + 1]]), p2(positions[indices[t + 2]]);
        const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0, q = glm::cross(d, e2);
        const double det = glm::dot(e1, q);
        if (det <= 1e-12) continue;  // back faces (culled) and edge-on triangles
        const glm::dvec3 s = o - p0, r = glm::cross(s, e1);
        const double u = glm::dot(s, q) / det, v = glm::dot(d, r) / det, dist = glm::dot(e2, r) / det;
        if (u < 0.0 || v < 0.0 || u + v > 1.0 || dist <= 0.0 || dist >= nearest) continue;
        nearest = dist;
        interpolated = (1.0 - u - v) * glm::dvec3(normals[indices[t]]) + u * glm::dvec3(normals[indices[t + 1]]) +
                       v * glm::dvec3(normals[indices[t + 2]]);
      }
      facingAway += nearest < 1e30 && glm::dot(interpolated, d) > 0.0;
    }
  }
  std::printf("covered %d, interpolated normal facing away %d, wrong %d, worst colour error %.3f\n", covered,
              facingAway, wrong, worst);
  EXPECT_GT(covered, 3000);
  EXPECT_GE(facingAway, 20) << "the case under test: rim pixels whose interpolated normal faces away";
  EXPECT_EQ(wrong, 0) << "pixels lit unlike the sphere (worst colour error " << worst << ")";
}

class SyncValidatedGpuTest : public GpuTest {
  bool useSynchronizationValidation() const override { return true; }
};

// Why: frames in flight share the colour and depth targets; synchronization validation checks the
// barriers between passes, frames and read-backs.
TEST_F(SyncValidatedGpuTest, SeveralFramesInFlightAreHazardFree) {
  createRenderer(64, 64);
  addQuad({0.0f, 0.0f, 0.0f}, 1.0f, {1.0f, 0.5f, 0.0f, 1.0f});
  addQuad({0.3f, 0.2f, 0.5f}, 1.0f, {0.0f, 0.5f, 1.0f, 1.0f});
  const Frame frame = render(frontCamera(4.0f, 64, 64), 5);
  EXPECT_GT(frame.depthAt(32, 32), 0.0f);
  render(frontCamera(3.0f, 64, 64), 2);  // read-back followed by more frames
}

}  // namespace
}  // namespace gputest
