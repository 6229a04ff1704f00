// engine::gpu::addShaderDirectory (engine/gpu/pipeline.h): a program's own SPIR-V folder searched
// before the engine's, as a project outside the repository has its shaders in a folder of its own.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <unistd.h>

#include "engine/gpu/pipeline.h"
#include "gpu_fault_support.h"

namespace engine::gpu {
namespace {

// Tricky: a shader only the added folder has must load once the folder is added (not before),
// the engine's own shaders must still load from theirs, and a shader no folder has must be
// refused naming every folder searched (a newcomer's project could not load its SPIR-V without
// copying the engine's 65 files beside it).
TEST(ShaderSearch, AnAddedFolderIsSearchedBeforeTheEnginesAndNamedWhenNothingIsFound) {
  auto context = test::makeTestContext();
  ASSERT_NE(context, nullptr);
  const std::filesystem::path own =
      std::filesystem::temp_directory_path() / ("hsdf_shader_search_" + std::to_string(::getpid()));
  std::filesystem::remove_all(own);
  std::filesystem::create_directories(own);
  std::filesystem::copy_file(shaderDirectory() / "mesh.vert.spv", own / "own_stage.vert.spv");

  EXPECT_FALSE(ShaderModule::load(*context, "own_stage.vert").ok()) << "found before its folder was added";
  addShaderDirectory(own);
  addShaderDirectory(own);  // added once
  ASSERT_EQ(shaderDirectories().size(), 2u);
  EXPECT_EQ(shaderDirectories().front(), own);
  auto loaded = ShaderModule::load(*context, "own_stage.vert");
  EXPECT_TRUE(loaded.ok()) << loaded.error().message;
  auto engines = ShaderModule::load(*context, "mesh.frag");
  EXPECT_TRUE(engines.ok()) << engines.error().message;

  auto missing = ShaderModule::load(*context, "nowhere.frag");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find(own.string()), std::string::npos) << missing.error().message;
  EXPECT_NE(missing.error().message.find(shaderDirectory().string()), std::string::npos) << missing.error().message;
  std::filesystem::remove_all(own);
  EXPECT_EQ(context->validationMessageCount(), 0u);
}

}  // namespace
}  // namespace engine::gpu
