#include "render/ray_anchor.h"

#include <cmath>

#include "engine/render/gpu_scene.h"

namespace hsdf {

ViewAxis viewAxis(const engine::render::CameraView& camera) {
  const glm::dmat3 rotation(glm::mat3(camera.view));
  return {-glm::inverse(rotation)[2], -glm::dvec3(rotation[0][2], rotation[1][2], rotation[2][2])};
}

glm::dvec3 eyeInGrid(const engine::render::CameraView& camera, const glm::mat4& world, const GridSpec& grid) {
  return (engine::render::eyeInObject(world, camera.position) - grid.origin) / grid.spacing;
}

glm::dvec4 rayAnchorGrid(const ViewAxis& axis, const glm::mat4& world, const GridSpec& grid, const glm::dvec3& eyeGrid) {
  const glm::dmat3 model(world);
  const glm::dvec3 depthPerCell = grid.spacing * (glm::transpose(model) * axis.depth);  // view depth of a grid unit per axis
  const double halfExtent = 0.5 * double(grid.cellsPerAxis());  // the grid spans [0, K - 1]
  const glm::dvec3 absolute = glm::abs(depthPerCell);
  const double nearest = glm::dot(glm::dvec3(halfExtent) - eyeGrid, depthPerCell) -
                         (halfExtent + 1.0) * (absolute.x + absolute.y + absolute.z);
  const double depth = nearest > 0.0 && std::isfinite(nearest) ? nearest : 0.0;
  return glm::dvec4(eyeGrid + depth * (glm::inverse(model) * axis.ahead) / grid.spacing, depth);
}

}  // namespace hsdf
