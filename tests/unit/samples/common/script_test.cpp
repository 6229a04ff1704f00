// Viewer test scripts (samples/common/script.h): what --script reads. The running side is covered
// by tests/gpu/run_panel_script_xvfb.sh; here the parser: a good script in order, and every bad
// line refused naming the file, the line and the problem before any frame is drawn.
#include <gtest/gtest.h>

#include "script.h"

namespace samples {
namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Tricky: comments (whole-line and trailing), blank lines, several commands per line, bare actions
// and two lines for the same frame must all survive, in order, with their line numbers.
TEST(Script, ParsesFramesAndCommandsInOrder) {
  const auto script = parseScript(
      "# header\n"
      "\n"
      "frame 0: panel=off method=trilinear  # trailing comment\n"
      "frame 3: resolution=32 wait-bake screenshot=out/a.png\n"
      "frame 3: cancel-bake size=200x100 view=7\n"
      "frame 4: scene-camera=front\n",
      "test.txt");
  ASSERT_TRUE(script.ok()) << script.error().message;
  ASSERT_EQ(script->frames.size(), 4u);
  EXPECT_EQ(script->frames[0].frame, 0u);
  ASSERT_EQ(script->frames[0].commands.size(), 2u);
  EXPECT_EQ(script->frames[0].commands[1].key, "method");
  EXPECT_EQ(script->frames[0].commands[1].value, "trilinear");
  EXPECT_EQ(script->frames[0].commands[1].line, 3);
  EXPECT_EQ(script->frames[1].commands[1].key, "wait-bake");
  EXPECT_EQ(script->frames[1].commands[1].value, "");
  EXPECT_EQ(script->frames[1].commands[2].value, "out/a.png");
  EXPECT_EQ(script->frames[2].frame, 3u);
  EXPECT_EQ(script->frames[3].commands[0].key, "scene-camera");  // the name is looked up when it runs
  EXPECT_EQ(script->frames[3].commands[0].value, "front");
  EXPECT_EQ(script->lastFrame(), 4u);
}

// Tricky: each mistake must be caught when the file is read (a typo found at frame 500 of a soak
// run wastes the run), naming file:line; tuning values go through the settings-file checks,
// including the resolution/padding rule with the padding the script set earlier.
TEST(Script, BadLinesNameFileLineAndProblem) {
  struct Case {
    const char* text;
    const char* expected;
  };
  const Case cases[] = {
      {"frame 1 method=cells\n", "s.txt:1: expected 'frame N: key=value ...'"},
      {"frame x: method=cells\n", "s.txt:1: 'x' is not a frame number"},
      {"frame 2: fp16=true\nframe 1: fp16=false\n", "s.txt:2: frame 1 comes after frame 2"},
      {"frame 0:\n", "s.txt:1: no commands"},
      {"frame 0: colour=red\n", "s.txt:1: unknown key 'colour'"},
      {"frame 0: subdivisions=0\n", "s.txt:1: setting 'subdivisions': 0 is outside 1..64"},
      {"frame 0: padding=4\nframe 1: resolution=8\n", "s.txt:2: --resolution 8 leaves no cells inside --padding 4"},
      {"frame 0: wait-bake=now\n", "s.txt:1: 'wait-bake' takes no value"},
      {"frame 0: screenshot\n", "s.txt:1: 'screenshot' needs a value"},
      {"frame 0: size=0x10\n", "s.txt:1: size: '0x10' is out of range: width and height must be 1..4096"},
      {"frame 0: panel=maybe\n", "s.txt:1: panel 'maybe' is not on or off"},
      {"frame 0: view=8\n", "s.txt:1: view '8' is not 0..7"},
      {"frame 0: camera=free\n", "s.txt:1: camera 'free' is not orbit or fly"},
      {"frame 0: reload-shaders=all\n", "s.txt:1: 'reload-shaders' takes no value"},
      {"frame 0: minimize=3\n", "s.txt:1: 'minimize' takes no value"},
      {"frame 0: fail-frame=oom\n", "s.txt:1: 'fail-frame' takes no value"},
      {"frame 0: shader-dir\n", "s.txt:1: 'shader-dir' needs a value"},
      {"frame 0: scene-camera\n", "s.txt:1: 'scene-camera' needs a value"},
      {"frame 0: present-fault=lost\n", "s.txt:1: present-fault 'lost' is not out-of-date or suboptimal"},
      {"frame 0: size=4097x1\n", "s.txt:1: size: '4097x1' is out of range: width and height must be 1..4096"},
      {"frame 0: split=both\n", "s.txt:1: setting 'split': \"both\" is not one of off, vertical, horizontal"},
  };
  for (const Case& c : cases) {
    const auto script = parseScript(c.text, "s.txt");
    ASSERT_FALSE(script.ok()) << c.text;
    EXPECT_TRUE(contains(script.error().message, c.expected)) << script.error().message;
  }
  const auto missing = loadScript("no_such_script.txt");
  ASSERT_FALSE(missing.ok());
  EXPECT_TRUE(contains(missing.error().message, "no_such_script.txt")) << missing.error().message;
}

// Tricky: settings that follow one another on a line are one change, checked together as a
// settings file's keys. From K = 16 (padding 1), "padding=16" alone leaves no cells inside the
// padding, so checking key by key refused "padding=16 resolution=40" but took the other order.
// An action between two settings still splits them: each part must stand on its own.
TEST(Script, SettingsOnALineAreCheckedTogether) {
  for (const char* line : {"frame 1: padding=16 resolution=40\n", "frame 1: resolution=40 padding=16\n"}) {
    const auto script = parseScript(std::string("frame 0: resolution=16\n") + line, "s.txt");
    EXPECT_TRUE(script.ok()) << line << script.error().message;
  }
  const auto split = parseScript("frame 0: resolution=16\nframe 1: padding=16 panel=on resolution=40\n", "s.txt");
  ASSERT_FALSE(split.ok());
  EXPECT_TRUE(contains(split.error().message, "s.txt:2: --resolution 16 leaves no cells inside --padding 16"))
      << split.error().message;
}

}  // namespace
}  // namespace samples
