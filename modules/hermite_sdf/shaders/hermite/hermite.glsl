// Tricubic Ferguson–Hermite interpolation in GLSL: the same formulation as
// modules/hermite_sdf/include/hermite_sdf/core/hermite.h (read that header for the derivation).
// A cell is 8 corners (index x + 2y + 4z), each vec4(f, fx, fy, fz) with the gradient in world
// units; u in [0,1]^3 is the cell-local position and h the grid spacing.
#ifndef HSDF_HERMITE_GLSL
#define HSDF_HERMITE_GLSL

// (H0, H1, G0, G1) at t: values at 0 and 1, derivatives at 0 and 1.
vec4 hermiteBasis(float t) {
  float t2 = t * t;
  float t3 = t2 * t;
  return vec4(2.0 * t3 - 3.0 * t2 + 1.0, -2.0 * t3 + 3.0 * t2, t3 - 2.0 * t2 + t, t3 - t2);
}

// d/dt of hermiteBasis.
vec4 hermiteBasisDerivative(float t) {
  float t2 = t * t;
  return vec4(6.0 * t2 - 6.0 * t, -6.0 * t2 + 6.0 * t, 3.0 * t2 - 4.0 * t + 1.0, 3.0 * t2 - 2.0 * t);
}

float hermiteValue(vec4 corners[8], float h, vec3 u) {
  vec4 bx = hermiteBasis(u.x), by = hermiteBasis(u.y), bz = hermiteBasis(u.z);
  float value = 0.0;
  for (int c = 0; c < 8; ++c) {
    int sx = c & 1, sy = (c >> 1) & 1, sz = c >> 2;
    float hx = bx[sx], hy = by[sy], hz = bz[sz];
    float gx = bx[2 + sx], gy = by[2 + sy], gz = bz[2 + sz];
    vec4 s = corners[c];
    value += s.x * hx * hy * hz + h * (s.y * gx * hy * hz + s.z * hx * gy * hz + s.w * hx * hy * gz);
  }
  return value;
}

// vec4(F, grad F) with the gradient in world units: (1/h) dF/du.
vec4 hermiteValueGradient(vec4 corners[8], float h, vec3 u) {
  vec4 bx = hermiteBasis(u.x), by = hermiteBasis(u.y), bz = hermiteBasis(u.z);
  vec4 dx = hermiteBasisDerivative(u.x), dy = hermiteBasisDerivative(u.y), dz = hermiteBasisDerivative(u.z);
  float value = 0.0;
  vec3 du = vec3(0.0);
  for (int c = 0; c < 8; ++c) {
    int sx = c & 1, sy = (c >> 1) & 1, sz = c >> 2;
    float hx = bx[sx], hy = by[sy], hz = bz[sz];
    float gx = bx[2 + sx], gy = by[2 + sy], gz = bz[2 + sz];
    float dhx = dx[sx], dhy = dy[sy], dhz = dz[sz];
    float dgx = dx[2 + sx], dgy = dy[2 + sy], dgz = dz[2 + sz];
    vec4 s = corners[c];
    value += s.x * hx * hy * hz + h * (s.y * gx * hy * hz + s.z * hx * gy * hz + s.w * hx * hy * gz);
    du.x += s.x * dhx * hy * hz + h * (s.y * dgx * hy * hz + s.z * dhx * gy * hz + s.w * dhx * hy * gz);
    du.y += s.x * hx * dhy * hz + h * (s.y * gx * dhy * hz + s.z * hx * dgy * hz + s.w * hx * dhy * gz);
    du.z += s.x * hx * hy * dhz + h * (s.y * gx * hy * dhz + s.z * hx * gy * dhz + s.w * hx * hy * dgz);
  }
  return vec4(value, du / h);
}

// Ray / box [lo, hi] slab test: (tEnter, tExit); empty when tEnter > tExit.
vec2 intersectBox(vec3 origin, vec3 direction, vec3 lo, vec3 hi) {
  vec3 inverse = 1.0 / direction;  // +-inf for axis-parallel rays is handled by min/max
  vec3 ta = (lo - origin) * inverse;
  vec3 tb = (hi - origin) * inverse;
  vec3 tmin = min(ta, tb), tmax = max(ta, tb);
  return vec2(max(max(tmin.x, tmin.y), tmin.z), min(min(tmax.x, tmax.y), tmax.z));
}

vec2 intersectUnitBox(vec3 origin, vec3 direction) { return intersectBox(origin, direction, vec3(0.0), vec3(1.0)); }

#endif
