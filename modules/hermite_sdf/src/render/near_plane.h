#pragma once
// Whether the camera's near plane may cut an object's box, which the ray-cast proxies then draw by
// their back faces (the sphere tracers' box, the cells of an object whose grid box it may cut).
#include <glm/glm.hpp>

#include "engine/render/camera_view.h"

namespace hsdf {

// Perspective: the box [lo, hi] placed by `model` comes within the near plane's reach of the eye
// (conservative for any affine transform, CameraView::nearPlaneReachInObject). Orthographic: the
// near plane is a plane across the whole view, so the box's nearest corner in view distance (in
// double) decides.
bool nearPlaneMayCut(const engine::render::CameraView& camera, const glm::mat4& model, const glm::vec3& lo,
                     const glm::vec3& hi);

}  // namespace hsdf
