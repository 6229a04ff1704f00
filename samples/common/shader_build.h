#pragma once
// "Reload shaders" rebuilds the SPIR-V first: the build tree's shader target (glslang through
// cmake/Shaders.cmake), run as `cmake --build <build dir> --target shaders`, so that an edited
// shaders/*.glsl reaches the running program; a variant (a row of a variant table, cmake/Shaders.cmake)
// is recompiled with its row's defines, as the build compiled it. A compile error fails the build:
// the old .spv files and the running pipelines stay, and the compiler's output is the error.
#include <filesystem>
#include <string>

#include "engine/core/expected.h"

namespace samples {

struct ShaderBuild {
  std::filesystem::path cmake;     // the cmake program
  std::filesystem::path buildDir;  // a configured build tree
};
// The build tree this program was built in (empty paths for an installed program whose build tree
// is gone, or when HSDF_SHADER_DIR points the loader elsewhere: then nothing is built).
ShaderBuild thisProgramsShaderBuild();

// Runs the shader target. Returns a one-line note of what was done ("shaders rebuilt", "no build
// tree: ..."); an error holding the build's output (the compiler's message) when it fails.
engine::Expected<std::string> rebuildShaders(const ShaderBuild& build);

}  // namespace samples
