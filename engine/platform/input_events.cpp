#include "engine/platform/input_events.h"

namespace engine::platform {

void InputEvents::onKey(int key, KeyAction action) {
  if (key < 0 || key >= InputState::kKeyCount) return;
  if (action == KeyAction::Press) {
    keyHeld_[key] = true;
    keyPressed_[key] = true;
  } else if (action == KeyAction::Release) {
    keyHeld_[key] = false;  // a press earlier in this frame still counts
  }
}

void InputEvents::onButton(int button, KeyAction action) {
  if (button < 0 || button >= kButtonCount) return;
  if (action == KeyAction::Press) {
    buttonHeld_[button] = true;
    buttonPressed_[button] = true;
  } else if (action == KeyAction::Release) {
    buttonHeld_[button] = false;
  }
}

void InputEvents::onCursor(glm::vec2 position) {
  if (!cursorKnown_) return setCursor(position);
  const glm::vec2 delta = position - cursor_;
  motion_ += delta;
  // Only a button down while the cursor moved drags: the motion before its press is not its drag.
  for (int b = 0; b < kButtonCount; ++b)
    if (buttonHeld_[b]) drag_[b] += delta;
  cursor_ = position;
}

void InputEvents::setCursor(glm::vec2 position) {
  cursor_ = position;
  cursorKnown_ = true;
}

void InputEvents::onScroll(float dy) { scroll_ += dy; }

InputState InputEvents::endFrame() {
  InputState state;
  state.cursor = cursor_;
  state.cursorDelta = motion_;
  state.leftDrag = drag_[kMouseLeft];
  state.rightDrag = drag_[kMouseRight];
  state.middleDrag = drag_[kMouseMiddle];
  state.scrollDelta = scroll_;
  state.leftButton = buttonHeld_[kMouseLeft] || buttonPressed_[kMouseLeft];
  state.rightButton = buttonHeld_[kMouseRight] || buttonPressed_[kMouseRight];
  state.middleButton = buttonHeld_[kMouseMiddle] || buttonPressed_[kMouseMiddle];
  state.leftPressed = buttonPressed_[kMouseLeft];
  state.rightPressed = buttonPressed_[kMouseRight];
  state.middlePressed = buttonPressed_[kMouseMiddle];
  for (int key = 0; key < InputState::kKeyCount; ++key) {
    state.keys[key] = keyHeld_[key] || keyPressed_[key];
    state.keysPressed[key] = keyPressed_[key];
    keyPressed_[key] = false;
  }
  for (int b = 0; b < kButtonCount; ++b) {
    buttonPressed_[b] = false;
    drag_[b] = glm::vec2(0.0f);
  }
  motion_ = glm::vec2(0.0f);
  scroll_ = 0.0f;
  return state;
}

void PolledKeyLevels::update(const InputState& input) {
  for (int key = 0; key < InputState::kKeyCount; ++key) {
    pending_[key] = pending_[key] || input.keysPressed[key];
    if (shown_[key]) {
      // Shown down last frame: a press since then needs a frame up first (it came after a
      // release), else the key shows as it is (without a press this frame, keys[] is its level).
      shown_[key] = pending_[key] ? false : input.keys[key];
    } else if (pending_[key]) {
      shown_[key] = true;  // down for this frame at least, even if already released
      pending_[key] = false;
    } else {
      shown_[key] = input.keys[key];
    }
  }
}

}  // namespace engine::platform
