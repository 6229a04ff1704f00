// Depth prepass of the Hermite cells: the paper's intersection. Compiled as cells_depth.frag
// (front faces, conservative depth) and cells_depth_near.frag (back faces of cells the near plane
// may cut; no depth guarantee relative to the face), and as their variants that count work
// (*_counted.frag) or belong to the early depth stage (*_early.frag): hit_depth.glsl.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/segment_roots.glsl"
#include "hermite/proxy_dilation.glsl"
#include "hermite/pixel_ray.glsl"
#include "hermite/record_cell.glsl"

layout(push_constant, scalar) uniform Push { HermitePushConstants pc; };

layout(location = 0) flat in vec4 inCorners[8];
layout(location = 8) flat in uvec4 inCell;
layout(location = 9) flat in uint inDraw;
layout(location = 12) flat in uint inRecord;
layout(location = 13) flat in float inDilation;  // the proxy: the cell's box grown by this, cells

// The pixel's ray in cell-local coordinates, u(t) = origin + t * direction, based near the object
// (the record's anchor, read here: a flat varying cost every box vertex 16 bytes of output),
// rebuilt from gl_FragCoord (pixel_ray.glsl, which also gives the depth of any camera t, base + t).
PixelRay cellRay(FrameGlobals frame, HermiteDraw draw) {
  mat4 invModel = ObjectsRef(pc.draw.objects).objects[draw.object].invModel;
  return pixelRay(frame, invModel, draw.gridOriginSpacing.w, draw.rayAnchor - vec4(vec3(inCell.xyz), 0.0));
}

layout(location = 0) out uvec2 outVisibility;  // (1 + object, cell record)
layout(location = 1) out float outHitOffset;  // where along the ray: pixelRayHitOffset (pixel_ray.glsl)
#if defined(HSDF_CONSERVATIVE_DEPTH) && !defined(HSDF_EARLY_DEPTH)
// Reverse-Z: the hit is never nearer than the front face, so its depth is never greater.
layout(depth_less) out float gl_FragDepth;
#endif
#include "hermite/hit_depth.glsl"

// Each cell searches the ray over its box dilated by inDilation cells on every side (the proxy that
// was rasterized, cells.vert), never before the near plane. A root on (or within rounding of) a
// face shared by two cells, as on the flat faces of a box fitted to the grid, is then a true sign
// change inside the searched segment of both cells, whichever way float rounding of the two cells'
// local coordinates falls; without it each cell could see the root just outside its own segment
// and the ray passed through the face. The rays are based near the object, and the boxes drawn from
// the same point (HermiteDraw::rayAnchor): a far eye costs the local coordinates no precision, and
// the margin is the dilation alone.
void main() {
  HermiteDraw draw = hermiteDrawAt(pc.draws, inDraw);  // inDraw: the record (the vertex shader looked it up)
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;
  PixelRay ray = cellRay(frame, draw);
  float margin = inDilation;
  vec3 lo, hi;
  proxyBox(inCell.w, draw.flags, lo, hi);  // every root of the cell lies in its proxy box
  vec2 box = intersectBox(ray.origin, ray.direction, lo - margin, hi + margin);
  float tNear = pixelRayNearT(frame) - ray.base;
  float t0 = max(box.x, tNear);
  float t1 = box.y;
  uint evaluations = 0u;
  float t = -1.0;
  if (t0 < t1) {
    float coefficients[SEGMENT_COEFFS];
    restrictToSegment(inCorners, draw.gridOriginSpacing.w, ray.origin + t0 * ray.direction,
                      ray.origin + t1 * ray.direction, coefficients);
    ++evaluations;  // the restriction: the cost of a few tricubic evaluations, counted once
    float s = segmentFirstRoot(coefficients, draw.subdivisions, draw.refineSteps,
                               (draw.flags & HERMITE_FLAG_CERTIFIED) != 0u, evaluations);
    if (s >= 0.0) t = mix(t0, t1, s);
  }
  countWork(evaluations);
  if (t < 0.0) {
    writeMiss();  // no discard: see hit_depth.glsl
  } else {
    writeHitDepth(pixelRayHitDepth(frame, ray.base, t));  // at the face if in front of it (front faces)
  }
  outVisibility = uvec2(draw.object + 1u, inRecord);  // kept only where the depth test passes
  outHitOffset = pixelRayHitOffset(frame, t);
}
