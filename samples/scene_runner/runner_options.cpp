#include "runner_options.h"

#include <cstdlib>
#include <regex>

#include <CLI/CLI.hpp>

namespace runner {
namespace {

constexpr std::uint32_t kMaxDimension = 16384;

// "WxH" with both in [1, kMaxDimension].
bool parseSize(const std::string& text, std::uint32_t& width, std::uint32_t& height) {
  static const std::regex pattern(R"((\d{1,6})[xX](\d{1,6}))");
  std::smatch match;
  if (!std::regex_match(text, match, pattern)) return false;
  const unsigned long w = std::stoul(match[1]), h = std::stoul(match[2]);
  if (w == 0 || h == 0 || w > kMaxDimension || h > kMaxDimension) return false;
  width = std::uint32_t(w);
  height = std::uint32_t(h);
  return true;
}

}  // namespace

std::filesystem::path defaultScenePath() {
  if (const char* dir = std::getenv("HSDF_ASSET_DIR")) return std::filesystem::path(dir) / "bunny.glb";
  return std::filesystem::path(HSDF_DEFAULT_ASSET_DIR) / "bunny.glb";
}

ParseResult parseOptions(int argc, const char* const* argv) {
  Options options;
  std::string size;
  CLI::App app{"hermite_sdf scene runner: renders a glTF scene (default: the bundled bunny)", "scene_runner"};
  app.add_option("--scene", options.scene, "glTF/GLB scene to load")->check(CLI::ExistingFile);
  app.add_flag("--headless", options.headless, "render offscreen without a window");
  app.add_option("--size", size, "image size WxH (default 1280x720)");
  app.add_option("--frames", options.frames, "frames to render, then exit (0: until closed; headless default 1)")
      ->check(CLI::Range(0u, 1000000u));
  app.add_option("--screenshot", options.screenshot, "write the last frame to this PNG file");
  app.add_option("--device", options.device, "Vulkan device: auto, gpu or lavapipe")
      ->check(CLI::IsMember({"auto", "gpu", "lavapipe"}));
  app.add_flag("--validation", options.validation, "enable the Vulkan validation layers");
  app.add_flag("--ui", options.headlessUi, "draw the ImGui panels into headless screenshots");
  app.add_flag("!--no-ground", options.groundPlane, "do not add the ground plane");

  ParseResult result;
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    result.message = app.help();
    return result;
  } catch (const CLI::ParseError& e) {
    result.message = std::string("scene_runner: ") + e.what() + "\nRun with --help for the options.";
    result.exitCode = 2;
    return result;
  }
  if (!size.empty() && !parseSize(size, options.width, options.height)) {
    result.message = "scene_runner: --size: '" + size + "' is not WxH with 1 <= W,H <= " +
                     std::to_string(kMaxDimension);
    result.exitCode = 2;
    return result;
  }
  if (!options.screenshot.empty() && options.screenshot.extension() != ".png") {
    result.message = "scene_runner: --screenshot: '" + options.screenshot.string() + "' must end in .png";
    result.exitCode = 2;
    return result;
  }
  if (options.headless && options.frames == 0) options.frames = 1;
  if (options.scene.empty()) options.scene = defaultScenePath();
  result.options = options;
  return result;
}

}  // namespace runner
