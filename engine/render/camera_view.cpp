#include "engine/render/camera_view.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

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

glm::vec3 CameraView::towardViewer() const {
  // The third row of the view's rotation: view space +Z in world space.
  return glm::normalize(glm::vec3(view[0][2], view[1][2], view[2][2]));
}

glm::vec4 CameraView::eye() const { return orthographic() ? glm::vec4(towardViewer(), 0.0f) : glm::vec4(position, 1.0f); }

float CameraView::viewDistance(const glm::vec3& p) const { return -(view * glm::vec4(p, 1.0f)).z; }

float CameraView::worldPerPixel(float distance, std::uint32_t height) const {
  // proj[1][1] is -1 / tan(fovY / 2) (perspective) or -1 / ymag (orthographic).
  const float halfHeightAtOne = 1.0f / std::abs(proj[1][1]);
  return 2.0f * halfHeightAtOne * (orthographic() ? 1.0f : distance) / float(std::max(height, 1u));
}

float CameraView::nearPlaneReach() const {
  // Half the near rectangle's width and height: znear * tan(half angle), or the orthographic extents.
  const float scale = orthographic() ? 1.0f : znear;
  const float halfX = scale / std::abs(proj[0][0]);
  const float halfY = scale / std::abs(proj[1][1]);
  return std::sqrt(znear * znear + halfX * halfX + halfY * halfY) * 1.01f;
}

float CameraView::nearPlaneReachInObject(const glm::mat4& invModel) const {
  const glm::mat3 inverse(invModel);
  const float frobenius = std::sqrt(glm::dot(inverse[0], inverse[0]) + glm::dot(inverse[1], inverse[1]) +
                                    glm::dot(inverse[2], inverse[2]));
  return nearPlaneReach() * frobenius;
}

glm::dmat4 CameraView::viewFrom(const glm::dvec3& origin) const {
  const glm::dmat3 rotation{glm::mat3(view)};
  glm::dmat4 shifted{rotation};
  shifted[3] = glm::dvec4(rotation * (origin - glm::dvec3(position)), 1.0);
  return shifted;
}

namespace {
// The camera's pose from a node's world matrix: orthonormal axes, -Z kept, then +Y (fromWorld).
Expected<glm::mat4> cameraPose(const glm::mat4& world) {
  for (int column = 0; column < 4; ++column)
    for (int row = 0; row < 4; ++row)
      if (!std::isfinite(world[column][row])) return makeError("the camera's world matrix is not finite");
  // In double, relative to the axes' own lengths: a camera under a parent scaled by 1e-6 is valid.
  const glm::dvec3 back(world[2]), up(world[1]);
  const double backLength = glm::length(back);
  if (!(backLength > 0.0)) return makeError("the camera's Z axis has zero length (a zero scale)");
  const glm::dvec3 z = back / backLength;
  const glm::dvec3 upAcross = up - glm::dot(up, z) * z;
  const double upLength = glm::length(upAcross);
  if (!(upLength > 1e-6 * glm::length(up)))
    return makeError("the camera's Y axis has zero length or is parallel to its Z axis");
  const glm::dvec3 y = upAcross / upLength;
  const glm::dvec3 x = glm::cross(y, z);
  glm::mat4 pose(1.0f);
  pose[0] = glm::vec4(glm::vec3(x), 0.0f);
  pose[1] = glm::vec4(glm::vec3(y), 0.0f);
  pose[2] = glm::vec4(glm::vec3(z), 0.0f);
  pose[3] = glm::vec4(glm::vec3(world[3]), 1.0f);
  return pose;
}

Status checkAspect(float aspect) {
  if (!(aspect > 0.0f) || !std::isfinite(aspect)) return makeError(fmt::format("aspect ratio {:g} is not positive", aspect));
  return {};
}

Expected<CameraView> orthographicFromWorld(const glm::mat4& world, const Camera& camera, float aspect) {
  if (!(camera.ymag > 0.0f) || !std::isfinite(camera.ymag))
    return makeError(fmt::format("orthographic ymag {:g} is not positive", camera.ymag));
  if (!(camera.znear >= 0.0f) || !std::isfinite(camera.znear))
    return makeError(fmt::format("orthographic znear {:g} is negative", camera.znear));
  if (!(camera.zfar > camera.znear) || !std::isfinite(camera.zfar))
    return makeError(fmt::format("orthographic zfar {:g} is not beyond znear {:g}", camera.zfar, camera.znear));
  ENGINE_TRY(checkAspect(aspect));
  ENGINE_TRY_ASSIGN(const glm::mat4 pose, cameraPose(world));
  if (!std::isfinite(camera.ymag * aspect)) return makeError("the orthographic view's width is not finite");
  CameraView c;
  c.view = glm::inverse(pose);
  c.proj = math::orthographicReverseZ(camera.ymag * aspect, camera.ymag, camera.znear, camera.zfar);
  c.position = glm::vec3(world[3]);
  c.znear = camera.znear;
  c.projection = Projection::kOrthographic;
  c.ymag = camera.ymag;
  c.zfar = camera.zfar;
  return c;
}
}  // namespace

Expected<CameraView> CameraView::fromWorld(const glm::mat4& world, float fovY, float znear, float aspect) {
  if (!(fovY > 0.0f && fovY < 3.14159265f))
    return makeError(fmt::format("vertical field of view {:g} rad is not between 0 and pi", fovY));
  if (!(znear > 0.0f) || !std::isfinite(znear)) return makeError(fmt::format("znear {:g} is not positive", znear));
  ENGINE_TRY(checkAspect(aspect));
  ENGINE_TRY_ASSIGN(const glm::mat4 pose, cameraPose(world));
  CameraView c;
  c.view = glm::inverse(pose);
  c.proj = math::perspectiveReverseZInfinite(fovY, aspect, znear);
  c.position = glm::vec3(world[3]);
  c.znear = znear;
  c.fovY = fovY;
  return c;
}

Expected<CameraView> CameraView::fromWorld(const glm::mat4& world, const Camera& camera, float aspect) {
  if (camera.projection == Projection::kOrthographic) return orthographicFromWorld(world, camera, aspect);
  return fromWorld(world, camera.fovY, camera.znear, aspect);
}

}  // namespace engine::render
