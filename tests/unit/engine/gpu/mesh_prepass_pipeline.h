#pragma once
// One real pipeline for the tests of how pipelines are compiled (lazy_pipeline_test.cpp,
// pipeline_cache_device_test.cpp): the mesh depth prepass, mesh.vert with mesh_prepass.frag (the
// visibility and hit-offset targets and depth). What it draws does not matter to them; that a
// driver compiles it does.
#include <string>

#include <gtest/gtest.h>

#include "engine/gpu/lazy_pipeline.h"

namespace engine::gpu {

// The pipeline described and named `name`, not compiled; not described (a failed expectation)
// where the shaders cannot be loaded. The caller's LazyPipeline is then the modules' only owner.
inline LazyPipeline describeMeshPrepass(const Context& context, const std::string& name) {
  auto vert = loadSharedShaderModule(context, "mesh.vert");
  auto frag = loadSharedShaderModule(context, "mesh_prepass.frag");
  EXPECT_TRUE(vert && frag);
  if (!vert || !frag) return {};
  GraphicsPipelineDesc desc;
  desc.name = name;
  desc.vertex = (*vert)->handle();
  desc.fragment = (*frag)->handle();
  desc.vertexLayout.bindings.push_back({0, 48, VK_VERTEX_INPUT_RATE_VERTEX});  // render::MeshVertex
  desc.vertexLayout.attributes.push_back({0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0});
  desc.vertexLayout.attributes.push_back({1, 0, VK_FORMAT_R32G32B32_SFLOAT, 12});
  desc.vertexLayout.attributes.push_back({2, 0, VK_FORMAT_R32G32_SFLOAT, 24});
  desc.vertexLayout.attributes.push_back({3, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 32});
  desc.colorFormats = {VK_FORMAT_R32G32_UINT, VK_FORMAT_R32_SFLOAT};  // render::RendererFormats::prepassColorFormats()
  desc.depthFormat = VK_FORMAT_D32_SFLOAT;
  desc.pushConstantBytes = 128;
  return LazyPipeline(desc, {*vert, *frag});
}

}  // namespace engine::gpu
