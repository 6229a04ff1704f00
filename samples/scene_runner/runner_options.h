#pragma once
// Command line of the scene runner. Parsing is separate from running so that it can be tested and
// so that every option is validated (with a message naming it) before any window or device opens.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/expected.h"

namespace runner {

struct Options {
  std::filesystem::path scene;       // empty: the bundled bunny
  bool headless = false;
  std::uint32_t width = 1280;
  std::uint32_t height = 720;
  std::uint32_t frames = 0;          // 0: until the window closes (headless: 1)
  std::filesystem::path screenshot;  // PNG written after the last frame
  std::string device = "auto";       // auto | gpu | lavapipe
  bool validation = false;
  bool showUi = true;                // windowed: always; headless: drawn into the screenshot with --ui
  bool headlessUi = false;
  bool groundPlane = true;
};

// Parses argv. Returns the options, or an Error whose message names the bad option; `--help`
// yields an Error with `helpText` set and exit code 0.
struct ParseResult {
  std::optional<Options> options;
  std::string message;  // help text or error
  int exitCode = 0;
};
ParseResult parseOptions(int argc, const char* const* argv);

std::filesystem::path defaultScenePath();

}  // namespace runner
