#pragma once
// Where the ray-cast proxies base their rays (pixel_ray.glsl): a point near the object on the view
// axis, made once per object and view region on the host, in double (HermiteDraw::rayAnchor, the
// cells; SphereTraceDraw::rayAnchor, the sphere tracers).
#include <glm/glm.hpp>

#include "engine/render/camera_view.h"
#include "hermite_sdf/core/field.h"

namespace hsdf {

// The view axis as the frame's view rotation R (a float matrix, CameraView::view) draws it, world
// space: `ahead`, the point at view depth 1 straight ahead of the eye, less the eye (R^-1 (0, 0, -1),
// not R's third row: a float rotation is orthonormal to ~1e-7, and a point on that row ~7.5e6 cells
// ahead would be drawn most of a cell off the axis); `depth`, the view depth of a unit offset.
struct ViewAxis {
  glm::dvec3 ahead{0.0, 0.0, -1.0};
  glm::dvec3 depth{0.0, 0.0, -1.0};
};

ViewAxis viewAxis(const engine::render::CameraView& camera);

// The eye (an orthographic camera's point) in the grid units of an object placed by `world`:
// object space less the grid's origin, over its spacing.
glm::dvec3 eyeInGrid(const engine::render::CameraView& camera, const glm::mat4& world, const GridSpec& grid);

// Where an object's rays are based this view, in its grid units, and the view depth there (w,
// world units): the point of the view axis through `eyeGrid` (eyeInGrid) at the view depth of the
// grid's nearest corner, less a cell; the eye itself (depth 0) when it is beside or in the grid.
// Why: the rays searched (the cells) and marched (the tracers) in the camera's t, t = 1 at the
// rasterized face, and ~3e6 cells from a far camera (a telephoto lens, an orthographic camera
// placed back along its axis) a float t near 1 holds a quarter of a cell (docs/reliability.md,
// "Scales, distances and cameras"). Based here a ray runs in an offset from a point beside the
// grid, in front of every cell and of the margins around them, so that every root has t >= 0, as
// the searches' "no root" (-1) needs; the boxes are drawn as offsets from it too (eye.glsl,
// anchoredClipPosition). Made in double once per object and view region: made in the shaders, in
// float from the eye ~7.5e6 cells out at 3e5 object sizes, it held ~0.5 cell.
glm::dvec4 rayAnchorGrid(const ViewAxis& axis, const glm::mat4& world, const GridSpec& grid, const glm::dvec3& eyeGrid);

}  // namespace hsdf
