// Depth prepass of the sphere-tracing baselines: trace the pixel's ray from the box entry (or the
// near plane) and write the hit's depth and the visibility id. Included by the
// sphere_trace_*_depth*.frag variants; SPHERE_TRACE_CONSERVATIVE_DEPTH marks the front-face
// variant, whose hits are never nearer than the rasterized face.
#include "hermite/sphere_trace_common.glsl"

layout(buffer_reference, scalar) buffer WorkCountersRef { uint counts[]; };

layout(location = 0) flat in uint inDraw;
layout(location = 1) in vec3 inGrid;
layout(location = 2) flat in vec3 inEyeGrid;

layout(location = 0) out uvec2 outVisibility;  // (1 + object, field evaluations)
#ifdef SPHERE_TRACE_CONSERVATIVE_DEPTH
// Reverse-Z: the hit is never nearer than the front face, so its depth is never greater.
layout(depth_less) out float gl_FragDepth;
#endif

void main() {
  SphereTraceDraw draw = SphereTraceDrawsRef(pc.draws).draws[inDraw];
  // The ray u(t) = eye + t * (fragment - eye) in grid units has t = 1 at this fragment's point on
  // the box. View distance is linear in t, so the point at t has depth gl_FragCoord.z / t and the
  // near plane (depth 1) lies at t = gl_FragCoord.z.
  vec3 origin = inEyeGrid;
  vec3 direction = inGrid - inEyeGrid;
  float cells = float(draw.resolution - 1u);
  vec2 box = intersectUnitBox(origin / cells, direction / cells);
  float t0 = max(box.x, gl_FragCoord.z);
  uint evaluations = 0u;
  float t = t0 <= box.y ? sphereTrace(draw, origin, direction, t0, box.y, evaluations) : -1.0;
  if (pc.counters != 0ul) {  // every ray's steps, hits and misses alike (the renderer's work counters)
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;
    atomicAdd(WorkCountersRef(pc.counters).counts[pixel.y * int(frame.viewport.x) + pixel.x], evaluations);
  }
  if (t < 0.0) discard;
#ifdef SPHERE_TRACE_CONSERVATIVE_DEPTH
  t = max(t, 1.0);  // rounding of the box entry must not move the hit in front of the face
#endif
  gl_FragDepth = gl_FragCoord.z / t;
  outVisibility = uvec2(draw.object + 1u, evaluations);
}
