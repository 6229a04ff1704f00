// A blended mesh (glTF alphaMode BLEND: a glass pane) in front of an SDF object: the object is
// drawn as it is without the pane (its prepass and resolve never see the pane), and the pane is
// blended over the finished object.
#include <algorithm>
#include <cstdio>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "engine/core/math.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/render/features.h"
#include "hermite_test_support.h"
#include "shared/host_device.h"

namespace gputest {
namespace {

using namespace engine;

constexpr std::uint32_t kImage = 96;
constexpr double kColourTolerance = 0.04;  // linear, as the mesh feature's references (mesh_feature_test.cpp)

struct MethodCase {
  const char* label;
  hsdf::RenderMethod method;
};

// Every SDF method: the cell methods' colour comes from the resolve in the shading pass, the
// tracers' from their own shading pass.
const MethodCase kMethods[] = {{"cells", hsdf::RenderMethod::Cells},
                               {"cell runs", hsdf::RenderMethod::CellRuns},
                               {"cell bricks", hsdf::RenderMethod::CellBricks},
                               {"trilinear tracer", hsdf::RenderMethod::TrilinearSphereTrace},
                               {"hermite tracer", hsdf::RenderMethod::HermiteSphereTrace}};

class BlendedOverSdfTest : public GpuTest {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    createRenderer(kImage, kImage);  // the meshes first, as hsdf::addSceneFeatures adds them
    ASSERT_TRUE(hsdf::addRenderFeatures(*renderer_).ok());
  }
};

// Why: a glass pane in front of an SDF object shows the object through it. A pane of alpha 0.5
// covers part of a sphere (and some background beside it), drawn by the cells and by a sphere
// tracer; the frame without the pane, read back, is the independent reference of what lies behind
// it. Under the pane every pixel must be the pane's lit colour (the CPU reference of the lighting)
// blended over that frame's pixel, everywhere else the frame unchanged; the depth everywhere is the
// frame's without the pane. Tricky because the pane must be in no depth prepass (it would hide the
// sphere: no resolve, no trace behind it) and must be drawn after the SDF objects' shading, which
// paints its pixels whole (a pane drawn in the shading pass before the resolve would be painted
// over on the sphere and kept beside it). Tolerance: the mesh references' (the pane's lighting);
// the pixel behind it is the very value blended.
TEST_F(BlendedOverSdfTest, ABlendedQuadShowsTheSdfObjectBehindIt) {
  const auto asset = bakeAsset("sphere", 16);
  ASSERT_NE(asset, nullptr);
  const WorldSphere sphere = worldSphere(*asset, glm::mat4(1.0f));
  const glm::vec3 eye = sphere.center + glm::vec3(0.0f, 0.0f, 2.6f * sphere.radius);
  const render::CameraView camera = render::CameraView::lookAt(eye, sphere.center, 0.8f, 0.01f, 1.0f);
  // worldSphere's radius is its bounds' half diagonal: the sphere itself is 1 / sqrt(3) of it. The
  // pane covers its right edge and the background beside it.
  const float paneZ = sphere.center.z + 1.2f * sphere.radius, paneSide = 0.5f * sphere.radius;
  const glm::vec3 paneCentre(sphere.center.x + 0.35f * sphere.radius, sphere.center.y, paneZ);
  const glm::dvec3 paneColor(0.1, 0.6, 0.2);
  const double paneRoughness = render::MeshRenderable{}.roughness;

  // Where the ray through `pixel` meets the pane's plane, and whether inside the pane.
  auto onPane = [&](glm::vec2 pixel) {
    const math::Ray ray = math::pixelRay(camera.view, camera.proj, pixel, glm::ivec2(int(kImage)));
    return ray.origin + ((double(paneZ) - ray.origin.z) / ray.direction.z) * ray.direction;
  };
  auto inside = [&](glm::vec2 pixel) {
    const glm::dvec3 p = onPane(pixel) - glm::dvec3(paneCentre);
    return std::abs(p.x) < 0.5 * double(paneSide) && std::abs(p.y) < 0.5 * double(paneSide);
  };

  for (const MethodCase& m : kMethods) {
    SCOPED_TRACE(m.label);
    registry_.clear();
    addSdf(registry_, asset, m.method);
    const Frame alone = render(camera);
    const ecs::Entity pane = addQuad(paneCentre, paneSide, glm::vec4(glm::vec3(paneColor), 0.5f));
    registry_.get<render::MeshRenderable>(pane).alphaBlend = true;
    const Frame frame = render(camera);

    int overSphere = 0, overBackground = 0, wrong = 0, changedOutside = 0, depthChanged = 0;
    double worst = 0.0;
    for (std::uint32_t y = 0; y < kImage; ++y) {
      for (std::uint32_t x = 0; x < kImage; ++x) {
        depthChanged += frame.depthAt(x, y) != alone.depthAt(x, y);
        const glm::vec2 centre(float(x) + 0.5f, float(y) + 0.5f);
        const bool in = inside(centre);
        bool edge = false;
        for (const glm::vec2 offset : {glm::vec2(-0.5f), glm::vec2(0.5f, -0.5f), glm::vec2(-0.5f, 0.5f), glm::vec2(0.5f)})
          edge = edge || inside(centre + offset) != in;
        if (edge) continue;
        if (!in) {
          changedOutside += frame.pixel(x, y) != alone.pixel(x, y);
          continue;
        }
        const glm::dvec3 lit = referenceShading(renderer_->desc(), paneColor, paneRoughness, glm::dvec3(eye),
                                                onPane(centre), {0.0, 0.0, 1.0});
        const glm::dvec3 expected = 0.5 * lit + 0.5 * linearColor(alone.pixel(x, y));
        const double error = glm::length(linearColor(frame.pixel(x, y)) - expected);
        worst = std::max(worst, error);
        wrong += error > kColourTolerance;
        ++(alone.depthAt(x, y) > 0.0f ? overSphere : overBackground);
      }
    }
    std::printf("%s: pane over the sphere %d pixels, over the background %d, wrong %d (worst %.4f), changed outside "
                "the pane %d, depth changed %d\n",
                m.label, overSphere, overBackground, wrong, worst, changedOutside, depthChanged);
    EXPECT_GT(overSphere, 300);
    EXPECT_GT(overBackground, 100);
    EXPECT_EQ(wrong, 0) << "pixels unlike the pane blended over the frame without it (worst " << worst << ")";
    EXPECT_EQ(changedOutside, 0) << "pixels outside the pane changed";
    EXPECT_EQ(depthChanged, 0) << "the pane changed the depth: it is in the prepass";
  }
}

}  // namespace
}  // namespace gputest
