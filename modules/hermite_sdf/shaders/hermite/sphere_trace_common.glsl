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
  int cell;  // fieldCellKey of the cell whose corners these are
  vec4 corners[8];
};

FieldCursor newFieldCursor() {
  FieldCursor cursor;
  cursor.cell = -1;  // no cell's key: the first evaluation fetches
  for (int c = 0; c < 8; ++c) cursor.corners[c] = vec4(0.0);
  return cursor;
}

// One int per cell of the grid (fieldCell's, all >= 0; below 2^31 for every K up to
// SPHERE_TRACE_MAX_RESOLUTION, which the host enforces): the cursor that the march carries holds one register for its cell, not an ivec3. Every
// register held through the march counts at the peak, the interpolant's evaluation: the anchor's
// base and view depth, held for the depth and the hit offset, took the depth prepass from 72 to 76
// VGPRs on NAVI10 (12 subgroups per SIMD, not 14); the key brings it back
// (docs/perf/render-changes-session41.md).
int fieldCellKey(SphereTraceDraw draw, ivec3 cell) {
  int k = int(draw.resolution);
  return cell.x + k * (cell.y + k * cell.z);
}

void loadCell(SphereTraceDraw draw, ivec3 cell, out vec4 corners[8]) {
  for (int c = 0; c < 8; ++c) corners[c] = fieldSample(draw, cell + ivec3(c & 1, (c >> 1) & 1, c >> 2));
}

float evaluateField(SphereTraceDraw draw, inout FieldCursor cursor, vec3 g) {
  ivec3 cell = fieldCell(draw, g);
  int key = fieldCellKey(draw, cell);
  if (key != cursor.cell) {
    cursor.cell = key;
    loadCell(draw, cell, cursor.corners);
  }
  return hermiteValue(cursor.corners, draw.gridOriginSpacing.w, g - vec3(cell));
}

// The tracer already evaluates the exact interpolant (in float, from texelFetch'ed corners): the
// placement of a hit goes on with the tracer's cursor.
#define ExactCache FieldCursor
ExactCache newExactCache(FieldCursor cursor) { return cursor; }
float exactFieldValue(SphereTraceDraw draw, inout ExactCache cache, vec3 g) { return evaluateField(draw, cache, g); }

// Exact gradient of the interpolant, object units.
vec3 exactFieldGradient(SphereTraceDraw draw, vec3 g) {
  ivec3 cell = fieldCell(draw, g);
  vec4 corners[8];
  loadCell(draw, cell, corners);
  return hermiteValueGradient(corners, draw.gridOriginSpacing.w, g - vec3(cell)).yzw;
}
#else
// The filtered steps need no state.
struct FieldCursor {
  int unused;
};

FieldCursor newFieldCursor() { return FieldCursor(0); }

// The 8 texels of `cell` (clamped to the grid: the filter's clamp-to-edge), as two vec4s: lo the
// x = 0 corners, hi the x = 1 corners, each ordered by (y, z).
void cellTexels(SphereTraceDraw draw, ivec3 cell, out vec4 lo, out vec4 hi) {
  ivec3 last = ivec3(int(draw.resolution) - 1);
  float f[8];
  for (int c = 0; c < 8; ++c) f[c] = fieldSample(draw, clamp(cell + ivec3(c & 1, (c >> 1) & 1, c >> 2), ivec3(0), last)).r;
  lo = vec4(f[0], f[2], f[4], f[6]);
  hi = vec4(f[1], f[3], f[5], f[7]);
}

// Trilinear interpolation of a cell's texels (cellTexels) at fractions w, in float.
float mixTexels(vec4 lo, vec4 hi, vec3 w) {
  vec4 x = mix(lo, hi, w.x);  // ordered by (y, z)
  vec2 y = mix(x.xz, x.yw, w.y);
  return mix(y.x, y.y, w.z);
}

// What a GPU filter unit that rounds its weights to draw.filterBits fractional bits returns at g
// (clamp-to-edge): the 8 texels around g, mixed in float with the rounded fractions. Only tests and
// experiments set filterBits, to see a quantizing GPU's images on a device that filters in float.
float quantizedFilter(SphereTraceDraw draw, vec3 g) {
  float scale = float(1u << draw.filterBits);
  vec3 base = floor(g);
  vec4 lo, hi;
  cellTexels(draw, ivec3(base), lo, hi);
  return mixTexels(lo, hi, floor((g - base) * scale + 0.5) / scale);
}

// Texel centres: sample i sits at texture coordinate (i + 0.5) / K. The hardware filter is fast
// but may quantize its weights (8 fractional bits on many GPUs), so it only guides the steps far
// from the surface (evaluateField); hits are placed with exactFieldValue.
float filteredField(SphereTraceDraw draw, vec3 g) {
  if (draw.filterBits != 0u) return quantizedFilter(draw, g);
  // textureLod: inside the tracing loop implicit derivatives are undefined (non-uniform control flow).
  return textureLod(FIELD_TEXTURE(draw), (g + 0.5) / float(draw.resolution), 0.0).r;
}

// The trilinear interpolant itself at g: its cell's 8 texels fetched and mixed in float.
float exactTrilinear(SphereTraceDraw draw, vec3 g) {
  ivec3 cell = fieldCell(draw, g);
  vec4 lo, hi;
  cellTexels(draw, cell, lo, hi);
  return mixTexels(lo, hi, g - vec3(cell));
}

// Below draw.exactBelow (grid units, from the filter's weight precision: SphereTraceFeature::
// exactBelowCells) a step trusts the exact interpolant, not the filter. Above it the filtered sign
// is the exact one and the step is a sphere-tracing step on a value off by a small fraction of
// itself; below it every decision (epsilon, sign change, step length) is taken on the exact
// interpolant, as the dense Hermite tracer does. Quantized GPUs otherwise left rays creeping or
// oscillating at the surface until their step limit (H200: ~40 rays out of steps per 1080p view;
// the emulated 8-bit filter here: holes and out-of-steps rays in the sphere-tracing tests).
float evaluateField(SphereTraceDraw draw, inout FieldCursor cursor, vec3 g) {
  float filtered = filteredField(draw, g);
  if (abs(filtered) >= draw.exactBelow * draw.gridOriginSpacing.w) return filtered;
  return exactTrilinear(draw, g);
}

// The texels of the cell last evaluated exactly, kept while a hit is placed (a few evaluations,
// mostly in one cell). Only the placement carries it: carried through the stepping loop, it made
// lavapipe's prepass several times slower.
struct ExactCache {
  ivec3 cell;
  vec4 lo;  // x = 0 corners, ordered by (y, z)
  vec4 hi;  // x = 1 corners
};

ExactCache newExactCache(FieldCursor cursor) { return ExactCache(ivec3(-1), vec4(0.0), vec4(0.0)); }

// The trilinear interpolant itself: its cell's 8 texels fetched and interpolated in float.
float exactFieldValue(SphereTraceDraw draw, inout ExactCache cache, vec3 g) {
  ivec3 cell = fieldCell(draw, g);
  if (cell != cache.cell) {
    cache.cell = cell;
    cellTexels(draw, cell, cache.lo, cache.hi);
  }
  return mixTexels(cache.lo, cache.hi, g - vec3(cell));
}

// Exact gradient of the trilinear interpolant (not of the filtered texture, whose weights the
// hardware quantizes), object units: d/du along an axis is the bilinear interpolation of the four
// edge differences along that axis.
vec3 exactFieldGradient(SphereTraceDraw draw, vec3 g) {
  ivec3 cell = fieldCell(draw, g);
  vec3 u = g - vec3(cell);
  vec4 lo, hi;  // corner c = x + 2y + 4z: lo = (f0, f2, f4, f6), hi = (f1, f3, f5, f7)
  cellTexels(draw, cell, lo, hi);
  vec4 dx = hi - lo;                                                        // ordered by (y, z)
  vec4 dy = vec4(lo.y - lo.x, hi.y - hi.x, lo.w - lo.z, hi.w - hi.z);      // ordered by (x, z)
  vec4 dz = vec4(lo.z - lo.x, hi.z - hi.x, lo.w - lo.y, hi.w - hi.y);      // ordered by (x, y)
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

// A ray of the tracer in grid units, and what tracing it cost.
struct TraceRay {
  vec3 origin;
  vec3 direction;
  float tPerGridUnit;  // 1 / |direction|
};

float exactAt(SphereTraceDraw draw, inout ExactCache cache, TraceRay ray, float t) {
  return exactFieldValue(draw, cache, ray.origin + t * ray.direction) / draw.gridOriginSpacing.w;
}

// The root of the exact interpolant between ta and tb, where its values fa and fb (grid units)
// have opposite signs: Illinois (regula falsi that halves a stale end) until |f| < epsilon.
const uint kBracketSteps = 12u;
float rootInBracket(SphereTraceDraw draw, inout ExactCache cache, TraceRay ray, float ta, float fa, float tb,
                    float fb, inout uint evaluations) {
  int kept = 0;  // which end the last step kept: -1 a, 1 b
  for (uint i = 0u; i < kBracketSteps; ++i) {
    float t = (ta * fb - tb * fa) / (fb - fa);
    float f = exactAt(draw, cache, ray, t);
    ++evaluations;
    if (abs(f) < draw.epsilon) return t;
    if ((f < 0.0) == (fb < 0.0)) {
      tb = t;
      fb = f;
      if (kept == -1) fa *= 0.5;
      kept = -1;
    } else {
      ta = t;
      fa = f;
      if (kept == 1) fb *= 0.5;
      kept = 1;
    }
  }
  return (ta * fb - tb * fa) / (fb - fa);
}

// Where placing a hit on the exact interpolant ended: at t, whose exact value is f (grid units);
// converged when that is a hit.
struct Settled {
  float t;
  float f;
  bool converged;
};

// Places a hit the tracer found near t on the exact interpolant: a few sphere-tracing steps on
// exact values from t (either way along the ray: forward while outside, back once inside), the
// first sign change between two of them bracketing the root. `side` is the sign of f where the
// ray started (-1: it started inside). Not converged: the exact field has no root near t (a
// coarse filter put the filtered surface where the exact one is not), and the ray goes on from
// the returned t. Hermite: the tracer's values are exact, nothing to do.
const uint kSettleSteps = 8u;
Settled settleOnExact(SphereTraceDraw draw, inout ExactCache cache, TraceRay ray, float t, float d, float side,
                      inout uint evaluations) {
#ifdef SPHERE_TRACE_HERMITE
  return Settled(t, d, true);
#else
  float f = exactAt(draw, cache, ray, t);
  ++evaluations;
  for (uint i = 0u; i < kSettleSteps && abs(f) >= draw.epsilon; ++i) {
    float tNext = t + side * f * ray.tPerGridUnit;
    float fNext = exactAt(draw, cache, ray, tNext);
    ++evaluations;
    if (fNext * f < 0.0) return Settled(rootInBracket(draw, cache, ray, t, f, tNext, fNext, evaluations), 0.0, true);
    t = tNext;
    f = fNext;
  }
  return Settled(t, f, abs(f) < draw.epsilon);
#endif
}

// A sign change of the traced values between ta and tb: the hit, placed on the exact interpolant.
// Trilinear: the filtered values may disagree in sign with the exact ones near the surface. When
// the exact values at both ends lie beyond the surface, the exact surface is before ta (settled
// from there); when both lie on the ray's side, the filter invented the crossing: not converged,
// the ray goes on from tb with its exact distance.
Settled hitInBracket(SphereTraceDraw draw, inout ExactCache cache, TraceRay ray, float ta, float fa, float tb,
                     float fb, float side, inout uint evaluations) {
#ifndef SPHERE_TRACE_HERMITE
  fa = exactAt(draw, cache, ray, ta);
  fb = exactAt(draw, cache, ray, tb);
  evaluations += 2u;
  if (abs(fa) < draw.epsilon) return Settled(ta, fa, true);
  if (abs(fb) < draw.epsilon) return Settled(tb, fb, true);
  if (fa * fb > 0.0) {
    if (fa * side > 0.0) return Settled(tb, fb, false);
    Settled back = settleOnExact(draw, cache, ray, ta, fa, side, evaluations);
    back.converged = true;  // the best place for a surface the ray has passed
    return back;
  }
#endif
  return Settled(rootInBracket(draw, cache, ray, ta, fa, tb, fb, evaluations), 0.0, true);
}

// The shortest step, grid units. A ray that passes the surface at a distance just above epsilon
// would creep along it in steps of that distance (one bunny ray at K = 32 took more than 1024
// steps). A longer step that lands inside the surface is a sign change, found and placed exactly
// (hitInBracket); only a sliver thinner than this along the ray can be stepped over.
const float kMinStep = 1.0 / 64.0;

struct TraceResult {
  float t;             // the hit's t, or -1 on a miss
  uint evaluations;    // field evaluations (filtered and exact)
  bool outOfSteps;     // the step limit ran out before a hit or the box's end: a miss, counted
  bool startedInside;  // the ray's first point was inside the surface (f < 0): it hit the surface's back
};

// How many times a ray may go on after a crossing that the exact interpolant did not confirm (a
// coarse filter's, hitInBracket / settleOnExact) before it gives up as out of steps.
const uint kMaxUnconfirmed = 4u;

// Sphere tracing of origin + t * direction (grid units) over [0, t1]: step by the interpolated
// distance f. The hit is the first of: |f| < epsilon * h (the paper's test, where it can be
// reached), or a sign change of f between two steps (an overshoot: hardware-filtered values may
// never fall below epsilon, and a field that is not an exact distance can step through the
// surface); either is placed on the exact interpolant. A ray that starts inside the surface steps
// by -f and finds where it leaves. Leaving the box, or running out of steps (maxSteps), misses;
// the latter is reported so that it is counted, never silently dropped.
// The steps and the placement are separate loops: the placement's evaluations run once per ray,
// after the stepping loop, not inside it where every lane of a SIMD group or warp would wait for
// each other lane's placement in turn (10x the prepass on lavapipe).
TraceResult traceFromStart(SphereTraceDraw draw, vec3 origin, vec3 direction, float t1) {
  float h = draw.gridOriginSpacing.w;
  TraceRay ray = TraceRay(origin, direction, 1.0 / length(direction));
  FieldCursor cursor = newFieldCursor();
  TraceResult result = TraceResult(-1.0, 1u, false, false);
  float t = 0.0;
  float d = evaluateField(draw, cursor, origin) / h;  // grid units, what the next step trusts
  float side = d < 0.0 ? -1.0 : 1.0;
  result.startedInside = d < 0.0;
  // The ray's first point is never a hit by epsilon alone: there the surface may lie just behind
  // it, on the clipped side of the near plane (an eye pressed against a wall, the near plane a
  // hair beyond the wall: the tracer drew the wall at the near plane, where nothing nearer than
  // the plane is drawn). The first step finds a surface just ahead by its sign change instead.
  bool first = true;
  for (uint attempt = 0u; attempt < kMaxUnconfirmed; ++attempt) {
    float tNext = t;
    float dNext = d;
    while (first || abs(d) >= draw.epsilon) {
      first = false;
      if (result.evaluations >= draw.maxSteps) {
        result.outOfSteps = true;
        return result;
      }
      tNext = t + max(side * d, kMinStep) * ray.tPerGridUnit;
      if (tNext > t1) return result;
      dNext = evaluateField(draw, cursor, origin + tNext * direction) / h;
      ++result.evaluations;
      if (dNext * side < 0.0) break;
      t = tNext;
      d = dNext;
    }
    bool crossed = dNext * side < 0.0;
    ExactCache cache = newExactCache(cursor);
    Settled settled = crossed ? hitInBracket(draw, cache, ray, t, d, tNext, dNext, side, result.evaluations)
                              : settleOnExact(draw, cache, ray, t, d, side, result.evaluations);
    if (settled.converged || (!crossed && settled.f * side <= 0.0)) {
      result.t = settled.t;
      return result;
    }
    // The exact interpolant has no root here: go on with its distance.
    t = crossed ? tNext : settled.t;
    d = settled.f;
  }
  result.outOfSteps = true;
  return result;
}

// The ray is re-based at its first point, t0. The camera's t is about 1 at the box (t = 1 on the
// rasterized face): with the camera far away (|direction| past ~5e5 grid units: an orthographic
// camera placed back along its axis, a telephoto lens) every step would be shorter than half a
// float ulp of that t, t + step == t, and the ray would stand until its step limit. Counted from
// t0, the steps add to a t that starts at 0; the hit's t is t0 + that, rounded once.
TraceResult sphereTrace(SphereTraceDraw draw, vec3 origin, vec3 direction, float t0, float t1) {
  TraceResult result = traceFromStart(draw, origin + t0 * direction, direction, t1 - t0);
  if (result.t >= 0.0) result.t += t0;
  return result;
}
