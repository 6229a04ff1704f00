// The shader rebuild behind "Reload shaders" (samples/common/shader_build.h): what it reports when
// there is nothing to build and when the build fails. (Its success path is the build's own shader
// target; running it here would race a concurrent build of the same tree.)
#include <gtest/gtest.h>

#include <filesystem>

#include "shader_build.h"

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

}  // namespace
}  // namespace samples
