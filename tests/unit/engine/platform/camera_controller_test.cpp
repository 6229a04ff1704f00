// The camera controllers the scene runner's window drives, and the framing every program shares
// (scene runner --view, perf capture views, tests): what a user would notice if they broke.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <GLFW/glfw3.h>
#include <glm/glm.hpp>

#include "engine/core/math.h"
#include "engine/platform/camera_controller.h"

namespace engine::platform {
namespace {

std::vector<glm::vec3> corners(const glm::vec3& lo, const glm::vec3& hi) {
  std::vector<glm::vec3> out;
  for (int i = 0; i < 8; ++i) out.push_back({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
  return out;
}

// The largest angle between the view axis (eye -> target) and the direction to a corner.
float widestCornerAngle(const OrbitController& orbit, const glm::vec3& lo, const glm::vec3& hi) {
  const glm::vec3 axis = glm::normalize(orbit.target - orbit.eye());
  float widest = 0.0f;
  for (const glm::vec3& c : corners(lo, hi))
    widest = std::max(widest, std::acos(std::clamp(glm::dot(axis, glm::normalize(c - orbit.eye())), -1.0f, 1.0f)));
  return widest;
}

// Tricky: the box must fit whatever its scale (a scene in millimetres, one a kilometre across, a
// flat box) and from each of the 8 views; checked by the angle of every corner seen from the eye,
// which must stay inside the half field of view (a cone inside the frustum of any aspect >= 1).
TEST(FramingOrbit, EveryViewSeesTheWholeBoxAtAnyScale) {
  const float fovY = 0.8f;
  const std::vector<std::pair<glm::vec3, glm::vec3>> boxes = {
      {glm::vec3(-1.0f), glm::vec3(1.0f)},
      {glm::vec3(1e-3f, 2e-3f, 0.0f), glm::vec3(4e-3f, 3e-3f, 1e-3f)},
      {glm::vec3(-800.0f, 0.0f, -800.0f), glm::vec3(1200.0f, 5.0f, 900.0f)},
  };
  for (const auto& [lo, hi] : boxes) {
    for (int view = 0; view < 8; ++view) {
      const OrbitController orbit = framingOrbit(lo, hi, fovY, view);
      EXPECT_LT(widestCornerAngle(orbit, lo, hi), 0.5f * fovY) << "view " << view;
      // Not absurdly far either: the box fills a good part of the view.
      EXPECT_GT(widestCornerAngle(orbit, lo, hi), 0.2f * fovY) << "view " << view;
      EXPECT_NEAR(glm::length(orbit.eye() - orbit.target), orbit.radius, 1e-4f * orbit.radius);
    }
  }
}

// Tricky: a portrait image (width / height 0.28, as 90x320) has a horizontal field of view far
// narrower than fovY: framed by fovY alone, the bunny touched both sides of the image (found by a
// helper). Landscape images keep fovY's framing.
TEST(FramingOrbit, APortraitImageIsFramedByItsNarrowerFieldOfView) {
  const glm::vec3 lo(-1.0f), hi(1.0f);
  const float fovY = 0.8f, aspect = 90.0f / 320.0f;
  const float fovX = 2.0f * std::atan(std::tan(0.5f * fovY) * aspect);
  for (int view = 0; view < 8; ++view) {
    const OrbitController portrait = framingOrbit(lo, hi, fovY, view, aspect);
    EXPECT_LT(widestCornerAngle(portrait, lo, hi), 0.5f * fovX) << "view " << view;
    EXPECT_GT(widestCornerAngle(portrait, lo, hi), 0.2f * fovX) << "view " << view;
    EXPECT_EQ(framingOrbit(lo, hi, fovY, view, 16.0f / 9.0f).radius, framingOrbit(lo, hi, fovY, view).radius);
  }
}

// Tricky: the 8 views must be 8 different directions (the capture averages over them) and the
// index wraps, negative included, so --view 9 and --view -7 are view 1.
TEST(FramingOrbit, EightDistinctViewsAndTheIndexWraps) {
  const glm::vec3 lo(-1.0f), hi(1.0f);
  for (int a = 0; a < 8; ++a) {
    for (int b = a + 1; b < 8; ++b) {
      const glm::vec3 da = glm::normalize(framingOrbit(lo, hi, 0.8f, a).eye());
      const glm::vec3 db = glm::normalize(framingOrbit(lo, hi, 0.8f, b).eye());
      EXPECT_LT(glm::dot(da, db), 0.99f) << a << " and " << b;
    }
  }
  EXPECT_EQ(framingOrbit(lo, hi, 0.8f, 9).eye(), framingOrbit(lo, hi, 0.8f, 1).eye());
  EXPECT_EQ(framingOrbit(lo, hi, 0.8f, -7).eye(), framingOrbit(lo, hi, 0.8f, 1).eye());
}

// A box without extent (one point) still gets a finite, positive radius.
TEST(FramingOrbit, APointIsFramedAsABoxOneAcross) {
  const OrbitController orbit = framingOrbit(glm::vec3(2.0f), glm::vec3(2.0f), 0.8f);
  EXPECT_EQ(orbit.target, glm::vec3(2.0f));
  EXPECT_GT(orbit.radius, 0.5f);
  EXPECT_TRUE(std::isfinite(orbit.radius));
}

// Tricky: zooming must stop at the framing's limits (a user scrolling for a while must not end up
// inside the target or at infinity), and the pitch must stop short of the pole, where the view's
// up vector would flip.
TEST(OrbitController, ZoomAndPitchStopAtTheirLimits) {
  OrbitController orbit = framingOrbit(glm::vec3(-1.0f), glm::vec3(1.0f), 0.8f);
  InputState scroll;
  scroll.scrollDelta = 50.0f;
  for (int i = 0; i < 100; ++i) orbit.update(scroll);
  EXPECT_FLOAT_EQ(orbit.radius, orbit.minRadius);
  scroll.scrollDelta = -50.0f;
  for (int i = 0; i < 100; ++i) orbit.update(scroll);
  EXPECT_FLOAT_EQ(orbit.radius, orbit.maxRadius);

  InputState drag;
  drag.leftButton = true;
  drag.leftDrag = {0.0f, 1e4f};
  EXPECT_TRUE(orbit.update(drag));
  EXPECT_LT(orbit.pitch, 1.5708f);
  const glm::vec3 view = glm::normalize(orbit.target - orbit.eye());
  EXPECT_LT(std::abs(view.y), 0.9999f);  // lookAt with up = +Y stays defined
}

// Tricky: while the UI has the mouse (a slider is dragged), the camera must not move, and
// update() must say so (the runner redraws only on change).
TEST(OrbitController, IgnoresTheMouseWhileTheUiHasIt) {
  OrbitController orbit;
  const OrbitController before = orbit;
  InputState input;
  input.leftButton = true;
  input.middleButton = true;
  input.leftDrag = input.middleDrag = {30.0f, -20.0f};
  input.scrollDelta = 2.0f;
  input.uiWantsMouse = true;
  EXPECT_FALSE(orbit.update(input));
  EXPECT_EQ(orbit.eye(), before.eye());
  input.uiWantsMouse = false;
  EXPECT_TRUE(orbit.update(input));
  EXPECT_NE(orbit.eye(), before.eye());
}

// Dragging with the middle button pans: the target moves across the view, not along it.
TEST(OrbitController, PanMovesTheTargetAcrossTheView) {
  OrbitController orbit;
  const glm::vec3 axis = glm::normalize(orbit.target - orbit.eye());
  InputState input;
  input.middleButton = true;
  input.middleDrag = {40.0f, 25.0f};
  ASSERT_TRUE(orbit.update(input));
  const glm::vec3 moved = orbit.target - glm::vec3(0.0f);
  EXPECT_GT(glm::length(moved), 0.0f);
  EXPECT_NEAR(glm::dot(moved, axis), 0.0f, 1e-5f);
}

// W flies along the view direction at `speed` units per second (shift: 4x); S undoes it; the
// keyboard is ignored while the UI has it.
TEST(FlyController, FliesAtItsSpeedAlongTheView) {
  FlyController fly;
  fly.yaw = 0.4f;
  fly.pitch = -0.2f;
  fly.speed = 2.0f;
  const glm::vec3 start = fly.position;
  InputState input;
  input.keys[GLFW_KEY_W] = true;
  ASSERT_TRUE(fly.update(input, 0.5f));
  EXPECT_NEAR(glm::length(fly.position - start), 1.0f, 1e-5f);
  EXPECT_NEAR(glm::dot(glm::normalize(fly.position - start), fly.forward()), 1.0f, 1e-5f);
  input.keys[GLFW_KEY_LEFT_SHIFT] = true;
  fly.update(input, 0.5f);
  EXPECT_NEAR(glm::length(fly.position - start), 5.0f, 1e-4f);

  input = InputState{};
  input.keys[GLFW_KEY_S] = true;
  input.uiWantsKeyboard = true;
  const glm::vec3 held = fly.position;
  EXPECT_FALSE(fly.update(input, 1.0f));
  EXPECT_EQ(fly.position, held);
  EXPECT_NEAR(glm::length(fly.forward()), 1.0f, 1e-6f);
}

}  // namespace
}  // namespace engine::platform
