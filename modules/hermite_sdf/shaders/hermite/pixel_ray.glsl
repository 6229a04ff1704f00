// The pixel's ray, rebuilt from gl_FragCoord: the offset from the ray's start to the pixel centre
// unprojected at the fragment's own depth gl_FragCoord.z, in the grid units (object space /
// spacing) of the object whose inverse model matrix is `invModel`. The ray reaches this fragment's
// point on the rasterized face at the camera's t = 1 (pixelRayDepth, pixelRayNearT: the depth of
// any camera t). The direction is a view-space offset rotated into the grid, never a difference of
// two far points, and the ray is based near the object (pixelRay).
//
// Why not interpolate the face point from the vertices: an NVIDIA H200 interpolates varyings less
// precisely than lavapipe, and the depth of every hit on a ray built from an interpolated face point
// and a flat eye was 10-20x further from the reference there (median 1e-4 cells at K = 64, the
// roots tests' boxes lost pixels), while the bricks, which rebuilt their rays like this, matched
// lavapipe's 1e-6 (docs/gpu-vs-lavapipe.md). The viewport is the whole frame (FrameGlobals).
#include "hermite/eye.glsl"

struct PixelRay {
  vec3 origin;
  vec3 direction;
  float base;  // the camera's t at origin: the ray's point at t lies at the camera's t base + t
};

// The pixel's point at reverse-Z depth `depth` in view space (eye at 0, looking down -z).
vec3 pixelViewPoint(FrameGlobals frame, float depth) {
  vec2 ndc = gl_FragCoord.xy * frame.viewport.zw * 2.0 - 1.0;
  vec4 face = frame.invProj * vec4(ndc, depth, 1.0);
  return face.xyz / face.w;
}

// pixelRay with camera t = 1 at the pixel's point of reverse-Z depth `depth` (gl_FragCoord.z: the
// rasterized face; the resolve: the hit the prepass wrote), whose view depth it returns too.
PixelRay pixelRayThrough(FrameGlobals frame, mat4 invModel, float spacing, vec4 anchor, float depth, out float viewDepth) {
  vec3 faceView = pixelViewPoint(frame, depth);
  viewDepth = -faceView.z;
  vec3 start = vec3(faceView.xy * (1.0 - frame.cameraPosition.w), 0.0);
  vec3 toFace = mat3(frame.invView) * (faceView - start);
  float base = anchor.w > 0.0 ? anchor.w / viewDepth : 0.0;  // the view depth is at t = 1
  vec3 across = mat3(frame.invView) * vec3(faceView.xy * (frame.cameraPosition.w != 0.0 ? base : 1.0), 0.0);
  return PixelRay(anchor.xyz + mat3(invModel) * across / spacing, mat3(invModel) * toFace / spacing, base);
}

// This fragment's ray u(t) = origin + t * direction in the units of `anchor` (an object's grid or
// cell-local coordinates: object space / spacing, offset), based on the plane of view depth
// anchor.w (HermiteDraw::rayAnchor, in those units: flat, the same for every cell of the object).
// The camera's t (t = 1 at the fragment's point on the rasterized face, 0 at the eye or on the
// orthographic camera's plane; pixelRayDepth, pixelRayNearT: the depth of any such t) is base + t.
// Perspective (FrameGlobals::cameraPosition.w = 1): the ray from the eye reaches that plane at
// camera t base, beside the anchor by the face point's view-space x and y scaled by base.
// Orthographic (w = 0): the ray runs down the view axis, beside the anchor by the face point's x
// and y. Both offsets are small where the anchor is near the object: the search runs in an offset
// from a point among the cells, not in the camera's t (HermiteDraw::rayAnchor, made on the host). An anchor of depth
// 0 is the eye or the camera's point itself: base is 0, and t is the camera's t.
PixelRay pixelRay(FrameGlobals frame, mat4 invModel, float spacing, vec4 anchor) {
  float viewDepth;
  return pixelRayThrough(frame, invModel, spacing, anchor, gl_FragCoord.z, viewDepth);
}

// What the prepass stores beside the visibility for a hit at t on pixelRay's ray (the renderer's
// hit offsets, RendererFormats::hitOffset): the hit's view depth past the anchor's plane (t times
// the face's view depth, for both projections), a float as small as the object. The depth buffer
// holds the hit to a float of the whole distance (perspective: znear / d, ~6e-8 of d; orthographic:
// proj[3][2] + (z - proj[3][2]) t, an ulp of proj[3][2] ~ 5e4 at 3e5 object sizes): ~0.5 cell
// along the ray ~8e6 cells out, which the resolve's normals showed. The face's view depth is
// recomputed here, not kept from pixelRay, so that no register holds it through the search.
float pixelRayHitOffset(FrameGlobals frame, float t) {
  return -t * pixelViewPoint(frame, gl_FragCoord.z).z;
}

// The pixel's point `offset` (pixelRayHitOffset: the resolve reads the prepass's) past the anchor's
// plane, in the units of `anchor`, on pixelRay's ray rebuilt through the pixel's depth `depth`
// (any depth of the pixel gives the same ray; its direction is scaled to unit view depth here).
// Nothing of the distance's size is rounded: rebuilt from the depth, the hit was off by the depth
// buffer's precision (pixelRayHitOffset); through world space and the model's inverse, by a float
// ulp of the distance on each axis.
vec3 pixelRayStoredPoint(FrameGlobals frame, mat4 invModel, float spacing, vec4 anchor, float depth, float offset) {
  float viewDepth;
  PixelRay ray = pixelRayThrough(frame, invModel, spacing, anchor, depth, viewDepth);
  return ray.origin + (offset / viewDepth) * ray.direction;
}

// The reverse-Z depth of the ray's point at t. Perspective (w = 1): view distance is linear in t
// from the eye (t = 0), so depth = gl_FragCoord.z / t. Orthographic (w = 0): depth itself is linear
// in view distance, and the ray starts on the camera's plane, at depth proj[3][2] = zfar / (zfar -
// znear). A select on w, not a branch. One expression for both, (z w + linear (1 - w)) /
// (t w + 1 - w), gives the same values for w exactly 0 or 1, but shares 1 - w with the pixel ray:
// a fragment that searches would hold it, and z w, through its whole search, where the select
// needs gl_FragCoord.z alone.
float pixelRayDepth(FrameGlobals frame, float t) {
  float startDepth = frame.proj[3][2];
  return frame.cameraPosition.w != 0.0 ? gl_FragCoord.z / t : startDepth + (gl_FragCoord.z - startDepth) * t;
}

// Where the ray crosses the near plane (depth 1): t = gl_FragCoord.z in perspective; solved from the
// linear depth in orthographic, t = (1 - proj[3][2]) / (gl_FragCoord.z - proj[3][2]) (the face lies
// beyond the camera's plane, so the denominator is negative, as is the numerator unless znear = 0).
// A select on the projection, and the orthographic quotient with both of its terms negated (the
// same value): written as pixelRayDepth's terms, the compiler would share them, and a fragment that
// searches (the near t comes first, the depth last) would hold three of them, not gl_FragCoord.z,
// through its whole search.
float pixelRayNearT(FrameGlobals frame) {
  float startDepth = frame.proj[3][2];
  return frame.cameraPosition.w != 0.0 ? gl_FragCoord.z : (startDepth - 1.0) / (startDepth - gl_FragCoord.z);
}

// The depth to write for a hit at t on a ray based at camera t `base` (pixelRay). Front faces
// (HSDF_CONSERVATIVE_DEPTH, whose shaders promise depth_less): a root before the rasterized face, in
// the search margin, is a neighbour's, found exactly by the neighbour; it is drawn at the face
// (camera t 1), which keeps the depth conservative.
float pixelRayHitDepth(FrameGlobals frame, float base, float t) {
#ifdef HSDF_CONSERVATIVE_DEPTH
  return pixelRayDepth(frame, max(base + t, 1.0));
#else
  return pixelRayDepth(frame, base + t);
#endif
}
