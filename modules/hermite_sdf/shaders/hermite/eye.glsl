// The eye as the vertex shaders of the ray-cast proxies need it, for perspective and orthographic
// cameras alike, from the homogeneous eye FrameGlobals::cameraPosition (w = 1: the eye point;
// w = 0: the direction towards the viewer).
#ifndef HSDF_EYE_GLSL
#define HSDF_EYE_GLSL

// The point the fragments' rays are parametrized from (pixel_ray.glsl), in the frame's world space:
// the eye, or the orthographic camera's own point (the view's origin, invView's translation), on
// whose plane the parallel rays start. w is exactly 0 or 1: the perspective eye comes out exact.
vec3 rayEyePoint(FrameGlobals frame) {
  float w = frame.cameraPosition.w;
  return frame.cameraPosition.xyz * w + frame.invView[3].xyz * (1.0 - w);
}

// Where the viewer is, seen from an object with inverse model matrix `invModel`, as box.glsl's
// frontFanCorner takes it: the eye point in the object's local units (`eyeLocal`, from
// rayEyePoint), w = 1; or, orthographic, the direction towards the viewer in object space, w = 0
// (only its signs per axis matter, so the local units' positive scale is left out).
vec4 viewerLocal(FrameGlobals frame, mat4 invModel, vec3 eyeLocal) {
  float w = frame.cameraPosition.w;  // exactly 0 or 1: the other term is an exact zero
  vec3 towardViewer = mat3(invModel) * frame.cameraPosition.xyz;
  return vec4(eyeLocal * w + towardViewer * (1.0 - w), w);
}

// Where an object's cells base their rays (pixel_ray.glsl), in its grid units (object space /
// spacing, from the grid origin), and the view depth there (w, world units): the point of the view
// axis through `eyeGrid` (rayEyePoint in grid units) at the view depth of the grid's nearest
// corner, less a cell, never behind the camera's point. Why: the cells searched in the camera's t,
// t = 1 at the rasterized face, and ~3e6 cells from a far camera (a telephoto lens, an orthographic
// camera placed back along its axis) a float t near 1 holds a quarter of a cell: the segments'
// ends, and the roots, moved by that much (docs/reliability.md, "Scales, distances and cameras").
// Based here, the search runs in an offset from a point beside the cells, held to float's precision
// there; in front of every cell (and of the margins around them), so that every root has t >= 0,
// as the searches' "no root" (-1) needs. One point per object, the same in every cell's shader:
// its rounding moves every ray of the object alike (the object shifts by a rounding of the eye, as
// with the eye itself).
vec4 rayAnchorGrid(FrameGlobals frame, mat4 model, mat4 invModel, float spacing, uint resolution, vec3 eyeGrid) {
  vec3 forward = -frame.invView[2].xyz;                      // world, unit
  vec3 depthPerCell = spacing * (transpose(mat3(model)) * forward);  // view depth of a grid unit per axis
  float halfExtent = 0.5 * float(resolution - 1u);            // grid units: the grid spans [0, K - 1]
  float nearest = dot(vec3(halfExtent) - eyeGrid, depthPerCell) - (halfExtent + 1.0) * dot(abs(depthPerCell), vec3(1.0));
  float depth = nearest > 0.0 && nearest < 3.0e38 ? nearest : 0.0;  // the eye beside or in the grid, or NaN: the eye
  return vec4(eyeGrid + depth * (mat3(invModel) * forward / spacing), depth);
}

// rayAnchorGrid of an object whose grid has origin and spacing `gridOriginSpacing` (xyz, w) and
// `resolution` samples per axis, for the shaders that have no eye in grid units at hand.
vec4 objectRayAnchor(FrameGlobals frame, ObjectData object, vec4 gridOriginSpacing, uint resolution) {
  vec3 eyeObject = (object.invModel * vec4(rayEyePoint(frame), 1.0)).xyz;
  float h = gridOriginSpacing.w;
  return rayAnchorGrid(frame, object.model, object.invModel, h, resolution, (eyeObject - gridOriginSpacing.xyz) / h);
}

#endif
