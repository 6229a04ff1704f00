#pragma once
// What the samples' command lines (scene_runner, perf_capture) share: the result of parsing, the
// parse itself with --help and CLI11's errors, --size, --device and the default scene. Each
// program keeps its own options; the words of help and errors are the same in both.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "engine/core/expected.h"
#include "engine/gpu/device_names.h"

namespace CLI {
class App;
class Option;
}

namespace samples {

// A command line that gives no options: the help text (exit code 0), or an error naming the bad
// option as "<program>: ..." (exit code 2).
struct ParseStop {
  std::string message;
  int exitCode = 0;
};
ParseStop parseError(std::string_view program, std::string_view message);

// Runs app.parse: nullopt when the command line parsed (the program's own checks follow), else the
// help text on --help, or CLI11's error and "Run with --help for the options.".
std::optional<ParseStop> parseCommandLine(CLI::App& app, std::string_view program, int argc, const char* const* argv);

// What a program's parseOptions returns: the options, or the message of a ParseStop.
template <class Options>
struct ParseResult {
  std::optional<Options> options;
  std::string message;  // help text or error
  int exitCode = 0;
};
template <class Options>
ParseResult<Options> stoppedWith(ParseStop stop) {
  return {std::nullopt, std::move(stop.message), stop.exitCode};
}

// The bundled bunny: $HSDF_ASSET_DIR/bunny.glb when set (tests, installed samples), else the one of
// the source tree (samples/assets).
std::filesystem::path defaultScenePath();

// An image's size in pixels.
struct ImageSize {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
};

// The one parser of a size "WxH" (or "WXH"): two runs of decimal digits, nothing else (no sign, no
// space, no suffix), each 1..maxSide. The error names the option and the text as given:
// "--size: '0x0' is out of range: width and height must be 1..16384". The programs' --size takes
// kMaxImageDimension; a window (scripts' size=, the soak) takes what a window can be.
inline constexpr std::uint32_t kMaxImageDimension = 16384;
inline constexpr std::uint32_t kMaxWindowDimension = 4096;
engine::Expected<ImageSize> parseImageSize(std::string_view option, std::string_view text,
                                           std::uint32_t maxSide = kMaxImageDimension);

// The programs' --size: parseImageSize into width and height (left as they are when not given),
// refused through CLI11 (parseCommandLine's message) naming the option and the value.
CLI::Option* addSizeOption(CLI::App& app, std::uint32_t& width, std::uint32_t& height, const std::string& help);

// The programs' --device: one of engine::gpu::kDeviceNameList into `device`, refused through
// CLI11 (parseCommandLine's message) naming the option and the value.
CLI::Option* addDeviceOption(CLI::App& app, engine::gpu::DevicePreference& device);

}  // namespace samples
