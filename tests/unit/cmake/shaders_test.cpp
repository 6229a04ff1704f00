// The shader build (cmake/Shaders.cmake): variant rows compiled with their defines as the stage
// their name ends in, and the rows it refuses at configure time, each with a message naming the
// row and what is wrong. Each test builds a scratch project (tests/support/shader_project.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <string>

#include "shader_project.h"

namespace {

using hsdftest::CommandResult;
using hsdftest::ShaderProject;

constexpr int kExecutionModelVertex = 0;
constexpr int kExecutionModelFragment = 4;

bool holdsConstant(const std::vector<std::uint32_t>& spirv, float value) {
  const std::vector<std::uint32_t> words = hsdftest::constantWords(spirv);
  return std::find(words.begin(), words.end(), std::bit_cast<std::uint32_t>(value)) != words.end();
}

// Configures a project of one folder whose rows are `rows`; returns cmake's result.
CommandResult configureRows(const std::string& name, const std::string& rows) {
  const ShaderProject project = hsdftest::writeShaderProject(
      name, "hsdf_add_shaders(INCLUDE_DIRS ${CMAKE_CURRENT_SOURCE_DIR})\n" + rows, hsdftest::tintShaderFiles("0.25"));
  return hsdftest::configure(project);
}

// Tricky: three rows share one source, and only the defines (and the stage, from the name) tell
// them apart: a build that dropped the defines would make tint_on equal to tint_off, and one that
// took the stage from the source's extension (.glsl names none) would not compile the vertex row.
TEST(Shaders, EachVariantRowIsItsSourceWithItsDefinesAsItsNamesStage) {
  const ShaderProject project = hsdftest::writeShaderProject(
      "variants",
      "hsdf_add_shaders(INCLUDE_DIRS ${CMAKE_CURRENT_SOURCE_DIR})\n"
      "hsdf_shader_variant(tint_on.frag SOURCE tint.glsl DEFINES TINT_ON=1)\n"
      "hsdf_shader_variant(tint_off.frag SOURCE tint.glsl)\n"
      "hsdf_shader_variant(tint.vert SOURCE tint.glsl DEFINES TINT_VERTEX=1)\n",
      hsdftest::tintShaderFiles("0.25"));
  const CommandResult configured = hsdftest::configure(project);
  ASSERT_EQ(configured.status, 0) << configured.output;
  const CommandResult built = hsdftest::buildShaders(project);
  ASSERT_EQ(built.status, 0) << built.output;

  const auto on = hsdftest::readSpirv(project.build / "shaders" / "tint_on.frag.spv");
  const auto off = hsdftest::readSpirv(project.build / "shaders" / "tint_off.frag.spv");
  const auto vertex = hsdftest::readSpirv(project.build / "shaders" / "tint.vert.spv");
  EXPECT_TRUE(holdsConstant(on, 0.25f)) << "TINT_ON=1 picks the included TINT_VALUE";
  EXPECT_FALSE(holdsConstant(on, 0.75f));
  EXPECT_TRUE(holdsConstant(off, 0.75f)) << "no define: the other branch";
  EXPECT_FALSE(holdsConstant(off, 0.25f));
  EXPECT_EQ(hsdftest::executionModel(on), kExecutionModelFragment);
  EXPECT_EQ(hsdftest::executionModel(vertex), kExecutionModelVertex);
}

// Tricky: each bad row must stop the configure with a message naming the row and the fault; a row
// let through would fail later inside glslang (a missing #version, an unknown stage) or silently
// overwrite another row's .spv (two rows of one name).
TEST(Shaders, BadVariantRowsFailTheConfigureNamingTheFault) {
  struct Case {
    const char* rows;
    const char* message;
  };
  const Case cases[] = {
      {"hsdf_shader_variant(tint_on SOURCE tint.glsl)", "shader tint_on: the name must end in the stage"},
      {"hsdf_shader_variant(tint_on.glsl SOURCE tint.glsl)", "shader tint_on.glsl: the name must end in the stage"},
      {"hsdf_shader_variant(tint_on.frag SOURCE missing.glsl)", "does not exist"},
      {"hsdf_shader_variant(tint_on.frag)", "shader variant tint_on.frag: SOURCE <glsl> is required"},
      {"hsdf_shader_variant(tint_on.frag SOURCE tint.glsl DEFINES TINT_ON)", "define 'TINT_ON' is not NAME=VALUE"},
      {"hsdf_shader_variant(tint_on.frag SOURCE tint.glsl DEFINES -DTINT_ON=1)", "define '-DTINT_ON=1' is not NAME=VALUE"},
      {"hsdf_shader_variant(tint_on.frag SOURCE tint.glsl TINT_ON=1)", "unexpected arguments 'TINT_ON=1'"},
      {"hsdf_shader_variant(tint_on.frag SOURCE tint.glsl)\nhsdf_shader_variant(tint_on.frag SOURCE tint.glsl)",
       "Two shaders named tint_on.frag"},
  };
  int index = 0;
  for (const Case& bad : cases) {
    const CommandResult configured = configureRows("bad_row_" + std::to_string(index++), bad.rows);
    EXPECT_NE(configured.status, 0) << bad.rows;
    EXPECT_NE(configured.output.find(bad.message), std::string::npos) << bad.rows << "\n" << configured.output;
  }
}

// Tricky: a variant resolves its #includes through its folder's include folders, which only
// hsdf_add_shaders names; a row before it would compile without them and fail inside glslang.
TEST(Shaders, AVariantRowBeforeItsFoldersIncludeDirsIsRefused) {
  const ShaderProject project = hsdftest::writeShaderProject(
      "row_first", "hsdf_shader_variant(tint_on.frag SOURCE tint.glsl DEFINES TINT_ON=1)\n",
      hsdftest::tintShaderFiles("0.25"));
  const CommandResult configured = hsdftest::configure(project);
  EXPECT_NE(configured.status, 0);
  EXPECT_NE(configured.output.find("shader variant tint_on.frag: call hsdf_add_shaders"), std::string::npos)
      << configured.output;
}

}  // namespace
