#include "render/near_plane.h"

#include <algorithm>
#include <limits>

#include "engine/render/gpu_scene.h"

namespace hsdf {

bool nearPlaneMayCut(const engine::render::CameraView& camera, const glm::mat4& model, const glm::vec3& lo,
                     const glm::vec3& hi) {
  if (camera.orthographic()) {
    const glm::dmat4 toView = camera.viewFrom(glm::dvec3(0.0)) * glm::dmat4(model);
    double nearest = std::numeric_limits<double>::infinity();
    for (int c = 0; c < 8; ++c) {
      const glm::dvec3 corner((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
      nearest = std::min(nearest, -(toView * glm::dvec4(corner, 1.0)).z);
    }
    return nearest <= double(camera.znear) * 1.01 + 1e-6 * double(camera.zfar);
  }
  const glm::mat4 invModel = glm::inverse(model);
  const glm::vec3 eye(engine::render::eyeInObject(model, camera.position));
  const float objectDistance = glm::length(eye - glm::clamp(eye, lo, hi));
  return objectDistance <= camera.nearPlaneReachInObject(invModel);
}

}  // namespace hsdf
