#pragma once
// What the renderer needs of a camera for one frame.
#include <glm/glm.hpp>

#include "engine/core/expected.h"

namespace engine::render {

struct CameraView {
  glm::mat4 view{1.0f};
  glm::mat4 proj{1.0f};
  glm::vec3 position{0.0f};
  float znear = 0.05f;
  float fovY = 0.8f;

  // Radius around the eye (world units) that the near plane's rectangle reaches, with 1% margin:
  // geometry closer than this may be cut by the near plane.
  float nearPlaneReach() const;
  // nearPlaneReach() in the units of an object whose inverse model matrix is `invModel`: an upper
  // bound on the object-space distance from the eye to any point of the near plane's rectangle,
  // for any invertible affine model (mirroring, non-uniform scale and shear included). A world
  // length L spans at most L * |M^-1|_2 object units, and |M^-1|_2 <= |M^-1|_Frobenius.
  float nearPlaneReachInObject(const glm::mat4& invModel) const;
  // The view matrix of world space shifted by -origin (camera-relative rendering), in double, from
  // the view's rotation and `position` (view is rigid and puts `position` at the view origin): its
  // translation is exact, not the float product -R * position, which ~1e5 units from the world
  // origin is off by ~1e-2. viewFrom(dvec3(0)) is the world's view matrix in double.
  glm::dmat4 viewFrom(const glm::dvec3& origin) const;

  // A camera at `eye` looking at `target`, Y up, for an image of the given aspect ratio. Throws
  // std::invalid_argument when eye and target are the same point (no direction to look in).
  static CameraView lookAt(const glm::vec3& eye, const glm::vec3& target, float fovY, float znear, float aspect);
  // A camera placed by a world matrix, as a glTF camera node is: its local -Z is the viewing
  // direction and +Y is up. Scale and shear are dropped (the axes are orthonormalized, -Z kept,
  // then +Y), so that a camera under a scaled parent sees the scene undistorted. An error names
  // what cannot make a camera: a non-finite matrix, a zero or parallel -Z / +Y axis (zero scale),
  // fovY outside (0, pi), znear not positive and finite, an aspect that is not positive.
  static Expected<CameraView> fromWorld(const glm::mat4& world, float fovY, float znear, float aspect);
};

}  // namespace engine::render
