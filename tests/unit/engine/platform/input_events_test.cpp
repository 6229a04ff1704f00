// The window's input from events (InputEvents -> InputState) and what the camera controllers make
// of it; and the key levels handed to Dear ImGui 1.86 (PolledKeyLevels). Found by driving the
// scene runner's window with xdotool under Xvfb, where a frame takes 50-500 ms: taps shorter than a
// frame were lost and a plain click after moving the mouse rotated the camera.
#include <gtest/gtest.h>

#include <vector>

#include <GLFW/glfw3.h>
#include <glm/glm.hpp>

#include "engine/platform/camera_controller.h"
#include "engine/platform/input_events.h"

namespace engine::platform {
namespace {

constexpr KeyAction kPress = KeyAction::Press;
constexpr KeyAction kRelease = KeyAction::Release;

// Tricky: a key pressed and released between two polls (xdotool's 12 ms tap, a frame of 200 ms)
// is up when the frame looks; it must still count as pressed for that frame, and only that one.
TEST(InputEvents, ATapWithinOneFrameIsAPress) {
  InputEvents events;
  events.onKey(GLFW_KEY_F1, kPress);
  events.onKey(GLFW_KEY_F1, kRelease);
  const InputState tapped = events.endFrame();
  EXPECT_TRUE(tapped.keysPressed[GLFW_KEY_F1]);
  EXPECT_TRUE(tapped.keys[GLFW_KEY_F1]);
  const InputState next = events.endFrame();
  EXPECT_FALSE(next.keysPressed[GLFW_KEY_F1]);
  EXPECT_FALSE(next.keys[GLFW_KEY_F1]);
}

// Tricky: press, release, press within one frame ends with the key down: it is pressed in that
// frame and held (not pressed again) in the next; the release between must not clear it.
TEST(InputEvents, PressReleasePressInOneFrameIsPressedThenHeld) {
  InputEvents events;
  events.onKey(GLFW_KEY_W, kPress);
  events.onKey(GLFW_KEY_W, kRelease);
  events.onKey(GLFW_KEY_W, kPress);
  const InputState first = events.endFrame();
  EXPECT_TRUE(first.keysPressed[GLFW_KEY_W]);
  EXPECT_TRUE(first.keys[GLFW_KEY_W]);
  const InputState second = events.endFrame();
  EXPECT_FALSE(second.keysPressed[GLFW_KEY_W]);
  EXPECT_TRUE(second.keys[GLFW_KEY_W]);
}

// Tricky: a held key's auto-repeat must not toggle F1 again (a repeat is not a press), and key
// codes GLFW cannot name (GLFW_KEY_UNKNOWN, -1) or past the table must not write outside it.
TEST(InputEvents, RepeatsAndUnknownKeysAreNotPresses) {
  InputEvents events;
  events.onKey(GLFW_KEY_F1, kPress);
  events.endFrame();
  events.onKey(GLFW_KEY_F1, KeyAction::Repeat);
  events.onKey(GLFW_KEY_UNKNOWN, kPress);
  events.onKey(InputState::kKeyCount, kPress);
  const InputState held = events.endFrame();
  EXPECT_FALSE(held.keysPressed[GLFW_KEY_F1]);
  EXPECT_TRUE(held.keys[GLFW_KEY_F1]);
  for (bool pressed : held.keysPressed) EXPECT_FALSE(pressed);
}

// Tricky (the click that rotated the view): the mouse moves with no button down, then the left
// button is pressed, all before the next poll. The frame sees the button down and the cursor
// moved, but the move was before the press: no drag, and the orbit camera must stay put.
TEST(InputEvents, AMoveThenAClickIsNotADrag) {
  InputEvents events;
  events.setCursor({100.0f, 100.0f});
  events.onCursor({400.0f, 300.0f});
  events.onButton(kMouseLeft, kPress);
  const InputState input = events.endFrame();
  EXPECT_TRUE(input.leftButton);
  EXPECT_TRUE(input.leftPressed);
  EXPECT_EQ(input.cursorDelta, glm::vec2(300.0f, 200.0f));  // the cursor did move
  EXPECT_EQ(input.leftDrag, glm::vec2(0.0f));
  OrbitController orbit;
  const glm::vec3 eye = orbit.eye();
  EXPECT_FALSE(orbit.update(input));
  EXPECT_EQ(orbit.eye(), eye);
}

// Tricky: the other half of the same rule: motion after the press, while the button is held, is
// a drag, in the press's frame and in the frames after it (the orbit turns).
TEST(InputEvents, MotionWhileHeldIsADrag) {
  InputEvents events;
  events.setCursor({10.0f, 10.0f});
  events.onCursor({50.0f, 10.0f});  // before the press: not the drag
  events.onButton(kMouseLeft, kPress);
  events.onCursor({60.0f, 15.0f});
  InputState input = events.endFrame();
  EXPECT_EQ(input.leftDrag, glm::vec2(10.0f, 5.0f));
  events.onCursor({40.0f, 15.0f});
  input = events.endFrame();
  EXPECT_TRUE(input.leftButton);
  EXPECT_FALSE(input.leftPressed);
  EXPECT_EQ(input.leftDrag, glm::vec2(-20.0f, 0.0f));
  OrbitController orbit;
  const float yaw = orbit.yaw;
  EXPECT_TRUE(orbit.update(input));
  EXPECT_GT(orbit.yaw, yaw);  // dragged left: yaw -= dx * speed
}

// Tricky: a drag released mid-frame keeps the motion before the release (the end of a quick
// flick), and the motion after it is not dragged; the button still reads as down for that frame
// (it was down in it) and is up in the next.
TEST(InputEvents, AReleaseMidFrameKeepsTheMotionBeforeIt) {
  InputEvents events;
  events.setCursor({0.0f, 0.0f});
  events.onButton(kMouseMiddle, kPress);
  events.onCursor({8.0f, 0.0f});
  events.onButton(kMouseMiddle, kRelease);
  events.onCursor({30.0f, 4.0f});
  InputState input = events.endFrame();
  EXPECT_TRUE(input.middleButton);
  EXPECT_EQ(input.middleDrag, glm::vec2(8.0f, 0.0f));
  EXPECT_EQ(input.cursorDelta, glm::vec2(30.0f, 4.0f));
  events.onCursor({35.0f, 4.0f});
  input = events.endFrame();
  EXPECT_FALSE(input.middleButton);
  EXPECT_EQ(input.middleDrag, glm::vec2(0.0f));
}

// Tricky: each button drags only while it is itself down: right pressed during a left drag gets
// only the motion after its press (fly look must not take the left drag's motion), and a click
// shorter than a frame is seen as pressed.
TEST(InputEvents, EachButtonDragsOnlyWhileItIsDown) {
  InputEvents events;
  events.setCursor({0.0f, 0.0f});
  events.onButton(kMouseLeft, kPress);
  events.onCursor({5.0f, 0.0f});
  events.onButton(kMouseRight, kPress);
  events.onCursor({5.0f, 7.0f});
  events.onButton(kMouseMiddle, kPress);
  events.onButton(kMouseMiddle, kRelease);
  const InputState input = events.endFrame();
  EXPECT_EQ(input.leftDrag, glm::vec2(5.0f, 7.0f));
  EXPECT_EQ(input.rightDrag, glm::vec2(0.0f, 7.0f));
  EXPECT_EQ(input.middleDrag, glm::vec2(0.0f));
  EXPECT_TRUE(input.middleButton);
  EXPECT_TRUE(input.middlePressed);
}

// Tricky: the first cursor event of a window whose position was never set has nothing to move
// from: it is the position, not a jump from (0, 0) that a held button would drag.
TEST(InputEvents, TheFirstCursorPositionIsNotMotion) {
  InputEvents events;
  events.onButton(kMouseLeft, kPress);
  events.onCursor({600.0f, 400.0f});
  const InputState input = events.endFrame();
  EXPECT_EQ(input.cursor, glm::vec2(600.0f, 400.0f));
  EXPECT_EQ(input.cursorDelta, glm::vec2(0.0f));
  EXPECT_EQ(input.leftDrag, glm::vec2(0.0f));
}

// Tricky: several wheel steps between two polls add up (none lost to a long frame), and the next
// frame starts from zero (the orbit must not keep zooming).
TEST(InputEvents, ScrollAddsUpWithinAFrameAndResets) {
  InputEvents events;
  events.onScroll(1.0f);
  events.onScroll(1.0f);
  events.onScroll(-0.5f);
  EXPECT_FLOAT_EQ(events.endFrame().scrollDelta, 1.5f);
  EXPECT_FLOAT_EQ(events.endFrame().scrollDelta, 0.0f);
}

// Tricky: W tapped within one frame moves the fly camera for that frame (it was lost), but not
// while the UI has the keyboard (typing a W into a text field must not fly).
TEST(InputEvents, AMovementKeyTapFliesUnlessTheUiHasTheKeyboard) {
  InputEvents events;
  events.onKey(GLFW_KEY_W, kPress);
  events.onKey(GLFW_KEY_W, kRelease);
  InputState input = events.endFrame();
  FlyController fly;
  const glm::vec3 start = fly.position;
  EXPECT_TRUE(fly.update(input, 0.1f));
  EXPECT_NE(fly.position, start);

  events.onKey(GLFW_KEY_W, kPress);
  events.onKey(GLFW_KEY_W, kRelease);
  input = events.endFrame();
  input.uiWantsKeyboard = true;
  const glm::vec3 before = fly.position;
  EXPECT_FALSE(fly.update(input, 0.1f));
  EXPECT_EQ(fly.position, before);
}

// Tricky: fly look is a right drag: moving the mouse and then pressing the right button must not
// turn the view (the same bug as the orbit's click), while moving with it held does.
TEST(InputEvents, FlyLookTurnsOnlyForMotionWithTheRightButtonDown) {
  InputEvents events;
  events.setCursor({0.0f, 0.0f});
  events.onCursor({250.0f, 90.0f});
  events.onButton(kMouseRight, kPress);
  FlyController fly;
  const float yaw = fly.yaw, pitch = fly.pitch;
  EXPECT_FALSE(fly.update(events.endFrame(), 0.016f));
  EXPECT_EQ(fly.yaw, yaw);
  EXPECT_EQ(fly.pitch, pitch);
  events.onCursor({270.0f, 90.0f});
  EXPECT_TRUE(fly.update(events.endFrame(), 0.016f));
  EXPECT_NE(fly.yaw, yaw);
}

// The levels PolledKeyLevels shows over a run of frames, each frame's events given as a string:
// 'p' press, 'r' release.
std::vector<bool> levels(const std::vector<const char*>& frames, int key) {
  InputEvents events;
  PolledKeyLevels polled;
  std::vector<bool> out;
  for (const char* frame : frames) {
    for (const char* c = frame; *c; ++c) events.onKey(key, *c == 'p' ? kPress : kRelease);
    polled.update(events.endFrame());
    out.push_back(polled.down(key));
  }
  return out;
}

// Tricky (ImGui 1.86 reads io.KeysDown once a frame): Return tapped within one frame must show
// down for one frame, so that ImGui sees the press, then up (the release one frame late).
TEST(PolledKeyLevels, ATapWithinOneFrameIsDownForOneFrame) {
  EXPECT_EQ(levels({"pr", "", ""}, GLFW_KEY_ENTER), (std::vector<bool>{true, false, false}));
}

// Tricky: taps in two frames in a row: stretched naively the key would look held for two frames
// (one press); a frame up must come between, so the second tap is shown one frame later.
TEST(PolledKeyLevels, TapsInConsecutiveFramesAreTwoPresses) {
  EXPECT_EQ(levels({"pr", "pr", "", ""}, GLFW_KEY_BACKSPACE), (std::vector<bool>{true, false, true, false}));
}

// Tricky: a key held over frames is down throughout and up from the frame of its release (no
// delay for a release that is not in the press's frame); a press-release-press in one frame shows
// as a press that is then held.
TEST(PolledKeyLevels, AHeldKeyIsDownUntilItsRelease) {
  EXPECT_EQ(levels({"p", "", "", "r", ""}, GLFW_KEY_LEFT), (std::vector<bool>{true, true, true, false, false}));
  EXPECT_EQ(levels({"prp", "", "r"}, GLFW_KEY_LEFT), (std::vector<bool>{true, true, false}));
}

// Tricky: a release and a new press in one frame while the key was shown down (held, then tapped
// again quickly): the consumer must see it go up and down again, not one long hold.
TEST(PolledKeyLevels, AReleaseAndPressWhileHeldShowsUpThenDown) {
  EXPECT_EQ(levels({"p", "rp", "", "r"}, GLFW_KEY_DELETE), (std::vector<bool>{true, false, true, false}));
}

}  // namespace
}  // namespace engine::platform
