#include "shader_project.h"

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#ifndef HSDF_SOURCE_DIR
#error "HSDF_SOURCE_DIR must be defined by the build"
#endif
#ifndef HSDF_CMAKE_COMMAND
#error "HSDF_CMAKE_COMMAND must be defined by the build"
#endif
#ifndef HSDF_CMAKE_GENERATOR
#error "HSDF_CMAKE_GENERATOR must be defined by the build"
#endif

namespace hsdftest {
namespace {

constexpr std::uint32_t kSpirvMagic = 0x07230203u;
constexpr std::uint32_t kOpEntryPoint = 15u;
constexpr std::uint32_t kOpConstant = 43u;
constexpr std::size_t kHeaderWords = 5;

void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("could not write " + path.string());
}

// A path in double quotes for the shell (built by append: GCC 12 warns on "\"" + string).
std::string quoted(const std::filesystem::path& path) {
  std::string text(1, '"');
  text.append(path.string()).push_back('"');
  return text;
}

// Calls visit(opcode, operands, operandCount) for each instruction after the header.
template <typename Visit>
void forEachInstruction(const std::vector<std::uint32_t>& spirv, Visit visit) {
  if (spirv.size() < kHeaderWords || spirv[0] != kSpirvMagic) return;
  for (std::size_t at = kHeaderWords; at < spirv.size();) {
    const std::uint32_t words = spirv[at] >> 16;
    if (words == 0 || at + words > spirv.size()) return;  // a broken stream: stop, the test fails on what it misses
    visit(spirv[at] & 0xffffu, &spirv[at + 1], words - 1);
    at += words;
  }
}

}  // namespace

CommandResult runCommand(const std::string& command) {
  CommandResult result;
  std::FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return result;
  char buffer[512];
  while (std::fgets(buffer, sizeof(buffer), pipe)) result.output += buffer;
  const int status = pclose(pipe);
  result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

ShaderProject writeShaderProject(const std::string& name, const std::string& rows,
                                 const std::map<std::string, std::string>& files) {
  // The process id keeps two build trees' test runs (release and asan at once) apart.
  const std::filesystem::path root = std::filesystem::path(::testing::TempDir()) /
                                     ("hsdf_shader_project_" + std::to_string(::getpid()) + "_" + name);
  std::filesystem::remove_all(root);
  std::filesystem::create_directories(root / "source");
  writeText(root / "source" / "CMakeLists.txt",
            "cmake_minimum_required(VERSION 3.25)\nproject(shader_project NONE)\n"
            "list(APPEND CMAKE_MODULE_PATH \"" HSDF_SOURCE_DIR "/cmake\")\ninclude(Shaders)\n" +
                rows + "\nhsdf_compile_shaders(shaders)\n");
  for (const auto& [file, text] : files) writeText(root / "source" / file, text);
  return {root / "source", root / "build"};  // a prvalue: no copy whose destructor would remove it
}

ShaderProject::~ShaderProject() {
  if (::testing::Test::HasFailure()) return;
  std::error_code ignored;  // a scratch folder left behind is not the test's failure
  std::filesystem::remove_all(source.parent_path(), ignored);
}

CommandResult configure(const ShaderProject& project) {
  return runCommand(quoted(cmakeProgram()) + " -S " + quoted(project.source) + " -B " + quoted(project.build) +
                    " -G " + quoted(HSDF_CMAKE_GENERATOR));
}

CommandResult buildShaders(const ShaderProject& project) {
  return runCommand(quoted(cmakeProgram()) + " --build " + quoted(project.build) + " --target shaders");
}

std::filesystem::path cmakeProgram() { return HSDF_CMAKE_COMMAND; }

std::map<std::string, std::string> tintShaderFiles(const std::string& tintValue) {
  return {{"tint.glsl",
           "#version 460\n#extension GL_GOOGLE_include_directive : require\n#include \"tint_value.glsl\"\n"
           "#ifdef TINT_VERTEX\nvoid main() { gl_Position = vec4(TINT_VALUE); }\n#else\n"
           "layout(location = 0) out vec4 outColor;\n"
           "#ifdef TINT_ON\nvoid main() { outColor = vec4(TINT_VALUE); }\n"
           "#else\nvoid main() { outColor = vec4(0.75); }\n#endif\n#endif\n"},
          {"tint_value.glsl", "#define TINT_VALUE " + tintValue + "\n"}};
}

std::vector<std::uint32_t> readSpirv(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::uint32_t> words(bytes.size() / 4);
  std::memcpy(words.data(), bytes.data(), words.size() * 4);
  return words;
}

std::vector<std::uint32_t> constantWords(const std::vector<std::uint32_t>& spirv) {
  std::vector<std::uint32_t> values;
  forEachInstruction(spirv, [&](std::uint32_t opcode, const std::uint32_t* operands, std::uint32_t count) {
    if (opcode == kOpConstant && count == 3) values.push_back(operands[2]);  // type, id, one value word
  });
  return values;
}

int executionModel(const std::vector<std::uint32_t>& spirv) {
  int model = -1;
  forEachInstruction(spirv, [&](std::uint32_t opcode, const std::uint32_t* operands, std::uint32_t count) {
    if (opcode == kOpEntryPoint && count > 0 && model < 0) model = static_cast<int>(operands[0]);
  });
  return model;
}

}  // namespace hsdftest
