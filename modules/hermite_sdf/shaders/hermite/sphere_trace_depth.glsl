// Depth prepass of the sphere-tracing baselines: trace the pixel's ray from the box entry (or the
// near plane) and write the hit's depth and the visibility id. Compiled as the
// sphere_trace_*_depth*.frag variants; HSDF_CONSERVATIVE_DEPTH marks the front-face variant, whose
// hits are never nearer than the rasterized face. Beside the visibility it stores the hit's offset
// from the rays' anchor (pixelRayHitOffset), from which the shading rebuilds the hit.
//
// The variants that draw frames have no discard and no buffer write: on GPUs either one costs the
// early and hierarchical depth rejection of every fragment of the pipeline (measured on an H100,
// docs/gpu-vs-lavapipe.md). A miss writes depth 0, the far plane under reverse-Z, which fails the
// GREATER test like nothing drawn. HSDF_COUNT_WORK (the *_counted.frag variants, chosen only for
// frames that count work) adds the per-pixel evaluation counts and the rays out of steps.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "hermite/sphere_trace_common.glsl"
#include "hermite/pixel_ray.glsl"

#ifdef HSDF_COUNT_WORK
layout(buffer_reference, scalar) buffer WorkCountersRef { uint counts[]; };
layout(buffer_reference, scalar) buffer WorkTotalsRef { WorkTotals totals; };
#endif

layout(location = 0) flat in uint inDraw;

layout(location = 0) out uvec2 outVisibility;  // (1 + object, field evaluations | SPHERE_TRACE_STARTED_INSIDE)
layout(location = 1) out float outHitOffset;  // where along the ray: pixelRayHitOffset (pixel_ray.glsl)
#ifdef HSDF_CONSERVATIVE_DEPTH
// Reverse-Z: the hit is never nearer than the front face, so its depth is never greater (a miss
// writes 0, which is less too).
layout(depth_less) out float gl_FragDepth;
#endif

void main() {
  SphereTraceDraw draw = SphereTraceDrawsRef(pc.draws).draws[inDraw];
  // The ray u(t) = origin + t * direction in grid units, based near the object at the draw's anchor
  // (pixel_ray.glsl): the camera's t is ray.base + t, 1 at this fragment's point on the box, and
  // pixelRayHitDepth gives the depth of a hit, pixelRayNearT the near plane's camera t. Based at the
  // eye, a far camera's ray started a float ~1e7 cells out, every axis rounded by ~0.5 cell.
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;
  mat4 invModel = ObjectsRef(pc.draw.objects).objects[draw.object].invModel;
  PixelRay ray = pixelRay(frame, invModel, draw.gridOriginSpacing.w, draw.rayAnchor);
  float cells = float(draw.resolution - 1u);
  vec2 box = intersectUnitBox(ray.origin / cells, ray.direction / cells);
  float t0 = max(box.x, pixelRayNearT(frame) - ray.base);
  TraceResult trace = TraceResult(-1.0, 0u, false, false);
  if (t0 <= box.y) trace = sphereTrace(draw, ray.origin, ray.direction, t0, box.y);
#ifdef HSDF_COUNT_WORK
  // Every ray's steps, hits and misses alike (the renderer's work counters).
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  atomicAdd(WorkCountersRef(pc.counters).counts[pixel.y * int(frame.viewport.x) + pixel.x], trace.evaluations);
  if (trace.outOfSteps) atomicAdd(WorkTotalsRef(pc.workTotals).totals.raysOutOfSteps, 1u);
#endif
  // Front faces: rounding of the box entry must not move the hit in front of the face (pixelRayHitDepth).
  gl_FragDepth = trace.t < 0.0 ? 0.0 : pixelRayHitDepth(frame, ray.base, trace.t);
  outVisibility = uvec2(draw.object + 1u, trace.evaluations | (trace.startedInside ? SPHERE_TRACE_STARTED_INSIDE : 0u));
  outHitOffset = pixelRayHitOffset(frame, trace.t);
}
