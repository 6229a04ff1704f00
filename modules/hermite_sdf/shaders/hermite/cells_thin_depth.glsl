// Depth prepass of the thin cell boxes (cells_thin.vert): the search of cells_depth.glsl over the
// cell's proxy box dilated by the search margin (cell_search.glsl; docs/root-finding.md), with the
// cell's record read by buffer address instead of handed on as varyings, and the ray rebuilt from
// gl_FragCoord (pixel_ray.glsl). Compiled as cells_thin_depth{,_near}{,_counted}.frag; no early
// depth variant (a frame that draws thin cells keeps the early depth stage off).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/proxy_dilation.glsl"
#include "hermite/pixel_ray.glsl"
#include "hermite/record_cell.glsl"

layout(push_constant, scalar) uniform Push { HermitePushConstants pc; };
#include "hermite/cell_search.glsl"

layout(location = 0) flat in uint inRecord;
layout(location = 1) flat in uint inDraw;
layout(location = 2) flat in float inDilation;  // the proxy: the cell's box grown by this, cells

layout(location = 0) out uvec2 outVisibility;  // (1 + object, cell record)
layout(location = 1) out float outHitOffset;  // where along the ray: pixelRayHitOffset (pixel_ray.glsl)
#if defined(HSDF_CONSERVATIVE_DEPTH)
layout(depth_less) out float gl_FragDepth;  // reverse-Z: the hit is never nearer than the front face
#endif
#include "hermite/hit_depth.glsl"

void main() {
  HermiteDraw draw = hermiteDrawAt(pc.draws, inDraw);  // inDraw: the record (the vertex shader looked it up)
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;
  mat4 invModel = ObjectsRef(pc.draw.objects).objects[draw.object].invModel;
  float h = draw.gridOriginSpacing.w;
  vec3 lo, hi;  // the cell's proxy box
  PixelRay ray = pixelRay(frame, invModel, h, draw.rayAnchor - vec4(recordCellBox(draw, inRecord, lo, hi), 0.0));
  vec3 origin = ray.origin;
  vec3 direction = ray.direction;
  float margin = inDilation;  // the search margin: the proxy's dilation (docs/root-finding.md)
  uint evaluations = 0u;
  // From the near plane (pixel_ray.glsl) on; searchCell clips to the dilated box.
  float t = searchCell(draw, inRecord, lo, hi, origin, direction, margin, pixelRayNearT(frame) - ray.base, 3.0e38, evaluations);
  countWork(evaluations);
  if (t < 0.0) {
    writeMiss();  // no discard: see hit_depth.glsl
  } else {
    writeHitDepth(pixelRayHitDepth(frame, ray.base, t));  // at the face if in front of it (front faces)
  }
  outVisibility = uvec2(draw.object + 1u, inRecord);  // kept only where the depth test passes
  outHitOffset = pixelRayHitOffset(frame, t);
}
