#pragma once
// Input from window events, gathered between two polls into the per-frame InputState the camera
// controllers and the programs read. Pure (no GLFW, no display) so that it can be unit-tested;
// engine::platform::Window feeds it from GLFW's callbacks (key and button codes are GLFW's).
//
// Why events and not the state at the poll: a frame can take 50-500 ms (lavapipe, a stall), and a
// key tapped or a button clicked between two polls is up again when the state is read, so the tap
// was lost; and the cursor's move since the last poll included the motion before a button was
// pressed, so a plain click after moving the mouse rotated the camera as a drag.
#include <cstdint>

#include <glm/glm.hpp>

namespace engine::platform {

struct InputState {
  static constexpr int kKeyCount = 512;  // GLFW key codes (GLFW_KEY_LAST is 348)

  glm::vec2 cursor{0.0f};  // where the cursor is, window pixels
  // All of the cursor's motion since the last poll, with or without a button: not a drag (the
  // motion before a click is in it). Camera gestures read the drags below.
  glm::vec2 cursorDelta{0.0f};
  // A drag: the motion since the last poll while that button was down (between its press and its
  // release; a press and release within one poll keep the motion between them).
  glm::vec2 leftDrag{0.0f};
  glm::vec2 rightDrag{0.0f};
  glm::vec2 middleDrag{0.0f};
  float scrollDelta = 0.0f;  // wheel steps since the last poll (+ away from the user)
  // Down now, or pressed since the last poll (a click shorter than a frame is still seen).
  bool leftButton = false;
  bool rightButton = false;
  bool middleButton = false;
  // Pressed at least once since the last poll (the press edge).
  bool leftPressed = false;
  bool rightPressed = false;
  bool middlePressed = false;
  bool keys[kKeyCount] = {};         // down now, or pressed since the last poll (held keys move the fly camera)
  bool keysPressed[kKeyCount] = {};  // pressed at least once since the last poll (toggles: F1, F2, ...)
  bool uiWantsMouse = false;         // set by the UI layer: the camera ignores the mouse then
  bool uiWantsKeyboard = false;
};

// Key and button actions, numbered as GLFW's (window.cpp checks that they match).
enum class KeyAction : int { Release = 0, Press = 1, Repeat = 2 };

// Mouse buttons as GLFW numbers them.
inline constexpr int kMouseLeft = 0;
inline constexpr int kMouseRight = 1;
inline constexpr int kMouseMiddle = 2;

class InputEvents {
 public:
  // Codes outside 0..kKeyCount-1 (GLFW_KEY_UNKNOWN) are ignored; a repeat is neither a press nor
  // a change of state.
  void onKey(int key, KeyAction action);
  void onButton(int button, KeyAction action);
  // The cursor's new position; its motion from the last position counts for every button down.
  void onCursor(glm::vec2 position);
  // The cursor's position without motion (where it is when the window opens).
  void setCursor(glm::vec2 position);
  void onScroll(float dy);
  // The input since the last endFrame() (ui flags false); starts the next frame's gathering.
  InputState endFrame();

 private:
  static constexpr int kButtonCount = 3;  // left, right, middle

  bool keyHeld_[InputState::kKeyCount] = {};
  bool keyPressed_[InputState::kKeyCount] = {};
  bool buttonHeld_[kButtonCount] = {};
  bool buttonPressed_[kButtonCount] = {};
  glm::vec2 drag_[kButtonCount] = {glm::vec2(0.0f), glm::vec2(0.0f), glm::vec2(0.0f)};
  glm::vec2 cursor_{0.0f};
  glm::vec2 motion_{0.0f};
  bool cursorKnown_ = false;
  float scroll_ = 0.0f;
};

// The key levels to hand a consumer that reads keys as down/up once a frame (Dear ImGui 1.86's
// io.KeysDown: its GLFW backend writes the state at each event, so a key pressed and released
// between two frames is up again when ImGui looks, and the press is never seen; 1.87 queues
// events instead). Every press is shown down for at least one frame, and a key pressed again after
// it was shown down is shown up for one frame first, so two quick taps are two presses:
//   tap within one frame  -> down this frame, up the next (the release is delivered a frame late)
//   taps in two frames    -> down, up, down, up
//   held                  -> down while held
// Two presses within the same frame are seen as one.
class PolledKeyLevels {
 public:
  // Call once per frame with the frame's input; then down() gives the levels to show.
  void update(const InputState& input);
  bool down(int key) const { return key >= 0 && key < InputState::kKeyCount && shown_[key]; }

 private:
  bool shown_[InputState::kKeyCount] = {};
  bool pending_[InputState::kKeyCount] = {};  // a press not shown yet
};

}  // namespace engine::platform
