// The shader rebuild behind "Reload shaders" (samples/common/shader_build.h): what it reports when
// there is nothing to build and when the build fails, and a rebuild of a scratch project's variants
// (tests/support/shader_project.h; this build tree's own shader target is left alone: rebuilding it
// here would race a concurrent build of the same tree).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <filesystem>
#include <fstream>

#include "shader_build.h"
#include "shader_project.h"

namespace samples {
namespace {

// Tricky: an installed program (or HSDF_SHADER_DIR) has no build tree: that is not an error, the
// SPIR-V on disk is reloaded as it is, and the note says so.
TEST(ShaderBuild, NoBuildTreeIsANoteNotAnError) {
  const auto note = rebuildShaders({});
  ASSERT_TRUE(note.ok()) << note.error().message;
  EXPECT_NE(note->find("no build tree"), std::string::npos) << *note;
}

// Tricky: a failing build must come back as an error carrying the build tool's own output (where
// the compiler's message of a broken shader would be), not just an exit code.
TEST(ShaderBuild, FailedBuildReturnsTheToolsOutput) {
  const std::filesystem::path notABuild = std::filesystem::path(::testing::TempDir()) / "hsdf_not_a_build_tree";
  std::filesystem::create_directories(notABuild);
  const auto built = rebuildShaders({"cmake", notABuild});
  ASSERT_FALSE(built.ok());
  EXPECT_NE(built.error().message.find("shader build failed"), std::string::npos) << built.error().message;
  EXPECT_NE(built.error().message.find("hsdf_not_a_build_tree"), std::string::npos) << built.error().message;
  EXPECT_NE(built.error().message.find("Error"), std::string::npos) << "cmake's own message: " << built.error().message;
}

bool holdsConstant(const std::filesystem::path& spv, float value) {
  const std::vector<std::uint32_t> words = hsdftest::constantWords(hsdftest::readSpirv(spv));
  return std::find(words.begin(), words.end(), std::bit_cast<std::uint32_t>(value)) != words.end();
}

// Tricky: hot reload recompiles a variant from its GLSL, and must compile it as the build does:
// with its row's defines (tint_on would otherwise come back as tint_off, 0.75), and after an edit
// of a header only the source #includes (the depfile, else the old SPIR-V stays and 0.25 is
// reloaded). The reload's rebuild runs the project's own shader target, so the build's rows are
// the one table.
TEST(ShaderBuild, RebuildRecompilesAVariantWithItsDefinesAfterAnIncludeChanges) {
  const hsdftest::ShaderProject project = hsdftest::writeShaderProject(
      "hot_reload",
      "hsdf_add_shaders(INCLUDE_DIRS ${CMAKE_CURRENT_SOURCE_DIR})\n"
      "hsdf_shader_variant(tint_on.frag SOURCE tint.glsl DEFINES TINT_ON=1)\n"
      "hsdf_shader_variant(tint_off.frag SOURCE tint.glsl)\n",
      hsdftest::tintShaderFiles("0.25"));
  const hsdftest::CommandResult configured = hsdftest::configure(project);
  ASSERT_EQ(configured.status, 0) << configured.output;
  const ShaderBuild build{hsdftest::cmakeProgram(), project.build};
  const auto first = rebuildShaders(build);
  ASSERT_TRUE(first.ok()) << first.error().message;
  const std::filesystem::path on = project.build / "shaders" / "tint_on.frag.spv";
  const std::filesystem::path off = project.build / "shaders" / "tint_off.frag.spv";
  ASSERT_TRUE(holdsConstant(on, 0.25f));

  std::ofstream(project.source / "tint_value.glsl") << "#define TINT_VALUE 0.125\n";
  const auto reloaded = rebuildShaders(build);
  ASSERT_TRUE(reloaded.ok()) << reloaded.error().message;
  EXPECT_NE(reloaded->find("shaders rebuilt"), std::string::npos) << *reloaded;
  EXPECT_TRUE(holdsConstant(on, 0.125f)) << "the edited header, through the row's TINT_ON";
  EXPECT_FALSE(holdsConstant(on, 0.25f)) << "the old SPIR-V was kept";
  EXPECT_FALSE(holdsConstant(on, 0.75f)) << "the variant lost its define";
  EXPECT_TRUE(holdsConstant(off, 0.75f));
  EXPECT_FALSE(holdsConstant(off, 0.125f));
}

}  // namespace
}  // namespace samples
