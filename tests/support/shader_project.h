#pragma once
// A scratch CMake project that compiles its shaders with this source tree's cmake/Shaders.cmake
// (stage files and variant rows, as the engine's and the module's CMakeLists do), for the tests of
// the shader build and of its hot reload. Its `shaders` target writes build/shaders/<name>.spv.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace hsdftest {

struct CommandResult {
  int status = -1;     // the shell's exit status; 0 is success
  std::string output;  // stdout and stderr together
};
CommandResult runCommand(const std::string& command);

struct ShaderProject {
  std::filesystem::path source;  // CMakeLists.txt and the GLSL files
  std::filesystem::path build;   // the build tree (its SPIR-V in build/shaders)
  // Removes both at the end of a passing test; a failed test's stay for its reader.
  ~ShaderProject();
};
// Writes a fresh project under the test temp folder: CMakeLists.txt includes cmake/Shaders.cmake,
// then `rows` (hsdf_add_shaders / hsdf_shader_variant calls), then makes the `shaders` target;
// `files` are the GLSL files (name -> text).
ShaderProject writeShaderProject(const std::string& name, const std::string& rows,
                                 const std::map<std::string, std::string>& files);
// Configures the project's build tree with the generator this build uses.
CommandResult configure(const ShaderProject& project);
// Builds its `shaders` target.
CommandResult buildShaders(const ShaderProject& project);
// The cmake program this build runs (what samples/common/shader_build.h's ShaderBuild holds).
std::filesystem::path cmakeProgram();

// tint.glsl, a shader source for variant rows, and the header it includes, tint_value.glsl, which
// defines TINT_VALUE as `tintValue`. Compiled with TINT_VERTEX it is a vertex shader (gl_Position =
// TINT_VALUE); else a fragment shader writing TINT_VALUE with TINT_ON, 0.75 without.
std::map<std::string, std::string> tintShaderFiles(const std::string& tintValue);

std::vector<std::uint32_t> readSpirv(const std::filesystem::path& path);
// The value words of the module's scalar OpConstant instructions (a float constant's bits).
std::vector<std::uint32_t> constantWords(const std::vector<std::uint32_t>& spirv);
// The execution model of the module's first OpEntryPoint (0 vertex, 4 fragment, 5 compute);
// -1 when it has none.
int executionModel(const std::vector<std::uint32_t>& spirv);

}  // namespace hsdftest
