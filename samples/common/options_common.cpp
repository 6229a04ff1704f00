#include "options_common.h"

#include <algorithm>
#include <charconv>
#include <cstdlib>

#include <fmt/format.h>

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

namespace {

bool allDigits(std::string_view text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

}  // namespace

engine::Expected<ImageSize> parseImageSize(std::string_view option, std::string_view text, std::uint32_t maxSide) {
  const std::string where = fmt::format("{}: '{}'", option, text);
  const std::size_t x = text.find_first_of("xX");
  const std::string_view w = text.substr(0, x), h = x == std::string_view::npos ? "" : text.substr(x + 1);
  if (!allDigits(w) || !allDigits(h))
    return engine::makeError(where + " is not WxH (two whole numbers joined by x, e.g. 1280x720)");
  // Digits past what 64 bits hold leave the value at 0: out of range as well.
  std::uint64_t width = 0, height = 0;
  std::from_chars(w.data(), w.data() + w.size(), width);
  std::from_chars(h.data(), h.data() + h.size(), height);
  if (width < 1 || height < 1 || width > maxSide || height > maxSide)
    return engine::makeError(fmt::format("{} is out of range: width and height must be 1..{}", where, maxSide));
  return ImageSize{std::uint32_t(width), std::uint32_t(height)};
}

CLI::Option* addSizeOption(CLI::App& app, std::uint32_t& width, std::uint32_t& height, const std::string& help) {
  const auto set = [&width, &height](const std::string& text) {
    auto parsed = parseImageSize("--size", text);
    if (!parsed) throw CLI::ValidationError(parsed.error().message);
    width = parsed->width;
    height = parsed->height;
  };
  return app.add_option_function<std::string>("--size", set, help);
}

CLI::Option* addDeviceOption(CLI::App& app, engine::gpu::DevicePreference& device) {
  const auto set = [&device](const std::string& text) {
    auto parsed = engine::gpu::parseDeviceName("--device", text);
    if (!parsed) throw CLI::ValidationError(parsed.error().message);
    device = *parsed;
  };
  return app.add_option_function<std::string>("--device", set,
                                              fmt::format("Vulkan device: {}", engine::gpu::kDeviceNameList));
}

}  // namespace samples
