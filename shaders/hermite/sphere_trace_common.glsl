// Sphere-tracing baselines: field access and the tracer, shared by the depth prepass and the
// shading pass. The including .frag selects the variant with defines:
//   SPHERE_TRACE_HERMITE   dense Hermite field, RGBA = (f, fx, fy, fz), corners fetched with
//                          texelFetch and evaluated as the tricubic Ferguson-Hermite interpolant;
//                          otherwise a trilinear field (R = f) read with hardware trilinear filtering.
//   SPHERE_TRACE_BINDLESS  one array of 3D textures indexed by SphereTraceDraw::texture;
//                          otherwise one texture per object in its own descriptor set.
// Positions are in grid units (object space / h, sample (i,j,k) at (i,j,k)); f is in object units.
#ifdef SPHERE_TRACE_BINDLESS
#extension GL_EXT_nonuniform_qualifier : require
#endif
#include "hermite/hermite_host_device.h"
#include "hermite/hermite.glsl"

layout(push_constant, scalar) uniform Push { SphereTracePushConstants pc; };
layout(buffer_reference, scalar) readonly buffer SphereTraceDrawsRef { SphereTraceDraw draws[]; };

#ifdef SPHERE_TRACE_BINDLESS
layout(set = 1, binding = 0) uniform sampler3D fieldTextures[];
#define FIELD_TEXTURE(draw) fieldTextures[nonuniformEXT((draw).texture)]
#else
layout(set = 1, binding = 0) uniform sampler3D fieldTexture;
#define FIELD_TEXTURE(draw) fieldTexture
#endif

// The cell whose interpolant covers grid position g (the last cell for g on the far faces).
ivec3 fieldCell(SphereTraceDraw draw, vec3 g) {
  return clamp(ivec3(floor(g)), ivec3(0), ivec3(int(draw.resolution) - 2));
}

vec4 fieldSample(SphereTraceDraw draw, ivec3 sampleIndex) {
  return texelFetch(FIELD_TEXTURE(draw), sampleIndex, 0);
}

#ifdef SPHERE_TRACE_HERMITE
// The corners of the last cell evaluated: sphere-tracing steps near the surface mostly stay in
// one cell, so its 8 fetches are reused.
struct FieldCursor {
  ivec3 cell;
  vec4 corners[8];
};

FieldCursor newFieldCursor() {
  FieldCursor cursor;
  cursor.cell = ivec3(-1);  // fieldCell() never returns it: the first evaluation fetches
  for (int c = 0; c < 8; ++c) cursor.corners[c] = vec4(0.0);
  return cursor;
}

void loadCell(SphereTraceDraw draw, ivec3 cell, out vec4 corners[8]) {
  for (int c = 0; c < 8; ++c) corners[c] = fieldSample(draw, cell + ivec3(c & 1, (c >> 1) & 1, c >> 2));
}

float evaluateField(SphereTraceDraw draw, inout FieldCursor cursor, vec3 g) {
  ivec3 cell = fieldCell(draw, g);
  if (cell != cursor.cell) {
    cursor.cell = cell;
    loadCell(draw, cell, cursor.corners);
  }
  return hermiteValue(cursor.corners, draw.gridOriginSpacing.w, g - vec3(cell));
}

// Exact gradient of the interpolant, object units.
vec3 exactFieldGradient(SphereTraceDraw draw, vec3 g) {
  ivec3 cell = fieldCell(draw, g);
  vec4 corners[8];
  loadCell(draw, cell, corners);
  return hermiteValueGradient(corners, draw.gridOriginSpacing.w, g - vec3(cell)).yzw;
}
#else
struct FieldCursor {
  int unused;
};

FieldCursor newFieldCursor() { return FieldCursor(0); }

// Texel centres: sample i sits at texture coordinate (i + 0.5) / K.
float evaluateField(SphereTraceDraw draw, inout FieldCursor cursor, vec3 g) {
  return texture(FIELD_TEXTURE(draw), (g + 0.5) / float(draw.resolution)).r;
}

// Exact gradient of the trilinear interpolant (not of the filtered texture, whose weights the
// hardware quantizes), object units: d/du along an axis is the bilinear interpolation of the four
// edge differences along that axis.
vec3 exactFieldGradient(SphereTraceDraw draw, vec3 g) {
  ivec3 cell = fieldCell(draw, g);
  vec3 u = g - vec3(cell);
  float f[8];
  for (int c = 0; c < 8; ++c) f[c] = fieldSample(draw, cell + ivec3(c & 1, (c >> 1) & 1, c >> 2)).r;
  vec4 dx = vec4(f[1] - f[0], f[3] - f[2], f[5] - f[4], f[7] - f[6]);  // ordered by (y, z)
  vec4 dy = vec4(f[2] - f[0], f[3] - f[1], f[6] - f[4], f[7] - f[5]);  // ordered by (x, z)
  vec4 dz = vec4(f[4] - f[0], f[5] - f[1], f[6] - f[2], f[7] - f[3]);  // ordered by (x, y)
  vec3 du = vec3(mix(mix(dx.x, dx.y, u.y), mix(dx.z, dx.w, u.y), u.z),
                 mix(mix(dy.x, dy.y, u.x), mix(dy.z, dy.w, u.x), u.z),
                 mix(mix(dz.x, dz.y, u.x), mix(dz.z, dz.w, u.x), u.y));
  return du / draw.gridOriginSpacing.w;
}
#endif

// f at grid position g, clamped to the grid (central differences reach past the faces).
float fieldValue(SphereTraceDraw draw, vec3 g) {
  FieldCursor cursor = newFieldCursor();
  return evaluateField(draw, cursor, clamp(g, vec3(0.0), vec3(float(draw.resolution - 1u))));
}

// Central differences of the interpolant with an offset of draw.centralStep grid units, object units.
vec3 centralFieldGradient(SphereTraceDraw draw, vec3 g) {
  float e = draw.centralStep;
  vec3 x = vec3(e, 0.0, 0.0), y = vec3(0.0, e, 0.0), z = vec3(0.0, 0.0, e);
  return vec3(fieldValue(draw, g + x) - fieldValue(draw, g - x), fieldValue(draw, g + y) - fieldValue(draw, g - y),
              fieldValue(draw, g + z) - fieldValue(draw, g - z)) /
         (2.0 * e * draw.gridOriginSpacing.w);
}

// Sphere tracing of origin + t * direction (grid units) over [t0, t1]: step by the interpolated
// distance until |f| < epsilon * h. A ray that starts inside the surface steps by -f and finds
// where it leaves; an overshoot (f changes sign) steps back. Returns the hit's t, or -1 on a miss
// (left the box, or the step limit ran out). `evaluations` counts field evaluations.
float sphereTrace(SphereTraceDraw draw, vec3 origin, vec3 direction, float t0, float t1, out uint evaluations) {
  float h = draw.gridOriginSpacing.w;
  float tPerGridUnit = 1.0 / length(direction);
  FieldCursor cursor = newFieldCursor();
  float t = t0;
  float d = evaluateField(draw, cursor, origin + t * direction) / h;  // grid units
  float side = d < 0.0 ? -1.0 : 1.0;
  evaluations = 1u;
  while (abs(d) >= draw.epsilon) {
    if (evaluations >= draw.maxSteps) return -1.0;
    t += side * d * tPerGridUnit;
    if (t > t1) return -1.0;
    d = evaluateField(draw, cursor, origin + t * direction) / h;
    ++evaluations;
  }
  return t;
}
