// Depth prepass of the Hermite cell runs (RenderMethod::CellRuns). Compiled as runs_depth.frag
// (front faces, conservative depth) and runs_depth_near.frag (back faces of runs the near plane may
// cut), and as their counting and early depth variants (hit_depth.glsl). The same search as the cells (cells_depth.glsl), cell by cell along the ray inside the run:
// each cell is searched over its own box dilated as in the cells (docs/root-finding.md), from the
// cell the ray enters first, and the walk stops at the first root.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/proxy_dilation.glsl"
#include "hermite/pixel_ray.glsl"

layout(push_constant, scalar) uniform Push { HermitePushConstants pc; };
#include "hermite/cell_search.glsl"

layout(location = 0) flat in uvec4 inRun;  // x, y, z, length
layout(location = 1) flat in uint inFirstRecord;
layout(location = 2) flat in uint inDraw;
layout(location = 5) flat in float inDilation;

layout(location = 0) out uvec2 outVisibility;  // (1 + object, cell record)
layout(location = 1) out float outHitOffset;  // where along the ray: pixelRayHitOffset (pixel_ray.glsl)
#if defined(HSDF_CONSERVATIVE_DEPTH) && !defined(HSDF_EARLY_DEPTH)
layout(depth_less) out float gl_FragDepth;  // reverse-Z: the hit is never nearer than the front face
#endif
#include "hermite/hit_depth.glsl"

void main() {
  HermiteDraw draw = hermiteDrawAt(pc.draws, inDraw);  // inDraw: the record (the vertex shader looked it up)
  // The ray in run-local coordinates (cells; cell i of the run spans x in [i, i + 1]), based near
  // the object on the record's anchor (pixel_ray.glsl: camera t = base + t, the depth of any camera
  // t, the near plane's).
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;
  mat4 invModel = ObjectsRef(pc.draw.objects).objects[draw.object].invModel;
  PixelRay ray = pixelRay(frame, invModel, draw.gridOriginSpacing.w, draw.rayAnchor - vec4(vec3(inRun.xyz), 0.0));
  vec3 origin = ray.origin;
  vec3 direction = ray.direction;
  float margin = inDilation;  // the search margin: the proxy's dilation (docs/root-finding.md)
  float length = float(inRun.w);
  // The run's box mirrored through the origin, the same interval: 1 / -direction shares nothing with the
  // cells' searches' 1 / direction, which the compiler would otherwise hold from here through the walk
  // (3 registers more through every search).
  vec2 box = intersectBox(-origin, -direction, -vec3(length + margin, 1.0 + margin, 1.0 + margin), vec3(margin));
  float tNear = pixelRayNearT(frame) - ray.base;
  float t0 = max(box.x, tNear);
  float t1 = box.y;
  uint evaluations = 0u;
  float t = -1.0;
  uint hitRecord = 0u;
  if (t0 < t1) {
    // The run's cells in the order the ray meets them.
    int stepX = direction.x < 0.0 ? -1 : 1;
    int last = int(inRun.w) - 1;
    int first = clamp(int(floor(origin.x + t0 * direction.x)), 0, last);
    int end = clamp(int(floor(origin.x + t1 * direction.x)), 0, last);
    int count = abs(end - first) + 1;
    for (int k = 0; k < count; ++k) {
      int cell = first + stepX * k;
      vec3 cellOrigin = origin - vec3(float(cell), 0.0, 0.0);
      vec3 lo, hi;
      recordProxyBox(draw, inFirstRecord + uint(cell), lo, hi);
      t = searchCell(draw, inFirstRecord + uint(cell), lo, hi, cellOrigin, direction, margin, t0, t1, evaluations);
      if (t >= 0.0) {
        hitRecord = inFirstRecord + uint(cell);
        break;
      }
    }
  }
  countWork(evaluations);
  if (t < 0.0) {
    writeMiss();  // no discard: see hit_depth.glsl
  } else {
    writeHitDepth(pixelRayHitDepth(frame, ray.base, t));  // at the run's face if in front of it (front faces)
  }
  outVisibility = uvec2(draw.object + 1u, hitRecord);  // kept only where the depth test passes
  outHitOffset = pixelRayHitOffset(frame, t);
}
