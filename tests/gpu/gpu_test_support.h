#pragma once
// Shared fixture of the GPU tests: a lavapipe context with validation layers on (a test fails on
// any validation message), a renderer with the mesh feature, and helpers to build small scenes.
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "engine/ecs/registry.h"
#include "engine/gpu/context.h"
#include "engine/render/camera_view.h"
#include "engine/render/mesh_feature.h"
#include "engine/render/mesh_pool.h"
#include "engine/render/renderer.h"

namespace gputest {

// Creates the lavapipe context every GPU test uses; validation is always on.
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

class GpuTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override;  // fails the test on any validation message

  // Resolves the transform hierarchy, renders `frames` frames and reads the last one back.
  Frame render(const engine::render::CameraView& camera, std::uint32_t frames = 1);
  // Renders one frame with a debug view (DEBUG_VIEW_*) as the registry stands (WorldTransforms
  // are used as they are) and reads it back.
  Frame renderWith(const engine::render::CameraView& camera, std::uint32_t debugView);
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
