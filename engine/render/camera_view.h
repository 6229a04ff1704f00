#pragma once
// What the renderer needs of a camera for one frame.
#include <cstdint>

#include <glm/glm.hpp>

#include "engine/core/expected.h"
#include "engine/render/components.h"

namespace engine::render {

struct CameraView {
  glm::mat4 view{1.0f};
  glm::mat4 proj{1.0f};
  glm::vec3 position{0.0f};  // the eye; orthographic: the camera's point on its own plane
  float znear = 0.05f;
  float fovY = 0.8f;         // perspective only
  Projection projection = Projection::kPerspective;
  float ymag = 1.0f;         // orthographic only: half the view's height, world units
  float zfar = 0.0f;         // orthographic only: the far plane (a perspective one is infinite)

  bool orthographic() const { return projection == Projection::kOrthographic; }
  // The unit vector from the scene towards the viewer (the view's +Z axis in world space).
  glm::vec3 towardViewer() const;
  // The eye as a homogeneous point (FrameGlobals::cameraPosition): w = 1, the eye point; w = 0 for an
  // orthographic camera, whose xyz is towardViewer(). A point p's ray leaves p towards the viewer
  // along eye.xyz - p * eye.w in both cases, and eye transforms as a point by any model matrix.
  glm::vec4 eye() const;
  // Distance of the world point p in front of the camera, along the view axis (not along the ray).
  float viewDistance(const glm::vec3& p) const;
  // World units one pixel spans at a view distance (the image `height` pixels tall): grows with the
  // distance in perspective, constant (2 ymag / height) in orthographic.
  float worldPerPixel(float viewDistance, std::uint32_t height) const;

  // Radius around `position` (world units) that the near plane's rectangle reaches, with 1% margin:
  // geometry closer than this may be cut by the near plane. Orthographic: the rectangle is the
  // view's (2 ymag tall) at znear in front of the camera's plane.
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
  // then +Y), so that a camera under a scaled parent sees the scene undistorted; znear (and an
  // orthographic camera's ymag, zfar) stay in world units, unscaled, as glTF 2.0 asks: "The view
  // matrix is derived from the global transform of the node containing the camera with the scaling
  // ignored" ("Cameras", "View Matrix"), the projection mapping that view space to clip space. An error names
  // what cannot make a camera: a non-finite matrix, a zero or parallel -Z / +Y axis (zero scale),
  // fovY outside (0, pi), znear not positive and finite, an aspect that is not positive.
  static Expected<CameraView> fromWorld(const glm::mat4& world, float fovY, float znear, float aspect);
  // The same for a camera component of either projection. An orthographic camera's error names a
  // ymag that is not positive and finite, a znear below 0 or a zfar not beyond znear; its view is
  // 2 ymag tall and 2 ymag * aspect wide (the image's aspect wins over xmag).
  static Expected<CameraView> fromWorld(const glm::mat4& world, const Camera& camera, float aspect);
};

}  // namespace engine::render
