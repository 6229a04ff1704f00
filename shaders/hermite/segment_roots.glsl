// Root search of a Hermite cell along one ray segment, on F restricted to the segment.
//
// Restricted to a line, the tricubic F is a polynomial of degree <= 9 in the line parameter. It is
// built once per fragment, directly in Bernstein form on the segment (s in [0,1]), from the cubic
// Hermite basis functions at the two ends of the segment; then
//   - all 10 coefficients of one strict sign prove that the segment holds no root (convex hull):
//     the fragment is rejected without sampling (most box fragments that miss the surface);
//   - the paper's search samples the polynomial at n+1 equidistant points (de Casteljau, far cheaper
//     than a tricubic evaluation), brackets the first sign change, places the root by linear (or
//     parabolic) interpolation and refines it with safeguarded Newton steps on the polynomial;
//   - a pair of roots between two samples (a thin feature, a grazing ray) shows no sign change:
//     once the samples bracket a root at s, the coefficients of F on [0, s] prove by Descartes'
//     rule that it is the only root there, or the certified search below finds the first; with no
//     bracket at all, the certified search decides whenever the coefficients do not exclude a
//     root. So the paper's search never passes through a surface; only its placement of the root
//     (interpolation and `refine` Newton steps) is approximate (docs/root-finding.md);
//   - the certified mode (HERMITE_FLAG_CERTIFIED) skips the samples and always runs the certified
//     search: the first root of the restricted polynomial, placed to 2^-18 of its interval.
// The math is derived in modules/hermite_sdf/include/hermite_sdf/hermite.h (restrictToSegment: the
// same polynomial, built there from the 64 tensor Bernstein coefficients) and the rules for roots
// on shared cell faces are in docs/root-finding.md.
#ifndef HSDF_SEGMENT_ROOTS_GLSL
#define HSDF_SEGMENT_ROOTS_GLSL

#include "hermite/hermite.glsl"

#define SEGMENT_DEGREE 9
#define SEGMENT_COEFFS 10

// The Bernstein coefficients of a cubic p on s in [0,1] follow from its values and derivatives at
// the ends: (p(0), p(0) + p'(0)/3, p(1) - p'(1)/3, p(1)). Here for the four Hermite basis
// functions (H0, H1, G0, G1) of one axis at once, u(s) = a + s (b - a), scaled by the binomial
// weights (1, 3, 3, 1) so that products of such polynomials are plain convolutions.
void axisBasisScaledBernstein(float a, float b, out vec4 k[4]) {
  float d = (b - a) / 3.0;
  vec4 pa = hermiteBasis(a), pb = hermiteBasis(b);
  k[0] = pa;
  k[1] = 3.0 * (pa + d * hermiteBasisDerivative(a));
  k[2] = 3.0 * (pb - d * hermiteBasisDerivative(b));
  k[3] = pb;
}

// Scaled Bernstein coefficients (times C(6, m)) of the product of two cubics given scaled.
void multiplyCubics(float p[4], float q[4], out float r[7]) {
  for (int m = 0; m < 7; ++m) r[m] = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r[i + j] += p[i] * q[j];
}

// Bernstein coefficients (degree 9, s in [0,1]) of F along the segment from cell-local u0 to u1.
// F = sum over corners of f Hx Hy Hz + h (fx Gx Hy Hz + fy Hx Gy Hz + fz Hx Hy Gz), grouped by the
// x factor: F = sum over x sides of Hx * QH + Gx * QG, with QH, QG products of y and z cubics.
void restrictToSegment(vec4 corners[8], float h, vec3 u0, vec3 u1, out float b[SEGMENT_COEFFS]) {
  vec4 kx[4], ky[4], kz[4];
  axisBasisScaledBernstein(u0.x, u1.x, kx);
  axisBasisScaledBernstein(u0.y, u1.y, ky);
  axisBasisScaledBernstein(u0.z, u1.z, kz);
  float qh[2][7], qg[2][7];
  for (int side = 0; side < 2; ++side)
    for (int m = 0; m < 7; ++m) {
      qh[side][m] = 0.0;
      qg[side][m] = 0.0;
    }
  for (int sy = 0; sy < 2; ++sy)
    for (int sz = 0; sz < 2; ++sz) {
      float hy[4], gy[4], hz[4], gz[4];
      for (int i = 0; i < 4; ++i) {
        hy[i] = ky[i][sy];
        gy[i] = ky[i][2 + sy];
        hz[i] = kz[i][sz];
        gz[i] = kz[i][2 + sz];
      }
      float hh[7], gh[7], hg[7];
      multiplyCubics(hy, hz, hh);
      multiplyCubics(gy, hz, gh);
      multiplyCubics(hy, gz, hg);
      for (int sx = 0; sx < 2; ++sx) {
        vec4 s = corners[sx + 2 * sy + 4 * sz];
        for (int m = 0; m < 7; ++m) {
          qh[sx][m] += s.x * hh[m] + h * (s.z * gh[m] + s.w * hg[m]);
          qg[sx][m] += h * s.y * hh[m];
        }
      }
    }
  const float binomial9[SEGMENT_COEFFS] = float[](1.0, 9.0, 36.0, 84.0, 126.0, 126.0, 84.0, 36.0, 9.0, 1.0);
  for (int k = 0; k < SEGMENT_COEFFS; ++k) b[k] = 0.0;
  for (int sx = 0; sx < 2; ++sx)
    for (int i = 0; i < 4; ++i) {
      float hx = kx[i][sx], gx = kx[i][2 + sx];
      for (int m = 0; m < 7; ++m) b[i + m] += hx * qh[sx][m] + gx * qg[sx][m];
    }
  for (int k = 0; k < SEGMENT_COEFFS; ++k) b[k] /= binomial9[k];
}

// Value and derivative (d/ds) of the Bernstein polynomial at s, by de Casteljau (stable in float).
vec2 bernsteinValueDerivative(float b[SEGMENT_COEFFS], float s) {
  float c[SEGMENT_COEFFS] = b;
  for (int level = SEGMENT_DEGREE; level > 1; --level)
    for (int i = 0; i < level; ++i) c[i] = mix(c[i], c[i + 1], s);
  return vec2(mix(c[0], c[1], s), float(SEGMENT_DEGREE) * (c[1] - c[0]));
}

float bernsteinValue(float b[SEGMENT_COEFFS], float s) { return bernsteinValueDerivative(b, s).x; }

// The coefficients of the same polynomial on the sub-interval [s0, s1] of [0,1] (two de Casteljau
// splits: keep [s0, 1], then its left part up to s1).
void bernsteinSubSegment(float b[SEGMENT_COEFFS], float s0, float s1, out float c[SEGMENT_COEFFS]) {
  c = b;
  if (s0 > 0.0) {
    for (int level = SEGMENT_DEGREE; level > 0; --level)
      for (int i = 0; i < level; ++i) c[i] = mix(c[i], c[i + 1], s0);  // c[i] becomes the right part's
  }
  float split = s0 < 1.0 ? (s1 - s0) / (1.0 - s0) : 1.0;
  if (split < 1.0) {
    for (int level = SEGMENT_DEGREE; level > 0; --level)
      for (int i = SEGMENT_DEGREE; i > SEGMENT_DEGREE - level; --i) c[i] = mix(c[i - 1], c[i], split);
  }
}

// +1 / -1 when every coefficient is strictly of that sign (no root by the convex hull), else 0.
int strictSign(float c[SEGMENT_COEFFS]) {
  float lo = c[0], hi = c[0];
  for (int i = 1; i < SEGMENT_COEFFS; ++i) {
    lo = min(lo, c[i]);
    hi = max(hi, c[i]);
  }
  return lo > 0.0 ? 1 : (hi < 0.0 ? -1 : 0);
}

int signVariations(float c[SEGMENT_COEFFS]) {
  int variations = 0;
  float previous = 0.0;
  for (int i = 0; i < SEGMENT_COEFFS; ++i) {
    if (c[i] == 0.0) continue;
    if (previous != 0.0 && (previous < 0.0) != (c[i] < 0.0)) ++variations;
    previous = c[i];
  }
  return variations;
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

// `steps` safeguarded Newton steps on the polynomial from the guess s inside the bracket [a, b]
// (fa, fb of different sign or zero): each step shrinks the bracket and takes the Newton step if it
// stays inside, else the secant of the new bracket. Counts one evaluation per step.
float refineInBracket(float c[SEGMENT_COEFFS], float s, float a, float fa, float b, float fb, uint steps,
                      inout uint evaluations) {
  for (uint i = 0u; i < steps; ++i) {
    vec2 fd = bernsteinValueDerivative(c, s);
    ++evaluations;
    if (fd.x == 0.0) return s;
    if ((fa < 0.0) != (fd.x < 0.0)) {
      b = s;
      fb = fd.x;
    } else {
      a = s;
      fa = fd.x;
    }
    float newton = fd.y != 0.0 ? s - fd.x / fd.y : a - 1.0;
    s = (newton > a && newton < b) ? newton : ((fa == fb) ? a : a + (b - a) * (fa / (fa - fb)));
  }
  return s;
}

// The root of a polynomial with exactly one root in [0,1] (end values of opposite sign, one sign
// variation): Newton steps kept inside a shrinking bracket, bisecting whenever a step leaves it or
// does not halve it, until the bracket is below kRootWidth of the interval. Certified search only:
// its interval may be the whole segment, where the paper's one refinement step is not enough.
const float kRootWidth = 1.0 / 262144.0;

float solveUniqueRoot(float c[SEGMENT_COEFFS], inout uint evaluations) {
  float a = 0.0, b = 1.0;
  bool startNegative = c[0] < 0.0;
  float s = placeRoot(0.0, c[0], 1.0, c[SEGMENT_DEGREE], false, 0.0, 0.0);
  for (int i = 0; i < 32 && b - a > kRootWidth; ++i) {
    vec2 fd = bernsteinValueDerivative(c, s);
    ++evaluations;
    if (fd.x == 0.0) return s;
    float width = b - a;
    if ((fd.x < 0.0) == startNegative) a = s; else b = s;
    float newton = fd.y != 0.0 ? s - fd.x / fd.y : -1.0;
    s = (newton > a && newton < b && b - a < 0.5 * width) ? newton : 0.5 * (a + b);
  }
  return s;
}

// Certified first root of the polynomial on [0,1]: a depth-first walk over dyadic sub-intervals,
// left to right, without a stack. An interval whose coefficients are all of one strict sign holds no
// root (convex hull) and is skipped; one whose end values differ in sign with a single sign
// variation holds exactly one root (Descartes), which is solved; anything else is halved. An
// interval narrower than kCertifiedMinWidth that cannot be excluded is a contact (F touches zero
// within rounding) and reported at its middle; so is running out of the step budget, which keeps
// the search bounded on adversarial data. Returns -1 when [0,1] holds no root.
const float kCertifiedMinWidth = 1.0 / 65536.0;
const int kCertifiedMaxSteps = 96;

float certifiedFirstRoot(float b[SEGMENT_COEFFS], inout uint evaluations) {
  float a = 0.0, w = 1.0;
  for (int step = 0; step < kCertifiedMaxSteps; ++step) {
    float c[SEGMENT_COEFFS];
    bernsteinSubSegment(b, a, a + w, c);
    ++evaluations;
    if (strictSign(c) != 0) {
      a += w;  // next interval in depth-first order: climb while this one was a right child
      while (w < 1.0 && mod(a, 2.0 * w) == 0.0) w *= 2.0;
      if (a >= 1.0) return -1.0;
      continue;
    }
    if (c[0] == 0.0) return a;
    bool endsDiffer = c[SEGMENT_DEGREE] == 0.0 || (c[0] < 0.0) != (c[SEGMENT_DEGREE] < 0.0);
    if (endsDiffer && signVariations(c) <= 1) return a + w * solveUniqueRoot(c, evaluations);
    if (w <= kCertifiedMinWidth) return a + 0.5 * w;
    w *= 0.5;  // descend into the left half
  }
  return a;
}

// The first root on [0,1] of the restricted polynomial b: the fast rejection, then the paper's
// equidistant search with `subdivisions` intervals (or the certified search). -1: no root.
float segmentFirstRoot(float b[SEGMENT_COEFFS], uint subdivisions, uint refineSteps, bool certified,
                       inout uint evaluations) {
  if (strictSign(b) != 0) return -1.0;
  if (certified) return certifiedFirstRoot(b, evaluations);
  float previousS = 0.0, previousF = b[0];
  float olderS = 0.0, olderF = b[0];
  if (previousF == 0.0) return 0.0;
  float step = 1.0 / float(subdivisions);
  for (uint i = 1u; i <= subdivisions; ++i) {
    float s = (i == subdivisions) ? 1.0 : step * float(i);
    float f = (i == subdivisions) ? b[SEGMENT_DEGREE] : bernsteinValue(b, s);
    ++evaluations;
    if (f == 0.0 || (previousF < 0.0) != (f < 0.0)) {
      // The samples before s agree in sign, but a pair of roots may hide between two of them (a
      // thin feature in front of the surface), or the bracket may hold three roots. One split
      // gives F on [0, s]: a single sign variation of its coefficients proves that the bracket's
      // root is the only one there (Descartes), and the paper's interpolation places it;
      // otherwise the certified search finds the first.
      float head[SEGMENT_COEFFS];
      bernsteinSubSegment(b, 0.0, s, head);
      ++evaluations;
      float first = signVariations(head) > 1 ? certifiedFirstRoot(head, evaluations) : -1.0;
      if (first >= 0.0) return s * first;
      float guess = placeRoot(previousS, previousF, s, f, i >= 2u, olderS, olderF);
      return refineInBracket(b, guess, previousS, previousF, s, f, refineSteps, evaluations);
    }
    olderS = previousS;
    olderF = previousF;
    previousS = s;
    previousF = f;
  }
  // No sign change among the samples, but the coefficients do not rule a root out: a pair of roots
  // (or a touching contact) may lie between two samples.
  return certifiedFirstRoot(b, evaluations);
}

#endif
