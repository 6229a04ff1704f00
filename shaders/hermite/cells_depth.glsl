// Depth prepass of the Hermite cells: the paper's intersection. Included by cells_depth.frag
// (front faces, conservative depth) and cells_depth_near.frag (back faces of cells the near plane
// may cut; no depth guarantee relative to the face).
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/hermite.glsl"

layout(push_constant, scalar) uniform Push { HermitePushConstants pc; };
layout(buffer_reference, scalar) readonly buffer HermiteDrawsRef { HermiteDraw draws[]; };
layout(buffer_reference, scalar) buffer CountersRef { uint counts[]; };

layout(location = 0) flat in vec4 inCorners[8];
layout(location = 8) flat in uvec4 inCell;
layout(location = 9) flat in uint inDraw;
layout(location = 10) in vec3 inLocal;
layout(location = 11) flat in vec3 inCameraLocal;
layout(location = 12) flat in uint inRecord;

// The pixel's ray in cell-local coordinates, u(t) = origin + t * direction, parametrized so that
// t = 1 at this fragment's point on the box. View distance is linear in t, so a point at t has
// reverse-Z depth gl_FragCoord.z / t, and the near plane lies at t = gl_FragCoord.z.
struct CellRay {
  vec3 origin;
  vec3 direction;
};

CellRay cellRay() { return CellRay(inCameraLocal, inLocal - inCameraLocal); }

layout(location = 0) out uvec2 outVisibility;  // (1 + object, cell record)
#ifdef HSDF_CONSERVATIVE_DEPTH
// Reverse-Z: the hit is never nearer than the front face, so its depth is never greater.
layout(depth_less) out float gl_FragDepth;
#endif

void main() {
  HermiteDraw draw = HermiteDrawsRef(pc.draws).draws[inDraw];
  CellRay ray = cellRay();
  vec2 box = intersectUnitBox(ray.origin, ray.direction);
  float tNear = gl_FragCoord.z;  // the near plane (see cellRay)
  float t0 = max(box.x, tNear);
  float t1 = box.y;
#ifdef HSDF_CONSERVATIVE_DEPTH
  t0 = max(t0, 1.0 - 1e-6);  // this face point is the entry; rounding must not move it forward
#endif
  uint evaluations = 0u;
  float t = -1.0;
  if (t0 <= t1)
    t = findFirstRoot(inCorners, draw.gridOriginSpacing.w, ray.origin, ray.direction, t0, t1, draw.subdivisions,
                      draw.refineSteps, evaluations);
  if (pc.counters != 0ul) {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;
    atomicAdd(CountersRef(pc.counters).counts[pixel.y * int(frame.viewport.x) + pixel.x], evaluations);
  }
  if (t < 0.0) discard;
#ifdef HSDF_CONSERVATIVE_DEPTH
  t = max(t, 1.0);
#endif
  gl_FragDepth = gl_FragCoord.z / t;
  outVisibility = uvec2(draw.object + 1u, inRecord);
}
