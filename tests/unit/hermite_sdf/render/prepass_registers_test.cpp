// The production depth prepass's fragment shaders, as the scene's render features build them,
// compiled for the paper's GPU family (AMD RX 5700, NAVI10) by Mesa's ACO on RADV's null device
// (engine/gpu/shader_statistics.h): none may spill a register or use scratch memory. A spill moves
// live values to memory on every GPU it happens on; a change that pushes a prepass shader past the
// register file shows here before any GPU runs it. The rule that names the production prepass
// shaders is PrepassSpirv's (tests/support/prepass_shaders.h). RADV's null device is part of
// mesa-vulkan-drivers, which CI installs (scripts/deps.sh): without it this fails, never skips.
// Compiler statistics, not timings.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "engine/gpu/context.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/shader_statistics.h"
#include "engine/render/mesh_pool.h"
#include "engine/render/renderer.h"
#include "hermite_sdf/render/features.h"
#include "prepass_shaders.h"
#include "test_files.h"
#include "test_device.h"

namespace {

using namespace engine;

std::unique_ptr<gpu::Context> navi10StatisticsContext() {
  gpu::ContextDesc desc;
  desc.applicationName = "prepass registers test";
  const auto device = hsdftest::testDevicePreference();
  EXPECT_TRUE(device.ok()) << device.error().message;
  if (!device) return nullptr;
  desc.device = *device;
  desc.validation = true;
  desc.shaderStatistics = {gpu::StatisticsTarget::Device, "NAVI10"};
  auto context = gpu::Context::create(desc);
  EXPECT_TRUE(context.ok()) << "RADV's null NAVI10 device (mesa-vulkan-drivers) is needed: " << context.error().message;
  return context ? std::move(*context) : nullptr;
}

bool isProductionPrepass(const std::string& shader) {
  return hsdftest::isPrepassFragmentShader(shader) && !hsdftest::isExemptPrepassVariant(shader);
}

// The production prepass shaders this build has (file names without .spv) that the rendering
// device builds: the bindless tracer variants only where it has descriptor indexing.
std::set<std::string> builtPrepassShaders(bool descriptorIndexing) {
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(gpu::shaderDirectory())) {
    const std::string file = entry.path().filename().string();
    if (entry.path().extension() != ".spv" || !isProductionPrepass(file)) continue;
    if (!descriptorIndexing && hsdftest::nameContains(file, "bindless")) continue;
    names.insert(entry.path().stem().string());
  }
  return names;
}

// Every pipeline the scene's render features build, compiled once for the suite (createAllPipelines:
// frames would compile them one by one) on RADV's null NAVI10 device: each stage's statistics.
struct Navi10Compilation {
  std::vector<gpu::StageStatistics> stages;
  bool descriptorIndexing = false;
  std::uint64_t validationMessages = 0;
  std::string error;  // why nothing was compiled
};

Navi10Compilation compileSceneFeaturesOnNavi10() {
  const hsdftest::ScopedEnvironment family("RADV_FORCE_FAMILY", "navi10");
  std::unique_ptr<gpu::Context> context = navi10StatisticsContext();
  if (context == nullptr) return {.error = "no NAVI10 statistics device"};
  Navi10Compilation compilation;
  {
    render::MeshPool meshes(*context);
    render::Renderer renderer(*context, render::RendererDesc{}, VkExtent2D{32, 32});
    const Status added = hsdf::addSceneFeatures(renderer, meshes);
    const Status created = added.ok() ? renderer.createAllPipelines() : added;
    if (!created.ok()) compilation.error = created.error().message;
  }
  compilation.stages = context->shaderStatistics()->stages();
  compilation.descriptorIndexing = context->capabilities().descriptorIndexing;
  compilation.validationMessages = hsdftest::messagesThroughDestruction(context);
  return compilation;
}

class PrepassRegisters : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { compilation_ = new Navi10Compilation(compileSceneFeaturesOnNavi10()); }
  static void TearDownTestSuite() {
    delete compilation_;
    compilation_ = nullptr;
  }
  void SetUp() override {
    ASSERT_TRUE(compilation_->error.empty()) << compilation_->error;
    EXPECT_EQ(compilation_->validationMessages, 0u);
  }
  static const Navi10Compilation& compilation() { return *compilation_; }

 private:
  static inline Navi10Compilation* compilation_ = nullptr;
};

// Tricky: the features describe their pipelines when they are added and compile them when a frame
// first needs one, from several families (cells, thin cells, runs, bricks, tiles, the tracers,
// meshes) in variants per precision and near plane; checking only the rows found would pass
// vacuously if a family went missing, so every production prepass shader of the build must have
// been compiled, and every one without a spill or scratch.
TEST_F(PrepassRegisters, ProductionPrepassShadersNeitherSpillNorUseScratchOnNavi10) {
  std::set<std::string> compiled;
  for (const gpu::StageStatistics& row : compilation().stages) {
    if (row.stage != "fragment" || !isProductionPrepass(row.shader)) continue;
    SCOPED_TRACE(row.pipeline + " (" + row.shader + ")");
    compiled.insert(row.shader);
    EXPECT_TRUE(row.error.empty()) << row.error;
    for (const char* zero : {"Spilled VGPRs", "Spilled SGPRs", "Scratch size"}) {
      ASSERT_TRUE(row.value(zero).has_value()) << "ACO reports no '" << zero << "'";
      EXPECT_EQ(*row.value(zero), 0.0) << zero << " (VGPRs " << row.value("VGPRs").value_or(-1) << ")";
    }
  }
  const std::set<std::string> expected = builtPrepassShaders(compilation().descriptorIndexing);
  EXPECT_GE(expected.size(), 10u) << "cells, near cells, thin cells, runs, bricks, tiles, the tracers and meshes at least";
  for (const std::string& shader : expected) EXPECT_TRUE(compiled.contains(shader)) << shader << " was not compiled";
}

// The Hermite sphere tracer's depth prepass is the baseline every cell timing is compared with. At
// 72 VGPRs NAVI10 keeps 14 of its subgroups per SIMD, at 76 only 12: every value held through the
// march counts at its peak, the interpolant's evaluation (session 40's anchor held two more and
// took it to 76; the cursor's cell as one int, fieldCellKey, brought it back). Production variants
// only: the counted ones draw no timed frame. The NAVI10 figures are ACO's (mesa-vulkan-drivers as
// CI installs it); a newer compiler may move them, which this names.
TEST_F(PrepassRegisters, HermiteSphereTracerDepthKeepsFourteenSubgroupsOnNavi10) {
  int checked = 0;
  for (const gpu::StageStatistics& row : compilation().stages) {
    if (row.stage != "fragment" || !isProductionPrepass(row.shader) ||
        !row.shader.starts_with("sphere_trace_hermite_depth"))
      continue;
    SCOPED_TRACE(row.pipeline + " (" + row.shader + ")");
    ++checked;
    ASSERT_TRUE(row.value("VGPRs").has_value()) << "ACO reports no 'VGPRs'";
    EXPECT_LE(*row.value("VGPRs"), 72.0) << "subgroups per SIMD: " << row.value("Subgroups per SIMD").value_or(-1);
  }
  EXPECT_GE(checked, 2) << "the Hermite tracer's depth and near-plane depth prepass";
}

}  // namespace
