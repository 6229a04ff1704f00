#include "options_common.h"

#include <cstdlib>
#include <regex>

#include <CLI/CLI.hpp>

namespace samples {

ParseStop parseError(std::string_view program, std::string_view message) {
  return {std::string(program) + ": " + std::string(message), 2};
}

std::optional<ParseStop> parseCommandLine(CLI::App& app, std::string_view program, int argc, const char* const* argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    return ParseStop{app.help(), 0};
  } catch (const CLI::ParseError& e) {
    return parseError(program, std::string(e.what()) + "\nRun with --help for the options.");
  }
  return std::nullopt;
}

std::filesystem::path defaultScenePath() {
  if (const char* dir = std::getenv("HSDF_ASSET_DIR"); dir && *dir) return std::filesystem::path(dir) / "bunny.glb";
  return std::filesystem::path(HSDF_DEFAULT_ASSET_DIR) / "bunny.glb";
}

std::optional<std::string> parseSize(const std::string& text, std::uint32_t& width, std::uint32_t& height) {
  static const std::regex pattern(R"((\d{1,6})[xX](\d{1,6}))");
  std::smatch match;
  if (std::regex_match(text, match, pattern)) {
    const unsigned long w = std::stoul(match[1]), h = std::stoul(match[2]);
    if (w >= 1 && h >= 1 && w <= kMaxImageDimension && h <= kMaxImageDimension) {
      width = std::uint32_t(w);
      height = std::uint32_t(h);
      return std::nullopt;
    }
  }
  return "--size: '" + text + "' is not WxH with 1 <= W,H <= " + std::to_string(kMaxImageDimension);
}

}  // namespace samples
