#include "engine/render/camera_view.h"

#include <cmath>

#include "engine/core/math.h"

namespace engine::render {

CameraView CameraView::lookAt(const glm::vec3& eye, const glm::vec3& target, float fovY, float znear, float aspect) {
  CameraView c;
  glm::vec3 up(0.0f, 1.0f, 0.0f);
  if (glm::length(glm::cross(glm::normalize(target - eye), up)) < 1e-4f) up = glm::vec3(0.0f, 0.0f, 1.0f);
  c.view = math::lookAt(eye, target, up);
  c.proj = math::perspectiveReverseZInfinite(fovY, aspect, znear);
  c.position = eye;
  c.znear = znear;
  c.fovY = fovY;
  return c;
}

float CameraView::nearPlaneReach() const {
  const float tanX = 1.0f / std::abs(proj[0][0]);
  const float tanY = 1.0f / std::abs(proj[1][1]);
  return znear * std::sqrt(1.0f + tanX * tanX + tanY * tanY) * 1.01f;
}

float CameraView::nearPlaneReachInObject(const glm::mat4& invModel) const {
  const glm::mat3 inverse(invModel);
  const float frobenius = std::sqrt(glm::dot(inverse[0], inverse[0]) + glm::dot(inverse[1], inverse[1]) +
                                    glm::dot(inverse[2], inverse[2]));
  return nearPlaneReach() * frobenius;
}

CameraView CameraView::fromWorld(const glm::mat4& world, float fovY, float znear, float aspect) {
  CameraView c;
  c.view = glm::inverse(world);
  c.proj = math::perspectiveReverseZInfinite(fovY, aspect, znear);
  c.position = glm::vec3(world[3]);
  c.znear = znear;
  c.fovY = fovY;
  return c;
}

}  // namespace engine::render
