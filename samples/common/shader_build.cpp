#include "shader_build.h"

#include <cstdio>
#include <cstdlib>

#include <fmt/format.h>

#ifndef HSDF_BUILD_DIR
#error "HSDF_BUILD_DIR must be defined by the build"
#endif
#ifndef HSDF_CMAKE_COMMAND
#error "HSDF_CMAKE_COMMAND must be defined by the build"
#endif

namespace samples {
namespace {

constexpr std::size_t kMaxOutput = 4000;  // the end of a long build log holds the error

// A path in double quotes for the shell (the build paths are the project's own, without quotes).
std::string quoted(const std::filesystem::path& path) {
  std::string text(1, '"');
  text.append(path.string()).push_back('"');
  return text;
}

}  // namespace

ShaderBuild thisProgramsShaderBuild() {
  if (const char* dir = std::getenv("HSDF_SHADER_DIR"); dir && *dir) return {};
  std::error_code ec;
  if (!std::filesystem::is_directory(HSDF_BUILD_DIR, ec)) return {};
  return {HSDF_CMAKE_COMMAND, HSDF_BUILD_DIR};
}

engine::Expected<std::string> rebuildShaders(const ShaderBuild& build) {
  if (build.cmake.empty() || build.buildDir.empty())
    return std::string("no build tree to rebuild (HSDF_SHADER_DIR set, or an installed program): loading the SPIR-V as it is");
  const std::string command = quoted(build.cmake) + " --build " + quoted(build.buildDir) + " --target shaders 2>&1";
  std::FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return engine::makeError("could not run: " + command);
  std::string output;
  char buffer[512];
  while (std::fgets(buffer, sizeof(buffer), pipe)) output += buffer;
  const int status = pclose(pipe);
  if (output.size() > kMaxOutput) output = std::string("...").append(output, output.size() - kMaxOutput, kMaxOutput);
  if (status != 0) return engine::makeError(fmt::format("shader build failed ({}):\n{}", command, output));
  return std::string("shaders rebuilt (cmake --build " + build.buildDir.string() + " --target shaders)");
}

}  // namespace samples
