// The floors of the house (docs/architecture.md), checked on every #include of the source tree:
// a file may include its own floor and the floors below it, never one above. The engine knows no
// module; the module's CPU half (core) knows no Vulkan and nothing of its GPU half (render); the
// shaders include only shaders, the engine's (shaders/) only the engine's, the module's
// (modules/hermite_sdf/shaders/) their own and the engine's. Samples, tools and tests stand on top
// and may include anything.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path kRoot = fs::path(HSDF_SOURCE_DIR);

// The floor a source file (path relative to the repository root) stands on; nullopt: on top.
std::optional<std::string> floorOfFile(const std::string& path) {
  static const std::vector<std::pair<std::string, std::string>> prefixes = {
      {"engine/core/", "engine/core"},
      {"engine/ecs/", "engine/ecs"},
      {"engine/gpu/", "engine/gpu"},
      {"engine/scene/", "engine/scene"},
      {"engine/platform/", "engine/platform"},
      {"engine/render/", "engine/render"},
      {"engine/ui/", "engine/ui"},
      {"modules/hermite_sdf/include/hermite_sdf/core/", "module/core"},
      {"modules/hermite_sdf/src/core/", "module/core"},
      {"modules/hermite_sdf/include/hermite_sdf/render/", "module/render"},
      {"modules/hermite_sdf/src/render/", "module/render"},
      {"modules/hermite_sdf/shaders/", "module/shaders"},
      {"shaders/", "engine/shaders"},
  };
  for (const auto& [prefix, floor] : prefixes)
    if (path.rfind(prefix, 0) == 0) return floor;
  return std::nullopt;
}

// The floor an #include "..." names. The module's private headers are named relative to its src/
// folders ("cells/cell_bricks.h" is core's, "render/cell_history.h" render's).
std::optional<std::string> floorOfInclude(const std::string& include) {
  static const std::vector<std::pair<std::string, std::string>> prefixes = {
      {"engine/core/", "engine/core"},
      {"engine/ecs/", "engine/ecs"},
      {"engine/gpu/", "engine/gpu"},
      {"engine/scene/", "engine/scene"},
      {"engine/platform/", "engine/platform"},
      {"engine/render/", "engine/render"},
      {"engine/ui/", "engine/ui"},
      {"hermite_sdf/core/", "module/core"},
      {"hermite_sdf/render/", "module/render"},
      {"source/", "module/core"},
      {"field/", "module/core"},
      {"cells/", "module/core"},
      {"io/", "module/core"},
      {"reference/", "module/core"},
      {"bake/", "module/core"},
      {"render/", "module/render"},
      {"hermite/", "module/shaders"},
      {"shared/", "engine/shaders"},
      {"samples/", "top"},
      {"tools/", "top"},
      {"tests/", "top"},
  };
  for (const auto& [prefix, floor] : prefixes)
    if (include.rfind(prefix, 0) == 0) return floor;
  return std::nullopt;  // a file beside the includer, or a third-party header
}

// Which floors each floor may include (itself included).
const std::map<std::string, std::set<std::string>>& allowedFloors() {
  static const std::map<std::string, std::set<std::string>> allowed = {
      {"engine/core", {"engine/core"}},
      {"engine/ecs", {"engine/ecs", "engine/core"}},
      {"engine/gpu", {"engine/gpu", "engine/core"}},
      {"engine/scene", {"engine/scene", "engine/core", "engine/ecs"}},
      {"engine/platform", {"engine/platform", "engine/core", "engine/gpu"}},
      // shaders/shared/host_device.h: the GPU structs of the engine's own passes.
      {"engine/render",
       {"engine/render", "engine/core", "engine/ecs", "engine/gpu", "engine/scene", "engine/shaders"}},
      {"engine/ui", {"engine/ui", "engine/core", "engine/gpu", "engine/platform", "engine/render"}},
      // hermite/hermite_host_device.h: the cell record's and the cones' GPU layout (data, no Vulkan).
      // It includes shared/host_device.h, the engine's.
      {"module/core", {"module/core", "engine/core", "engine/scene", "module/shaders", "engine/shaders"}},
      {"module/render",
       {"module/render", "module/core", "engine/core", "engine/ecs", "engine/gpu", "engine/scene", "engine/render",
        "module/shaders", "engine/shaders"}},
      {"engine/shaders", {"engine/shaders"}},
      {"module/shaders", {"module/shaders", "engine/shaders"}},
  };
  return allowed;
}

// Floors that must not see Vulkan, GLFW or ImGui (their angle-bracket includes).
bool mayIncludeGraphicsApis(const std::string& floor) {
  return floor != "engine/core" && floor != "engine/ecs" && floor != "engine/scene" && floor != "module/core" &&
         floor != "engine/shaders" && floor != "module/shaders";
}

// Every violation in one file's text: "<file>: includes <what> (<floor> may not include <floor>)".
std::vector<std::string> violations(const std::string& file, const std::string& text) {
  std::vector<std::string> out;
  const std::optional<std::string> floor = floorOfFile(file);
  if (!floor) return out;
  static const std::regex quoted(R"re(^\s*#\s*include\s*"([^"]+)")re");
  static const std::regex angled(R"re(^\s*#\s*include\s*<((vulkan|GLFW|imgui|volk)[^>]*)>)re");
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::smatch m;
    if (std::regex_search(line, m, quoted)) {
      const std::optional<std::string> target = floorOfInclude(m[1].str());
      if (target && !allowedFloors().at(*floor).contains(*target))
        out.push_back(file + ": includes \"" + m[1].str() + "\" (" + *floor + " may not include " + *target + ")");
    } else if (std::regex_search(line, m, angled) && !mayIncludeGraphicsApis(*floor)) {
      out.push_back(file + ": includes <" + m[1].str() + "> (" + *floor + " stays free of graphics APIs)");
    }
  }
  return out;
}

// Every line of one engine file's text that names the module (its name or its types' stem, in
// any case: "hermite_sdf", "HermiteCellFeature", "HERMITE_..."): "<file>:<line>: <text>". The engine
// is the floor under every module, in code, comments and build files alike.
std::vector<std::string> moduleNames(const std::string& file, const std::string& text) {
  static const std::regex moduleWord("hermite", std::regex::icase);
  std::vector<std::string> out;
  std::istringstream lines(text);
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number)
    if (std::regex_search(line, moduleWord)) out.push_back(file + ":" + std::to_string(number) + ": " + line);
  return out;
}

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

bool isSource(const fs::path& path) {
  static const std::set<std::string> extensions = {".h", ".hpp", ".cpp", ".glsl", ".vert", ".frag", ".comp"};
  return extensions.contains(path.extension().string());
}

// Tricky because a checker that never fires passes forever: each kind of step up is fed to it as
// text, with one legal include beside it, and must be named with its floors.
TEST(Layering, TheCheckNamesEachStepUp) {
  const auto one = [](const std::string& file, const std::string& include) {
    const auto found = violations(file, "#include \"engine/core/expected.h\"\n#include " + include + "\n");
    return found.size() == 1 ? found.front() : std::string("(") + std::to_string(found.size()) + " violations)";
  };
  EXPECT_EQ(one("engine/render/x.cpp", "\"hermite_sdf/render/cell_feature.h\""),
            "engine/render/x.cpp: includes \"hermite_sdf/render/cell_feature.h\" (engine/render may not include "
            "module/render)");
  EXPECT_EQ(one("engine/core/x.h", "\"engine/gpu/context.h\""),
            "engine/core/x.h: includes \"engine/gpu/context.h\" (engine/core may not include engine/gpu)");
  EXPECT_EQ(one("modules/hermite_sdf/src/core/cells/x.cpp", "\"render/cell_history.h\""),
            "modules/hermite_sdf/src/core/cells/x.cpp: includes \"render/cell_history.h\" (module/core may not include "
            "module/render)");
  EXPECT_EQ(one("modules/hermite_sdf/include/hermite_sdf/core/x.h", "\"engine/render/renderer.h\""),
            "modules/hermite_sdf/include/hermite_sdf/core/x.h: includes \"engine/render/renderer.h\" (module/core "
            "may not include engine/render)");
  EXPECT_EQ(one("modules/hermite_sdf/src/core/field/x.cpp", "<vulkan/vulkan.h>"),
            "modules/hermite_sdf/src/core/field/x.cpp: includes <vulkan/vulkan.h> (module/core stays free of "
            "graphics APIs)");
  EXPECT_EQ(one("engine/scene/x.cpp", "\"samples/common/viewer.h\""),
            "engine/scene/x.cpp: includes \"samples/common/viewer.h\" (engine/scene may not include top)");
  EXPECT_EQ(one("modules/hermite_sdf/src/render/x.cpp", "\"engine/ui/ui_layer.h\""),
            "modules/hermite_sdf/src/render/x.cpp: includes \"engine/ui/ui_layer.h\" (module/render may not include "
            "engine/ui)");
  // The module's GPU half is the module's: neither the engine's C++ nor its shaders see it.
  EXPECT_EQ(one("engine/render/x.h", "\"hermite/hermite_host_device.h\""),
            "engine/render/x.h: includes \"hermite/hermite_host_device.h\" (engine/render may not include "
            "module/shaders)");
  EXPECT_EQ(violations("shaders/x.frag", "#include \"shared/host_device.h\"\n#include \"hermite/hermite.glsl\"\n"),
            std::vector<std::string>{
                "shaders/x.frag: includes \"hermite/hermite.glsl\" (engine/shaders may not include module/shaders)"});
  // Steps down and sideways within a floor are fine; the top may include anything.
  EXPECT_TRUE(violations("modules/hermite_sdf/shaders/hermite/x.frag", "#include \"shared/host_device.h\"\n").empty());
  EXPECT_TRUE(violations("modules/hermite_sdf/src/render/x.cpp", "#include \"hermite_sdf/core/cells.h\"\n").empty());
  EXPECT_TRUE(violations("samples/common/x.cpp", "#include \"hermite_sdf/render/cell_feature.h\"\n").empty());
}

// Tricky because the name hides in comments, strings and build files, in several cases.
TEST(Layering, TheNameCheckFindsTheModuleInAnyCase) {
  EXPECT_EQ(moduleNames("engine/ui/x.cpp", "int a;\n  ImGui::Begin(\"hermite_sdf\");\n"),
            std::vector<std::string>{"engine/ui/x.cpp:2:   ImGui::Begin(\"hermite_sdf\");"});
  EXPECT_EQ(moduleNames("engine/render/x.h", "// as HermiteCellFeature does\n").size(), 1u);
  EXPECT_EQ(moduleNames("engine/CMakeLists.txt", "set(HERMITE_DIR x)\n").size(), 1u);
  EXPECT_TRUE(moduleNames("engine/render/x.h", "// a module's ray-cast surface\n").empty());
}

// Every file under engine/ and the engine's shaders/, of any kind (sources, CMakeLists): none
// names the module, so the engine builds and reads the same with the module gone.
TEST(Layering, TheEngineNamesNoModule) {
  std::vector<std::string> found;
  int files = 0;
  for (const char* folder : {"engine", "shaders"}) {
    for (const auto& entry : fs::recursive_directory_iterator(kRoot / folder)) {
      if (!entry.is_regular_file()) continue;
      const std::string relative = fs::relative(entry.path(), kRoot).generic_string();
      const auto v = moduleNames(relative, readFile(entry.path()));
      found.insert(found.end(), v.begin(), v.end());
      ++files;
    }
  }
  EXPECT_GT(files, 50) << "the walk found too few files: is HSDF_SOURCE_DIR the repository?";
  for (const std::string& v : found) ADD_FAILURE() << v;
}

TEST(Layering, NoFloorIncludesAFloorAboveIt) {
  std::vector<std::string> found;
  int files = 0;
  for (const char* folder : {"engine", "modules", "shaders"}) {
    for (const auto& entry : fs::recursive_directory_iterator(kRoot / folder)) {
      if (!entry.is_regular_file() || !isSource(entry.path())) continue;
      const std::string relative = fs::relative(entry.path(), kRoot).generic_string();
      const auto v = violations(relative, readFile(entry.path()));
      found.insert(found.end(), v.begin(), v.end());
      ++files;
    }
  }
  EXPECT_GT(files, 150) << "the walk found too few files: is HSDF_SOURCE_DIR the repository?";
  for (const std::string& v : found) ADD_FAILURE() << v;
}

}  // namespace
