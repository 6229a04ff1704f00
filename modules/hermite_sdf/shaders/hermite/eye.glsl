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

// The clip position of `gridPoint` (grid units) of the object placed by `model` whose cells base
// their rays on `draw.rayAnchor`: drawn as an offset of a few cells from the anchor, which lies on
// the view axis at view depth w, at view-space (0, 0, -w) (the frame's view is relative to the eye,
// GpuScene::setOrigin; for an orthographic camera, to its point). Why: through model's float
// translation, ~7.5e6 cells long at 3e5 object sizes, a box corner rounds by up to ~0.5 cell, and
// the boxes were drawn that far from where the rays, based on the host's exact anchor, search.
// The same for an object of grid spacing `spacing` whose rays are based on `anchor` (the sphere
// tracers' SphereTraceDraw::rayAnchor).
vec4 anchoredClipPosition(FrameGlobals frame, mat4 model, float spacing, vec4 anchor, vec3 gridPoint) {
  vec3 offset = mat3(model) * (spacing * (gridPoint - anchor.xyz));
  return frame.proj * vec4(mat3(frame.view) * offset - vec3(0.0, 0.0, anchor.w), 1.0);
}

vec4 anchoredClipPosition(FrameGlobals frame, mat4 model, HermiteDraw draw, vec3 gridPoint) {
  return anchoredClipPosition(frame, model, draw.gridOriginSpacing.w, draw.rayAnchor, gridPoint);
}

#endif
