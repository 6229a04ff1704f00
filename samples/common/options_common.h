#pragma once
// What the samples' command lines (scene_runner, perf_capture) share: the result of parsing, the
// parse itself with --help and CLI11's errors, --size and the default scene. Each program keeps
// its own options; the words of help and errors are the same in both.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace CLI {
class App;
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

// --size: "WxH" (or "Wxh") with 1 <= W, H <= kMaxImageDimension into width and height, else the
// message naming the option.
inline constexpr std::uint32_t kMaxImageDimension = 16384;
std::optional<std::string> parseSize(const std::string& text, std::uint32_t& width, std::uint32_t& height);

}  // namespace samples
