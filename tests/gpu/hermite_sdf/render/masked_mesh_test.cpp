// SDF objects behind glTF alphaMode MASK meshes: the cut-out parts of a mesh leave the shared depth
// prepass, its visibility and its hit offsets to whatever lies behind them.
#include <gtest/gtest.h>

#include <cstdio>
#include <optional>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/render/components.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/render/renderable.h"
#include "hermite_sdf/render/sphere_trace_feature.h"
#include "hermite_test_support.h"

namespace {

using namespace engine;
using namespace gputest;

class MaskedMeshTest : public GpuTest {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    createRenderer(96, 96);
    ASSERT_TRUE(renderer_->addFeature(std::make_unique<hsdf::HermiteCellFeature>()).ok());
    ASSERT_TRUE(renderer_->addFeature(std::make_unique<hsdf::SphereTraceFeature>()).ok());
  }
};

// Why: a leaf card or a fence (MASK) in front of an SDF object must show the object wherever it is
// cut out, for every way the object is drawn. The masked prepass writes depth 0 where it cuts out
// (no discard: issue 20's prepass rule), which the GREATER test rejects, so nothing of the mesh may
// reach the depth, the visibility or the hit offsets there. Tricky because the SDF paths meet the
// mesh's depth in several places: the boxes' conservative depth and early rejection, the tiles'
// and bricks' occlusion culling against the previous frame's depth (two frames are drawn), the
// resolve reading the visibility and the hit offsets, the tracers' depth. A quad whose whole
// surface is cut out (its alpha 0.2 under a cutoff of 0.5) must leave every frame byte for byte as
// without it; the same quad opaque hides most of the object (else the quad is not in front and the
// check proves nothing).
TEST_F(MaskedMeshTest, AWhollyCutOutQuadInFrontOfAnSdfChangesNoPixel) {
  const auto asset = bakeAsset("torus", 16);
  ASSERT_NE(asset, nullptr);
  const render::CameraView camera = orbitAround(worldSphere(*asset, glm::mat4(1.0f)), 0);
  const glm::vec3 eye = camera.position;
  const glm::vec3 center(asset->surfaceBounds.center());
  for (const hsdf::RenderMethod method : hsdf::kRenderMethods) {
    for (const bool tiles : {false, true}) {
      if (tiles && method != hsdf::RenderMethod::Cells) continue;
      const std::string label = std::string(hsdf::renderMethodName(method)) + (tiles ? " tiles" : "");
      SCOPED_TRACE(label);
      renderer_->feature<hsdf::HermiteCellFeature>()->settings().tiles =
          tiles ? hsdf::HermiteCellFeature::Tiles::On : hsdf::HermiteCellFeature::Tiles::Off;
      // The quad halfway between the eye and the object, facing the eye, covering the object.
      auto frameWith = [&](std::optional<float> cutoff, bool quad) {
        registry_ = ecs::Registry();
        addSdf(registry_, asset, method);
        if (quad) {
          const ecs::Entity e = addQuad(glm::vec3(0.0f), 1.0f, {0.9f, 0.7f, 0.2f, 0.2f});
          const glm::mat4 model = glm::inverse(glm::lookAt(glm::mix(eye, center, 0.5f), center, glm::vec3(0, 1, 0))) *
                                  glm::scale(glm::mat4(1.0f), glm::vec3(glm::length(center - eye)));
          registry_.emplace<scene::WorldTransform>(e, scene::WorldTransform{model});
          registry_.get<render::MeshRenderable>(e).alphaCutoff = cutoff;
        }
        renderer_->renderFrame(registry_, camera);  // the previous frame's depth for occlusion culling
        return renderWith(camera, 0);
      };
      const Frame without = frameWith(std::nullopt, false);
      const Frame cutOut = frameWith(0.5f, true);
      const Frame opaque = frameWith(std::nullopt, true);
      int hidden = 0;  // object pixels the opaque quad covers in front (reverse-Z: nearer is greater)
      for (std::uint32_t y = 0; y < without.height; ++y)
        for (std::uint32_t x = 0; x < without.width; ++x)
          hidden += without.depthAt(x, y) > 0.0f && opaque.depthAt(x, y) > without.depthAt(x, y);
      const std::size_t changed = differingPixels(without, cutOut);
      std::printf("%s: the opaque quad hides %d object px, the cut-out one changes %zu px\n", label.c_str(), hidden,
                  changed);
      EXPECT_GT(hidden, 1000) << "the quad must hide the object for the check to mean something";
      EXPECT_EQ(changed, 0u) << "pixels the wholly cut-out quad changed";
    }
  }
}

}  // namespace
