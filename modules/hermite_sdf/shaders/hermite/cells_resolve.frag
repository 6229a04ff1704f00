#version 460
// Shading pass of the Hermite cells, once per pixel: a rectangle over the objects
// (cells_resolve.vert) reads the visibility buffer; where a Hermite-cell object won the prepass, it
// fetches the winning cell's record, rebuilds the hit on its pixel's ray from the hit offset the
// prepass stored beside the visibility (pixel_ray.glsl), and shades it with the exact normal of the
// interpolant.
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/hermite.glsl"
#include "hermite/materials.glsl"
#include "hermite/pixel_ray.glsl"
#include "shared/debug_colors.glsl"
#include "shared/lighting.glsl"

layout(push_constant, scalar) uniform Push { HermitePushConstants pc; };
layout(buffer_reference, scalar) readonly buffer HermiteObjectRef { HermiteObject value; };
layout(buffer_reference, scalar) readonly buffer CountersRef { uint counts[]; };

layout(set = 0, binding = 0) uniform sampler2D sceneDepth;
layout(set = 0, binding = 1) uniform usampler2D sceneVisibility;
layout(set = 0, binding = 2) uniform sampler2D sceneHitOffset;  // pixelRayHitOffset of the winner

layout(location = 0) out vec4 outColor;

void loadCell(HermiteObject object, uint record, out vec4 corners[8], out uvec3 cell) {
  uint xy, zc;
  if (object.halfPrecision == 0u) {
    CellRecordGpu r = CellRecordsRef(object.records).records[record];
    corners = r.corners;
    xy = r.xy;
    zc = r.zc;
  } else {
    CellRecordHalfGpu r = CellRecordsHalfRef(object.records).records[record];
    for (int i = 0; i < 8; ++i) corners[i] = vec4(unpackHalf2x16(r.corners[i].x), unpackHalf2x16(r.corners[i].y));
    xy = r.xy;
    zc = r.zc;
  }
  cell = uvec3(xy & 0xffffu, xy >> 16, zc & 0xffffu);
}

vec3 centralDifferenceGradient(vec4 corners[8], float h, vec3 u) {
  const float e = 1e-3;
  vec3 c = clamp(u, vec3(e), vec3(1.0 - e));
  return vec3(hermiteValue(corners, h, c + vec3(e, 0, 0)) - hermiteValue(corners, h, c - vec3(e, 0, 0)),
              hermiteValue(corners, h, c + vec3(0, e, 0)) - hermiteValue(corners, h, c - vec3(0, e, 0)),
              hermiteValue(corners, h, c + vec3(0, 0, e)) - hermiteValue(corners, h, c - vec3(0, 0, e))) /
         (2.0 * e * h);
}

// The hit in world space (eye at the origin), for the lights: off by a float ulp of the view
// distance, which lighting does not see; the normal and material come from the anchored hit.
vec3 worldHit(FrameGlobals frame, ivec2 pixel, float depth) {
  vec2 ndc = (vec2(pixel) + 0.5) * frame.viewport.zw * 2.0 - 1.0;
  vec4 view = frame.invProj * vec4(ndc, depth, 1.0);
  return (frame.invView * vec4(view.xyz / view.w, 1.0)).xyz;
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  uvec2 visible = texelFetch(sceneVisibility, pixel, 0).xy;
  if (visible.x == 0u) discard;
  ObjectData object = ObjectsRef(pc.draw.objects).objects[visible.x - 1u];
  if (object.feature != HERMITE_CELLS_FEATURE_ID) discard;
  HermiteObject hermite = HermiteObjectRef(object.payload).value;
  vec4 corners[8];
  uvec3 cell;
  loadCell(hermite, visible.y, corners, cell);

  // The hit in cell-local coordinates, rebuilt on the pixel's ray as the prepass based it, on the
  // anchor of this view region, at the offset it stored (pixel_ray.glsl, pixelRayStoredPoint): a
  // far camera costs it nothing, where the depth held it to ~0.5 cell 8e6 cells out.
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;
  float depth = texelFetch(sceneDepth, pixel, 0).r;
  vec4 anchor = hermiteDrawAt(pc.draws, hermite.drawRecord).rayAnchor;
  float h = hermite.gridOriginSpacing.w;
  float offset = texelFetch(sceneHitOffset, pixel, 0).r;
  vec3 u = clamp(pixelRayStoredPoint(frame, object.invModel, h, anchor - vec4(vec3(cell), 0.0), depth, offset), 0.0, 1.0);

  vec3 gradient = (hermite.flags & HERMITE_FLAG_NORMALS_CENTRAL) != 0u ? centralDifferenceGradient(corners, h, u)
                                                                        : hermiteValueGradient(corners, h, u).yzw;
  // Scaled by its largest component first: the squared length of a huge gradient (fields with
  // values near 1e30) would overflow float inside normalize() and give (1,1,1)/sqrt(3).
  float largest = max(max(abs(gradient.x), abs(gradient.y)), abs(gradient.z));
  if (largest > 0.0) gradient /= largest;
  vec3 normal = transpose(mat3(object.invModel)) * gradient;
  largest = max(max(abs(normal.x), abs(normal.y)), abs(normal.z));
  if (largest > 0.0) normal /= largest;
  normal = normalize(normal);

  vec3 color;
  if (pc.draw.debugView == DEBUG_VIEW_NORMALS) {
    color = debugNormalColor(normal);
  } else if (pc.draw.debugView == DEBUG_VIEW_DEPTH) {
    color = vec3(depth);
  } else if (pc.draw.debugView == DEBUG_VIEW_CELLS) {
    color = hashColor(cell);
  } else if (pc.draw.debugView == DEBUG_VIEW_EVALS && pc.counters != 0ul) {
    uint count = CountersRef(pc.counters).counts[pixel.y * int(frame.viewport.x) + pixel.x];
    color = heat(float(count) / 64.0);
  } else {
    vec3 base = object.color.rgb;
    float roughness = object.material.x;
    // A multi-material asset: the palette entry of the hit cell's corner nearest to the hit.
    if (hermite.palette != 0ul)
      applyPaletteEntry(hermite.palette, cellCornerSlot(hermite.materialSlots, visible.y - hermite.firstRecord, nearestCorner(u)),
                        base, roughness);
    color = shadeSurface(frame, base, roughness, worldHit(frame, pixel, depth), normal);
  }
  outColor = vec4(color, 1.0);
}
