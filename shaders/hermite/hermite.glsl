// Tricubic Ferguson–Hermite interpolation in GLSL: the same formulation as
// modules/hermite_sdf/include/hermite_sdf/hermite.h (read that header for the derivation).
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

// Places the root of a bracket [a, b] (fa and fb of different sign or zero): by linear
// interpolation (the paper's method), or, when a third sample (c, fc) before the bracket is known,
// by the root of the parabola through the three samples, which follows the curvature of F along
// the ray at no extra cost (it falls back to the line when the parabola has no root in [a, b]).
float placeRoot(float a, float fa, float b, float fb, bool hasThird, float c, float fc) {
  float linear = (fa == fb) ? a : a + (b - a) * (fa / (fa - fb));
  if (!hasThird) return linear;
  // Newton's divided differences: q(t) = fa + s1 (t - a) + s2 (t - a)(t - b).
  float s1 = (fb - fa) / (b - a);
  float s2 = ((fa - fc) / (a - c) - s1) / (c - b);
  float t = linear;
  for (int i = 0; i < 3; ++i) {  // Newton on the parabola from the linear guess
    float q = fa + (t - a) * (s1 + s2 * (t - b));
    float dq = s1 + s2 * (2.0 * t - a - b);
    if (dq == 0.0) break;
    t -= q / dq;
  }
  return (t >= min(a, b) && t <= max(a, b)) ? t : linear;
}

// Refines a root placed in the bracket [a, b] with `refineSteps` safeguarded Newton steps on F
// along the ray u(t) = origin + t * direction: each step evaluates F and its exact derivative,
// shrinks the bracket, and takes the Newton step if it stays inside, else the secant of the new
// bracket. `evaluations` counts evaluations of F (value and gradient together count as one).
float refineRoot(vec4 corners[8], float h, vec3 origin, vec3 direction, float t, float a, float fa, float b, float fb,
                 uint refineSteps, inout uint evaluations) {
  for (uint i = 0u; i < refineSteps; ++i) {
    vec4 fg = hermiteValueGradient(corners, h, origin + t * direction);
    ++evaluations;
    float ft = fg.x;
    if (ft == 0.0) return t;
    if ((fa < 0.0) != (ft < 0.0)) {
      b = t;
      fb = ft;
    } else {
      a = t;
      fa = ft;
    }
    float slope = h * dot(fg.yzw, direction);  // dF/dt: the gradient is in world units
    float newton = slope != 0.0 ? t - ft / slope : a - 1.0;
    t = (newton > a && newton < b) ? newton : ((fa == fb) ? a : a + (b - a) * (fa / (fa - fb)));
  }
  return t;
}

// The paper's subdivision search: F at n+1 equidistant points of [t0, t1]; the first sign change
// (or zero) brackets the root. Returns the root's t, or -1 when there is no sign change.
float findFirstRoot(vec4 corners[8], float h, vec3 origin, vec3 direction, float t0, float t1, uint subdivisions,
                    uint refineSteps, inout uint evaluations) {
  float previousT = t0;
  float previousF = hermiteValue(corners, h, origin + t0 * direction);
  float olderT = t0, olderF = previousF;
  ++evaluations;
  if (previousF == 0.0) return t0;
  float step = (t1 - t0) / float(subdivisions);
  for (uint i = 1u; i <= subdivisions; ++i) {
    float t = (i == subdivisions) ? t1 : t0 + step * float(i);
    float f = hermiteValue(corners, h, origin + t * direction);
    ++evaluations;
    if (f == 0.0 || (previousF < 0.0) != (f < 0.0)) {
      float guess = placeRoot(previousT, previousF, t, f, i >= 2u, olderT, olderF);
      return refineRoot(corners, h, origin, direction, guess, previousT, previousF, t, f, refineSteps, evaluations);
    }
    olderT = previousT;
    olderF = previousF;
    previousT = t;
    previousF = f;
  }
  return -1.0;
}

// Ray / unit box [0,1]^3 slab test: (tEnter, tExit); empty when tEnter > tExit.
vec2 intersectUnitBox(vec3 origin, vec3 direction) {
  vec3 inverse = 1.0 / direction;  // +-inf for axis-parallel rays is handled by min/max
  vec3 ta = (vec3(0.0) - origin) * inverse;
  vec3 tb = (vec3(1.0) - origin) * inverse;
  vec3 tmin = min(ta, tb), tmax = max(ta, tb);
  return vec2(max(max(tmin.x, tmin.y), tmin.z), min(min(tmax.x, tmax.y), tmax.z));
}

#endif
