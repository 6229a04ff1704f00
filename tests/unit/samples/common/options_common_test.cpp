// The samples' shared command-line pieces (samples/common/options_common.h): the one size parser
// and its bounds, --size and --device through CLI11, the default scene, and the parse's help and
// error results that both programs return as they are.
#include "options_common.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

namespace samples {
namespace {

ImageSize parsedSize(std::string_view text, std::uint32_t maxSide = kMaxImageDimension) {
  const auto size = parseImageSize("--size", text, maxSide);
  EXPECT_TRUE(size.ok()) << text << ": " << size.error().message;
  return size.ok() ? *size : ImageSize{};
}

std::string refusal(std::string_view text, std::uint32_t maxSide = kMaxImageDimension) {
  const auto size = parseImageSize("--size", text, maxSide);
  EXPECT_FALSE(size.ok()) << text << " was accepted as " << size->width << "x" << size->height;
  return size.ok() ? std::string() : size.error().message;
}

// Tricky: both bounds are inside (1 and the largest side), the separator may be a capital X
// ("1920X1080" as people type it), and leading zeros are digits, not octal.
TEST(OptionsCommon, SizeAcceptsWxHWithinTheBounds) {
  const ImageSize size = parsedSize("64x32");
  EXPECT_EQ(size.width, 64u);
  EXPECT_EQ(size.height, 32u);
  const ImageSize capital = parsedSize("1920X1080");
  EXPECT_EQ(capital.width, 1920u);
  EXPECT_EQ(capital.height, 1080u);
  const ImageSize edges = parsedSize("16384x1");
  EXPECT_EQ(edges.width, 16384u);
  EXPECT_EQ(edges.height, 1u);
  const ImageSize zeros = parsedSize("0640x010");
  EXPECT_EQ(zeros.width, 640u);
  EXPECT_EQ(zeros.height, 10u);
}

// Tricky: each is a near miss a lenient parser takes. A missing side ("1920x", "x1080") must not
// read as 0 or as the other side; a sign ("+5x3") or a leading space (" 640x480") passes strtoul
// and from_chars-after-skipping; a suffix ("640x480junk") passes a parser that stops at the first
// non-digit; two separators ("2x3x4") pass one that splits at the last x.
TEST(OptionsCommon, SizeRefusesWhatIsNotWxHNamingTheOptionAndTheText) {
  for (const char* bad : {"1920x", "x1080", "+5x3", "5x+3", "-5x5", " 640x480", "640x480 ", "640x480junk", "640 x 480",
                          "2x3x4", "wide", "x", "", "1920*1080", "0x1p3"}) {
    EXPECT_EQ(refusal(bad), "--size: '" + std::string(bad) + "' is not WxH (two whole numbers joined by x, e.g. 1280x720)");
  }
}

// Tricky: "99999999999x1" overflows 32 bits (a parser into uint32 wraps it to a plausible width)
// and a run of digits past 64 bits makes from_chars fail: both are out of range, not malformed,
// and 0 on either side is refused though it is digits.
TEST(OptionsCommon, SizeRefusesZeroAndOversizeNamingTheLimit) {
  for (const char* bad : {"0x0", "0x100", "100x0", "16385x1", "1x16385", "100000x100000", "99999999999x1",
                          "1x4294967297", "123456789012345678901234567890x1"}) {
    EXPECT_EQ(refusal(bad), "--size: '" + std::string(bad) + "' is out of range: width and height must be 1..16384");
  }
}

// Tricky: a window's limit is smaller than an image's; the limit is the caller's, in the message too.
TEST(OptionsCommon, SizeTakesTheCallersLimit) {
  EXPECT_EQ(parsedSize("4096x4096", kMaxWindowDimension).width, 4096u);
  const auto window = parseImageSize("size", "4097x1", kMaxWindowDimension);
  ASSERT_FALSE(window.ok());
  EXPECT_EQ(window.error().message, "size: '4097x1' is out of range: width and height must be 1..4096");
}

std::optional<ParseStop> parse(CLI::App& app, std::vector<const char*> args) {
  args.insert(args.begin(), "prog");
  return parseCommandLine(app, "prog", int(args.size()), args.data());
}

// Tricky: a refused --size or --device must stop the parse with the parser's own message (not
// CLI11's generic one) and leave the defaults in place; --size given nowhere keeps the default.
TEST(OptionsCommon, SizeAndDeviceOptionsParseThroughTheSharedParsers) {
  std::uint32_t width = 7, height = 9;
  engine::gpu::DevicePreference device = engine::gpu::DevicePreference::Auto;
  {
    CLI::App app{"a test program", "prog"};
    addSizeOption(app, width, height, "size");
    addDeviceOption(app, device);
    EXPECT_FALSE(parse(app, {}).has_value());
    EXPECT_EQ(width, 7u);
    EXPECT_EQ(device, engine::gpu::DevicePreference::Auto);
    EXPECT_FALSE(parse(app, {"--size", "320X180", "--device", "lavapipe"}).has_value());
    EXPECT_EQ(width, 320u);
    EXPECT_EQ(height, 180u);
    EXPECT_EQ(device, engine::gpu::DevicePreference::Software);
  }
  for (const auto& [args, message] :
       {std::pair{std::vector<const char*>{"--size", "0x5"}, "prog: --size: '0x5' is out of range: width and height "
                                                             "must be 1..16384\nRun with --help for the options."},
        std::pair{std::vector<const char*>{"--device", "GPU"},
                  "prog: --device: 'GPU' is not one of auto, gpu, lavapipe\nRun with --help for the options."}}) {
    CLI::App app{"a test program", "prog"};
    std::uint32_t w = 7, h = 9;
    engine::gpu::DevicePreference d = engine::gpu::DevicePreference::Hardware;
    addSizeOption(app, w, h, "size");
    addDeviceOption(app, d);
    const std::optional<ParseStop> stop = parse(app, args);
    ASSERT_TRUE(stop.has_value()) << args[0];
    EXPECT_EQ(stop->exitCode, 2);
    EXPECT_EQ(stop->message, message);
    EXPECT_EQ(w, 7u);
    EXPECT_EQ(d, engine::gpu::DevicePreference::Hardware);
  }
}

TEST(OptionsCommon, DefaultSceneFollowsTheAssetDirectory) {
  const char* was = std::getenv("HSDF_ASSET_DIR");
  const std::string saved = was ? was : "";
  ASSERT_EQ(setenv("HSDF_ASSET_DIR", "/somewhere/assets", 1), 0);
  EXPECT_EQ(defaultScenePath(), std::filesystem::path("/somewhere/assets/bunny.glb"));
  ASSERT_EQ(unsetenv("HSDF_ASSET_DIR"), 0);
  const std::filesystem::path bundled = defaultScenePath();
  EXPECT_EQ(bundled.filename(), "bunny.glb");
  EXPECT_TRUE(std::filesystem::exists(bundled)) << bundled << ": the source tree's bunny";
  if (was) setenv("HSDF_ASSET_DIR", saved.c_str(), 1);
}

TEST(OptionsCommon, ParseGivesHelpErrorsOrNothing) {
  int value = 0;
  CLI::App app{"a test program", "prog"};
  app.add_option("--value", value, "a number");
  EXPECT_FALSE(parse(app, {"--value", "3"}).has_value());
  EXPECT_EQ(value, 3);

  const std::optional<ParseStop> help = parse(app, {"--help"});
  ASSERT_TRUE(help.has_value());
  EXPECT_EQ(help->exitCode, 0);
  EXPECT_NE(help->message.find("--value"), std::string::npos) << help->message;

  const std::optional<ParseStop> bad = parse(app, {"--value", "three"});
  ASSERT_TRUE(bad.has_value());
  EXPECT_EQ(bad->exitCode, 2);
  EXPECT_EQ(bad->message.rfind("prog: ", 0), 0u) << bad->message;
  EXPECT_NE(bad->message.find("--value"), std::string::npos) << bad->message;
  EXPECT_NE(bad->message.find("\nRun with --help for the options."), std::string::npos) << bad->message;

  const ParseResult<int> result = stoppedWith<int>(parseError("prog", "--x: no"));
  EXPECT_FALSE(result.options.has_value());
  EXPECT_EQ(result.message, "prog: --x: no");
  EXPECT_EQ(result.exitCode, 2);
}

}  // namespace
}  // namespace samples
