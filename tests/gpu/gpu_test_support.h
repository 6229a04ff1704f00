#pragma once
// Shared fixture of the GPU tests: a context on the device HSDF_TEST_DEVICE names (lavapipe unless
// set; tests/support/test_device.h) with validation layers on (a test fails on any validation message), a renderer with the mesh feature, and helpers to build small scenes.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/ecs/registry.h"
#include "engine/gpu/context.h"
#include "engine/render/camera_view.h"
#include "engine/render/mesh_feature.h"
#include "engine/render/mesh_pool.h"
#include "engine/render/renderer.h"
#include "test_files.h"

namespace gputest {

using hsdftest::sampleAsset;  // test_files.h

// Creates the context every GPU test uses, on the device HSDF_TEST_DEVICE names (lavapipe when
// unset); validation is always on. An unknown HSDF_TEST_DEVICE fails the test naming the value.
std::unique_ptr<engine::gpu::Context> createTestContext(bool synchronizationValidation = false);

struct Frame {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<std::uint8_t> rgba;  // sRGB-encoded RGBA8
  std::vector<float> depth;        // reverse-Z depth, 0 = background
  glm::u8vec4 pixel(std::uint32_t x, std::uint32_t y) const {
    const std::size_t i = (std::size_t(y) * width + x) * 4;
    return {rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]};
  }
  float depthAt(std::uint32_t x, std::uint32_t y) const { return depth[std::size_t(y) * width + x]; }
};

// Pixels whose depth or colour differ between two frames of one size.
std::size_t differingPixels(const Frame& a, const Frame& b);

// Object transforms an engine user (a glTF node, an editor gizmo) produces, each about `pivot`, as
// a parent's and a child's local matrix (both translation * rotation * scale, as glTF nodes are).
struct NamedTransform {
  std::string label;
  glm::mat4 parent;
  glm::mat4 local;
  glm::mat4 matrix() const { return parent * local; }
};
// Mirror in x combined with a rotation; rotation with non-uniform scale (1, 2.5, 0.4); and a
// parent's mirroring non-uniform scale over a rotated child (the child's axes end up sheared).
std::vector<NamedTransform> userTransforms(const glm::vec3& pivot);

// Camera set-ups at the edges of what a user may ask for, looking at a sphere (centre, radius):
// viewports 1x1, 7x300 and 300x7; fields of view 10 and 150 degrees; a camera so far away that the
// object covers a few pixels of a 128x128 image.
struct CameraSetup {
  std::string label;
  glm::uvec2 size;
  engine::render::CameraView camera;
};
std::vector<CameraSetup> extremeCameras(const glm::vec3& center, float radius);

// The world normal a DEBUG_VIEW_NORMALS frame shows at pixel index i (n * 0.5 + 0.5, sRGB target).
glm::dvec3 decodeNormal(const std::vector<std::uint8_t>& normalRgba, std::size_t i);

// The linear colour of an sRGB-encoded 8-bit pixel.
glm::dvec3 linearColor(glm::u8vec4 srgb);

// The linear colour shared/lighting.glsl's shadeSurface gives a point at `position` with the unit
// normal `normal`, facing the eye (the lighting of `desc`; written again here, in double, as the
// independent reference of the shaded frames); `occlusion` of its ambient light reaching it
// (shadeOccludedSurface).
glm::dvec3 referenceShading(const engine::render::RendererDesc& desc, const glm::dvec3& baseColor, double roughness,
                            const glm::dvec3& eye, const glm::dvec3& position, const glm::dvec3& normal,
                            double occlusion = 1.0);

class GpuTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override;  // fails the test on any validation message, at device destruction too

  // Resolves the transform hierarchy, renders `frames` frames and reads the last one back.
  Frame render(const engine::render::CameraView& camera, std::uint32_t frames = 1);
  // Renders one frame with a debug view (DEBUG_VIEW_*) as the registry stands (WorldTransforms
  // are used as they are) and reads it back.
  Frame renderWith(const engine::render::CameraView& camera, std::uint32_t debugView);
  // The same with any frame settings (work counters, ...).
  Frame renderWith(const engine::render::CameraView& camera, const engine::render::FrameSettings& settings);
  // An axis-aligned square of side `size` in the plane z = center.z, facing +Z.
  engine::ecs::Entity addQuad(const glm::vec3& center, float size, const glm::vec4& color);

  void createRenderer(std::uint32_t width, std::uint32_t height);
  virtual bool useSynchronizationValidation() const { return false; }

  std::unique_ptr<engine::gpu::Context> context_;
  std::unique_ptr<engine::render::MeshPool> pool_;
  std::unique_ptr<engine::render::Renderer> renderer_;
  engine::ecs::Registry registry_;
  engine::render::MeshHandle quad_;
};

}  // namespace gputest
