// The shader compiler's statistics of the pipelines built through engine::gpu::Pipeline
// (engine/gpu/shader_statistics.h): on a statistics device (Mesa RADV's null NAVI10 device, which
// compiles with the real ACO compiler and cannot run anything) and on the rendering device itself.
// The engine's own shaders stand in for any: mesh_prepass.frag writes an id (next to nothing to
// hold), mesh.frag shades (far more live values). RADV's null device is part of
// mesa-vulkan-drivers, which CI installs (scripts/deps.sh): a machine without it fails here, loudly.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "engine/gpu/context.h"
#include "engine/gpu/descriptor_set_layout.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/shader_statistics.h"
#include "shared/host_device.h"
#include "test_files.h"
#include "test_device.h"

namespace engine::gpu {
namespace {

constexpr std::uint32_t kPushBytes = 128;  // covers the mesh shaders' push constants

Expected<std::unique_ptr<Context>> createContext(const ShaderStatisticsDesc& statistics) {
  ContextDesc desc;
  desc.applicationName = "shader statistics test";
  const auto device = hsdftest::testDevicePreference();
  if (!device) return device.error();
  desc.device = *device;
  desc.validation = true;
  desc.shaderStatistics = statistics;
  return Context::create(desc);
}

// mesh.frag's material textures (set 0, bindings MESH_TEXTURE_*), made through DescriptorSetLayout.
DescriptorSetLayout meshTextureLayout(const Context& context) {
  DescriptorSetLayoutDesc desc{"mesh textures", {}, {}};
  for (std::uint32_t binding = 0; binding < MESH_TEXTURE_COUNT; ++binding)
    desc.bindings.push_back({binding, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr});
  return DescriptorSetLayout(context, desc);
}

// mesh.vert's inputs (position, normal, texture coordinate, tangent), a colour target of `color` and a
// depth target; `textures` is set 0 (mesh.frag samples it).
GraphicsPipelineDesc meshDesc(const std::string& name, VkShaderModule vert, VkShaderModule frag, VkFormat color,
                              VkDescriptorSetLayout textures = VK_NULL_HANDLE) {
  GraphicsPipelineDesc desc;
  desc.name = name;
  desc.vertex = vert;
  desc.fragment = frag;
  desc.vertexLayout.bindings.push_back({0, 48, VK_VERTEX_INPUT_RATE_VERTEX});
  desc.vertexLayout.attributes.push_back({0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0});
  desc.vertexLayout.attributes.push_back({1, 0, VK_FORMAT_R32G32B32_SFLOAT, 12});
  desc.vertexLayout.attributes.push_back({2, 0, VK_FORMAT_R32G32_SFLOAT, 24});
  desc.vertexLayout.attributes.push_back({3, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 32});
  if (textures != VK_NULL_HANDLE) desc.setLayouts = {textures};
  desc.colorFormats = {color};
  desc.depthFormat = VK_FORMAT_D32_SFLOAT;
  desc.pushConstantBytes = kPushBytes;
  return desc;
}

const StageStatistics* find(const std::vector<StageStatistics>& rows, const std::string& pipeline, const std::string& stage) {
  const auto row = std::find_if(rows.begin(), rows.end(),
                                [&](const StageStatistics& r) { return r.pipeline == pipeline && r.stage == stage; });
  return row == rows.end() ? nullptr : &*row;
}

std::size_t rowsOf(const std::vector<StageStatistics>& rows, const std::string& pipeline) {
  return std::size_t(std::count_if(rows.begin(), rows.end(), [&](const StageStatistics& r) { return r.pipeline == pipeline; }));
}

class ShaderStatisticsTest : public ::testing::Test {
 protected:
  // RADV shows its null device only when the variable is set as the instance is created.
  hsdftest::ScopedEnvironment family_{"RADV_FORCE_FAMILY", "navi10"};

  std::unique_ptr<Context> statisticsContext() {
    auto context = createContext({StatisticsTarget::Device, "NAVI10"});
    EXPECT_TRUE(context.ok()) << "RADV's null NAVI10 device (mesa-vulkan-drivers) is needed: "
                              << context.error().message;
    return context ? std::move(*context) : nullptr;
  }
};

// Tricky: the pipelines are created on the rendering device (lavapipe) with its handles; the
// statistics come from a second device that has to compile the same SPIR-V with its own copies of
// the modules and layouts. A copy made from the wrong module (the vertex shader for both stages,
// say) or not made at all would still leave rows, so the rows' shaders and stages are checked, and
// the heavier fragment shader must need more vector registers than the trivial one.
TEST_F(ShaderStatisticsTest, GraphicsAndComputePipelinesAreCompiledOnTheStatisticsDevice) {
  std::unique_ptr<Context> context = statisticsContext();
  ASSERT_NE(context, nullptr);
  ShaderStatistics* statistics = context->shaderStatistics();
  ASSERT_NE(statistics, nullptr);
  EXPECT_NE(statistics->deviceName().find("NAVI10"), std::string::npos) << statistics->deviceName();
  EXPECT_NE(context->capabilities().deviceName, statistics->deviceName()) << "it renders on another device";
  {
    auto vert = ShaderModule::load(*context, "mesh.vert");
    auto prepass = ShaderModule::load(*context, "mesh_prepass.frag");
    auto shade = ShaderModule::load(*context, "mesh.frag");
    auto pyramid = ShaderModule::load(*context, "depth_pyramid.comp");
    ASSERT_TRUE(vert && prepass && shade && pyramid);
    auto light = Pipeline::createGraphics(*context, meshDesc("light", vert->handle(), prepass->handle(), VK_FORMAT_R32G32_UINT));
    const DescriptorSetLayout textures = meshTextureLayout(*context);
    auto heavy = Pipeline::createGraphics(
        *context, meshDesc("heavy", vert->handle(), shade->handle(), VK_FORMAT_R16G16B16A16_SFLOAT, textures.handle()));
    auto compute = Pipeline::createCompute(*context, "pyramid", pyramid->handle(), kPushBytes);
    ASSERT_TRUE(light.ok()) << light.error().message;
    ASSERT_TRUE(heavy.ok()) << heavy.error().message;
    ASSERT_TRUE(compute.ok()) << compute.error().message;
  }
  const std::vector<StageStatistics> rows = statistics->stages();
  const StageStatistics* lightVertex = find(rows, "light", "vertex");
  const StageStatistics* lightFragment = find(rows, "light", "fragment");
  const StageStatistics* heavyFragment = find(rows, "heavy", "fragment");
  const StageStatistics* compute = find(rows, "pyramid", "compute");
  ASSERT_TRUE(lightVertex && lightFragment && heavyFragment && compute) << rows.size() << " rows";
  EXPECT_EQ(lightVertex->shader, "mesh.vert");
  EXPECT_EQ(lightFragment->shader, "mesh_prepass.frag");
  EXPECT_EQ(heavyFragment->shader, "mesh.frag");
  EXPECT_EQ(compute->shader, "depth_pyramid.comp");
  for (const StageStatistics* row : {lightVertex, lightFragment, heavyFragment, compute}) {
    EXPECT_TRUE(row->error.empty()) << row->pipeline << " " << row->stage << ": " << row->error;
    EXPECT_GT(row->value("VGPRs").value_or(0.0), 0.0) << row->pipeline << " " << row->stage;
    EXPECT_GT(row->value("Instructions").value_or(0.0), 0.0) << row->pipeline << " " << row->stage;
  }
  EXPECT_GT(heavyFragment->value("VGPRs").value_or(0.0), lightFragment->value("VGPRs").value_or(0.0));
  EXPECT_GT(heavyFragment->value("Instructions").value_or(0.0), lightFragment->value("Instructions").value_or(0.0));
  EXPECT_EQ(hsdftest::messagesThroughDestruction(context), 0u);
}

// Tricky: a pipeline's set layouts exist on the rendering device only; the statistics device gets
// a copy of those made through DescriptorSetLayout. One made around it cannot be copied: its
// pipeline still renders, and its rows say why they hold no statistics instead of going missing.
TEST_F(ShaderStatisticsTest, SetLayoutsAreCopiedAndOneMadeAroundTheHelperIsNamed) {
  std::unique_ptr<Context> context = statisticsContext();
  ASSERT_NE(context, nullptr);
  VkDescriptorSetLayout raw = VK_NULL_HANDLE;
  {
    auto vert = ShaderModule::load(*context, "mesh.vert");
    auto frag = ShaderModule::load(*context, "mesh_prepass.frag");
    ASSERT_TRUE(vert && frag);
    const DescriptorSetLayout helper(
        *context, {"sampled", {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}}, {}});
    GraphicsPipelineDesc desc = meshDesc("with set", vert->handle(), frag->handle(), VK_FORMAT_R32G32_UINT);
    desc.setLayouts = {helper.handle()};
    auto copied = Pipeline::createGraphics(*context, desc);
    ASSERT_TRUE(copied.ok()) << copied.error().message;

    VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    ASSERT_EQ(vkCreateDescriptorSetLayout(context->device(), &info, nullptr, &raw), VK_SUCCESS);
    desc.name = "with raw set";
    desc.setLayouts = {raw};
    auto uncopied = Pipeline::createGraphics(*context, desc);
    EXPECT_TRUE(uncopied.ok()) << "the rendering device is not held back: " << uncopied.error().message;
  }
  vkDestroyDescriptorSetLayout(context->device(), raw, nullptr);
  const std::vector<StageStatistics> rows = context->shaderStatistics()->stages();
  const StageStatistics* copied = find(rows, "with set", "fragment");
  const StageStatistics* uncopied = find(rows, "with raw set", "fragment");
  ASSERT_TRUE(copied && uncopied);
  EXPECT_TRUE(copied->error.empty()) << copied->error;
  EXPECT_TRUE(copied->value("VGPRs").has_value());
  EXPECT_NE(uncopied->error.find("DescriptorSetLayout"), std::string::npos) << uncopied->error;
  EXPECT_TRUE(uncopied->values.empty());
  EXPECT_EQ(hsdftest::messagesThroughDestruction(context), 0u);
}

// Tricky: reloading shaders creates every pipeline again under its name; the table must show the
// pipeline once, as compiled last, not both versions.
TEST_F(ShaderStatisticsTest, PipelineCreatedAgainReplacesItsRows) {
  std::unique_ptr<Context> context = statisticsContext();
  ASSERT_NE(context, nullptr);
  {
    auto vert = ShaderModule::load(*context, "mesh.vert");
    auto prepass = ShaderModule::load(*context, "mesh_prepass.frag");
    auto shade = ShaderModule::load(*context, "mesh.frag");
    ASSERT_TRUE(vert && prepass && shade);
    auto first = Pipeline::createGraphics(*context, meshDesc("reloaded", vert->handle(), prepass->handle(), VK_FORMAT_R32G32_UINT));
    auto other = Pipeline::createGraphics(*context, meshDesc("other", vert->handle(), prepass->handle(), VK_FORMAT_R32G32_UINT));
    const DescriptorSetLayout textures = meshTextureLayout(*context);
    auto again = Pipeline::createGraphics(
        *context, meshDesc("reloaded", vert->handle(), shade->handle(), VK_FORMAT_R16G16B16A16_SFLOAT, textures.handle()));
    ASSERT_TRUE(first && other && again);
  }
  const std::vector<StageStatistics> rows = context->shaderStatistics()->stages();
  EXPECT_EQ(rowsOf(rows, "reloaded"), 2u);
  EXPECT_EQ(rowsOf(rows, "other"), 2u);
  ASSERT_NE(find(rows, "reloaded", "fragment"), nullptr);
  EXPECT_EQ(find(rows, "reloaded", "fragment")->shader, "mesh.frag");
  EXPECT_EQ(rows.front().pipeline, "reloaded") << "it keeps the place it was first created in";
  EXPECT_EQ(hsdftest::messagesThroughDestruction(context), 0u);
}

// Tricky: a statistics device that is not there (RADV_FORCE_FAMILY unset, another family, no
// mesa-vulkan-drivers) must stop the program with the name it asked for and the way to get one,
// not render without statistics or crash.
TEST_F(ShaderStatisticsTest, MissingStatisticsDeviceIsAClearError) {
  const auto context = createContext({StatisticsTarget::Device, "NO-SUCH-GPU"});
  ASSERT_FALSE(context.ok());
  EXPECT_NE(context.error().message.find("no Vulkan device named '*NO-SUCH-GPU*'"), std::string::npos)
      << context.error().message;
  EXPECT_NE(context.error().message.find("RADV_FORCE_FAMILY"), std::string::npos) << context.error().message;
}

// Tricky: native statistics read the rendering device's own pipelines, which must be created with
// the capture flag and the extension on; a device without the extension is refused naming it.
// Both outcomes are checked, so the test holds on any device.
TEST_F(ShaderStatisticsTest, NativeStatisticsComeFromTheRenderingDeviceOrNameTheExtension) {
  auto created = createContext({StatisticsTarget::Native, {}});
  if (!created) {
    EXPECT_NE(created.error().message.find(VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME), std::string::npos)
        << created.error().message;
    return;
  }
  std::unique_ptr<Context> context = std::move(*created);
  ASSERT_NE(context->shaderStatistics(), nullptr);
  EXPECT_EQ(context->shaderStatistics()->deviceName(), context->capabilities().deviceName);
  // The spec reads statistics only from pipelines created with the flag; lavapipe answers without
  // it, so the flag is checked here rather than through the rows.
  EXPECT_EQ(context->shaderStatistics()->pipelineFlags(), VkPipelineCreateFlags(VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR));
  {
    auto pyramid = ShaderModule::load(*context, "depth_pyramid.comp");
    ASSERT_TRUE(pyramid.ok());
    auto compute = Pipeline::createCompute(*context, "pyramid", pyramid->handle(), kPushBytes);
    ASSERT_TRUE(compute.ok()) << compute.error().message;
  }
  const std::vector<StageStatistics> rows = context->shaderStatistics()->stages();
  const StageStatistics* compute = find(rows, "pyramid", "compute");
  ASSERT_NE(compute, nullptr);
  EXPECT_TRUE(compute->error.empty()) << compute->error;
  EXPECT_FALSE(compute->values.empty());
  EXPECT_EQ(compute->shader, "depth_pyramid.comp");
  EXPECT_EQ(hsdftest::messagesThroughDestruction(context), 0u);
}

// Tricky: without the option nothing changes: no statistics object, no flags on any pipeline.
TEST_F(ShaderStatisticsTest, OffByDefault) {
  auto context = createContext({});
  ASSERT_TRUE(context.ok()) << context.error().message;
  EXPECT_EQ((*context)->shaderStatistics(), nullptr);
}

}  // namespace
}  // namespace engine::gpu
