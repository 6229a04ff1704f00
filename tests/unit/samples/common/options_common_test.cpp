// The samples' shared command-line pieces (samples/common/options_common.h): --size bounds, the
// default scene, and the parse's help and error results that both programs return as they are.
#include "options_common.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace samples {
namespace {

TEST(OptionsCommon, SizeAcceptsWxHWithinTheBounds) {
  std::uint32_t w = 0, h = 0;
  EXPECT_FALSE(parseSize("64x32", w, h).has_value());
  EXPECT_EQ(w, 64u);
  EXPECT_EQ(h, 32u);
  EXPECT_FALSE(parseSize("16384X1", w, h).has_value()) << "the largest width, capital X";
  EXPECT_EQ(w, 16384u);
  EXPECT_EQ(h, 1u);
}

// Tricky: a refused size must leave the previous one (a preset's) in place.
TEST(OptionsCommon, SizeRefusesZeroOversizeAndJunkNamingTheOption) {
  for (const char* bad : {"0x100", "100x0", "16385x1", "100000x100000", "12x", "wide", "-5x5", ""}) {
    std::uint32_t w = 7, h = 9;
    const std::optional<std::string> message = parseSize(bad, w, h);
    ASSERT_TRUE(message.has_value()) << bad;
    EXPECT_EQ(*message, "--size: '" + std::string(bad) + "' is not WxH with 1 <= W,H <= 16384");
    EXPECT_EQ(w, 7u) << bad;
    EXPECT_EQ(h, 9u) << bad;
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

std::optional<ParseStop> parse(CLI::App& app, std::vector<const char*> args) {
  args.insert(args.begin(), "prog");
  return parseCommandLine(app, "prog", int(args.size()), args.data());
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
