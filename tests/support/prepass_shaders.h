#pragma once
// Which SPIR-V files are the depth prepass's fragment shaders, and which of them are production
// ones: one rule for every test that guards them (their SPIR-V, their registers on a GPU family).
#include <string>

namespace hsdftest {

inline bool nameContains(const std::string& text, const char* part) { return text.find(part) != std::string::npos; }

// Every fragment shader whose name says depth or prepass (cells_depth*, runs_depth*,
// sphere_trace_*_depth*, mesh_prepass, ...), new ones included: "<name>.frag.spv" or "<name>.frag".
inline bool isPrepassFragmentShader(std::string name) {
  const std::string spv = ".spv";
  if (name.size() > spv.size() && name.compare(name.size() - spv.size(), spv.size(), spv) == 0)
    name.resize(name.size() - spv.size());
  const std::string suffix = ".frag";
  if (name.size() <= suffix.size() || name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) return false;
  return nameContains(name, "depth") || nameContains(name, "prepass");
}

// Variants that are not drawn in a production frame's prepass, and so may write buffers: the work
// counters (_counted), the software rasterizers' early depth stage and its fix-up (_early) and
// the debug views (_wire, _debug).
inline bool isExemptPrepassVariant(const std::string& name) {
  return nameContains(name, "_counted") || nameContains(name, "_early") || nameContains(name, "_wire") ||
         nameContains(name, "_debug");
}

}  // namespace hsdftest
