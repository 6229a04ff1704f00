#include "engine/platform/camera_controller.h"

#include <algorithm>
#include <cmath>

#include <GLFW/glfw3.h>

#include "engine/core/math.h"

namespace engine::platform {
namespace {
constexpr float kMaxPitch = 1.55f;
}

bool OrbitController::update(const InputState& input) {
  bool moved = false;
  if (!input.uiWantsMouse) {
    if (input.leftDrag.x != 0.0f || input.leftDrag.y != 0.0f) {
      yaw -= input.leftDrag.x * rotateSpeed;
      pitch = std::clamp(pitch + input.leftDrag.y * rotateSpeed, -kMaxPitch, kMaxPitch);
      moved = true;
    }
    if (input.scrollDelta != 0.0f) {
      radius = std::clamp(radius * std::exp(-input.scrollDelta * zoomSpeed), minRadius, maxRadius);
      moved = true;
    }
    if (input.rightDrag.y != 0.0f) {
      radius = std::clamp(radius * std::exp(input.rightDrag.y * 0.01f), minRadius, maxRadius);
      moved = true;
    }
    if (input.middleDrag.x != 0.0f || input.middleDrag.y != 0.0f) {
      const glm::vec3 forward = glm::normalize(target - eye());
      const glm::vec3 right = glm::normalize(glm::cross(forward, glm::vec3(0, 1, 0)));
      const glm::vec3 up = glm::cross(right, forward);
      target += (-right * input.middleDrag.x + up * input.middleDrag.y) * radius * 0.002f;
      moved = true;
    }
  }
  return moved;
}

OrbitController framingOrbit(const glm::vec3& lo, const glm::vec3& hi, float fovY, int viewIndex, float aspect) {
  OrbitController orbit;
  orbit.target = 0.5f * (lo + hi);
  // In double: the float length of a box 1e20 across overflows (its squared length does).
  const double halfDiagonal = 0.5 * glm::length(glm::dvec3(hi) - glm::dvec3(lo));
  const double halfFov = aspect < 1.0f && aspect > 0.0f ? std::atan(std::tan(0.5 * double(fovY)) * double(aspect))
                                                        : 0.5 * double(fovY);
  const double radius = (halfDiagonal > 0.0 ? halfDiagonal : 0.5) / std::sin(halfFov) * 1.05;
  orbit.radius = float(radius);
  orbit.minRadius = float(1e-3 * radius);
  orbit.maxRadius = float(1e3 * radius);
  const int index = ((viewIndex % 8) + 8) % 8;
  orbit.yaw = 0.6f + float(index) * 0.78539816f;
  orbit.pitch = (index % 2 == 0) ? 0.35f : 0.61f;
  return orbit;
}

glm::vec3 OrbitController::eye() const { return math::orbitEye(target, radius, yaw, pitch); }

glm::vec3 FlyController::forward() const {
  return {std::cos(pitch) * -std::sin(yaw), std::sin(pitch), std::cos(pitch) * -std::cos(yaw)};
}

bool FlyController::update(const InputState& input, float dt) {
  bool moved = false;
  if (!input.uiWantsMouse && (input.rightDrag.x != 0.0f || input.rightDrag.y != 0.0f)) {
    yaw -= input.rightDrag.x * lookSpeed;
    pitch = std::clamp(pitch - input.rightDrag.y * lookSpeed, -kMaxPitch, kMaxPitch);
    moved = true;
  }
  if (input.uiWantsKeyboard) return moved;
  const glm::vec3 f = forward();
  const glm::vec3 r = glm::normalize(glm::cross(f, glm::vec3(0, 1, 0)));
  glm::vec3 step(0.0f);  // keys[]: held, or tapped since the last poll (a tap moves for one frame)
  if (input.keys[GLFW_KEY_W]) step += f;
  if (input.keys[GLFW_KEY_S]) step -= f;
  if (input.keys[GLFW_KEY_D]) step += r;
  if (input.keys[GLFW_KEY_A]) step -= r;
  if (input.keys[GLFW_KEY_E]) step.y += 1.0f;
  if (input.keys[GLFW_KEY_Q]) step.y -= 1.0f;
  if (glm::dot(step, step) > 0.0f) {
    position += glm::normalize(step) * speed * dt * (input.keys[GLFW_KEY_LEFT_SHIFT] ? 4.0f : 1.0f);
    moved = true;
  }
  return moved;
}

}  // namespace engine::platform
