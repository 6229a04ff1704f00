// Root search of a Hermite cell along one ray segment, on F restricted to the segment.
//
// Restricted to a line, the tricubic F is a polynomial of degree <= 9 in the line parameter. It is
// built once per fragment, directly in Bernstein form on the segment (s in [0,1]), from the cubic
// Hermite basis functions at the two ends of the segment; then
//   - all 10 coefficients of one strict sign prove that the segment holds no root (convex hull):
//     the fragment is rejected without sampling (most box fragments that miss the surface);
//   - one walk over sub-intervals does the paper's search and its certification together
//     (segmentFirstRoot below): the paper's n equal intervals, left to right, each decided by its
//     own coefficients (no root / exactly one root / halve), so a pair of roots between two
//     samples (a thin feature, a grazing ray) is never passed over; a unique root is placed at the
//     zero of the control polygon and refined by `refine` safeguarded Newton steps, so only the
//     root's placement is approximate (docs/root-finding.md);
//   - the certified mode (HERMITE_FLAG_CERTIFIED) walks from the whole segment and places the
//     first root to 2^-18 of its interval.
// The math is derived in modules/hermite_sdf/include/hermite_sdf/core/hermite.h (restrictToSegment: the
// same polynomial, built there from the 64 tensor Bernstein coefficients) and the rules for roots
// on shared cell faces are in docs/root-finding.md.
#ifndef HSDF_SEGMENT_ROOTS_GLSL
#define HSDF_SEGMENT_ROOTS_GLSL

#include "hermite/hermite.glsl"

#define SEGMENT_DEGREE 9
#define SEGMENT_COEFFS 10

// The Bernstein coefficients of a cubic p on s in [0,1] follow from its values and derivatives at
// the ends: (p(0), p(0) + p'(0)/3, p(1) - p'(1)/3, p(1)). Here for the two Hermite basis functions
// of one axis that weight the corners on `side` (0: H0 and G0, 1: H1 and G1), u(s) = a + s (b - a),
// scaled by the binomial weights (1, 3, 3, 1) so that products of such polynomials are plain
// convolutions. One side at a time, where it is used (addZSide): a y or z side's 8 floats are then
// live only while that side is summed.
void sideCubics(float a, float b, int side, out vec4 value, out vec4 slope) {
  float d = (b - a) / 3.0;
  vec4 pa = hermiteBasis(a), pb = hermiteBasis(b);
  vec4 ka = 3.0 * (pa + d * hermiteBasisDerivative(a)), kb = 3.0 * (pb - d * hermiteBasisDerivative(b));
  value = vec4(pa[side], ka[side], kb[side], pb[side]);
  slope = vec4(pa[2 + side], ka[2 + side], kb[2 + side], pb[2 + side]);
}

// The same cubics from the mirrored axis (H_side(t) = H_(1-side)(1 - t), G_side(t) = -G_(1-side)(1 - t)):
// the same polynomials, rounded differently. The second z side builds its y cubics this way on
// purpose (addZSide): built the same way as the first side's, the compiler merges the two and keeps
// the first side's y and z cubics (16 + 8 floats) live through the whole second side.
void sideCubicsMirrored(float a, float b, int side, out vec4 value, out vec4 slope) {
  sideCubics(1.0 - a, 1.0 - b, 1 - side, value, slope);
  slope = -slope;
}

// The scaled cubic of the constant 1 (H0 + H1 = 1).
const vec4 kScaledOne = vec4(1.0, 3.0, 3.0, 1.0);

// Scaled coefficients of the product of a scaled cubic and a scaled degree-6 polynomial, added to r.
void addCubicTimesSextic(vec4 p, float q[7], inout float r[SEGMENT_COEFFS]) {
  for (int i = 0; i < 4; ++i)
    for (int m = 0; m < 7; ++m) r[i + m] += p[i] * q[m];
}

// The part of the restriction (restrictToSegment below) from the four corners of one z side:
// corner x + 2y + 4 sz is side[x + 2y]. Added to the scaled coefficients b.
void addZSide(vec4 side[4], int sz, float h, vec3 u0, vec3 u1, inout float b[SEGMENT_COEFFS]) {
  vec4 x0, gx0, x1, gx1;  // x1 goes unused: H1 = 1 - H0 (below)
  sideCubics(u0.x, u1.x, 0, x0, gx0);
  sideCubics(u0.x, u1.x, 1, x1, gx1);
  float d[7], e[7];
  for (int m = 0; m < 7; ++m) {
    d[m] = 0.0;
    e[m] = 0.0;
  }
  for (int sy = 0; sy < 2; ++sy) {
    vec4 s0 = side[2 * sy], s1 = side[1 + 2 * sy];
    // H0 + H1 = 1, so sum_x f Hx = f1 (1, 3, 3, 1) + (f0 - f1) H0 in scaled form: H1's cubic is
    // never built or held (4 registers fewer through the whole restriction, and fewer products).
    vec4 cubicA = s1.x * kScaledOne + (s0.x - s1.x) * x0 + h * (s0.y * gx0 + s1.y * gx1);
    vec4 cubicB = h * (s1.z * kScaledOne + (s0.z - s1.z) * x0);
    vec4 cubicC = h * (s1.w * kScaledOne + (s0.w - s1.w) * x0);
    vec4 y, gy;  // mirrored on the second z side: not merged with the first side's (above)
    if (sz == 0)
      sideCubics(u0.y, u1.y, sy, y, gy);
    else
      sideCubicsMirrored(u0.y, u1.y, sy, y, gy);
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        d[i + j] += y[i] * cubicA[j] + gy[i] * cubicB[j];
        e[i + j] += y[i] * cubicC[j];
      }
  }
  vec4 z, gz;  // the same on z: the second side's cubics share no arithmetic with the first's
  if (sz == 0)
    sideCubics(u0.z, u1.z, sz, z, gz);
  else
    sideCubicsMirrored(u0.z, u1.z, sz, z, gz);
  addCubicTimesSextic(z, d, b);
  addCubicTimesSextic(gz, e, b);
}

// Scaled coefficients (times the binomial weights of degree 9) to Bernstein coefficients.
void fromScaledBernstein(inout float b[SEGMENT_COEFFS]) {
  const float binomial9[SEGMENT_COEFFS] = float[](1.0, 9.0, 36.0, 84.0, 126.0, 126.0, 84.0, 36.0, 9.0, 1.0);
  for (int k = 0; k < SEGMENT_COEFFS; ++k) b[k] /= binomial9[k];
}

// Bernstein coefficients (degree 9, s in [0,1]) of F along the segment from cell-local u0 to u1.
// F = sum over corners of f Hx Hy Hz + h (fx Gx Hy Hz + fy Hx Gy Hz + fz Hx Hy Gz), summed inside
// out to share the products: per (y, z) side, the x cubics A = sum_x (f Hx + h fx Gx),
// B = sum_x h fy Hx, C = sum_x h fz Hx; per z side, D = sum_y (Hy A + Gy B), E = sum_y Hy C
// (degree 6); F = sum_z (Hz D + Gz E). In scaled Bernstein form (coefficients times the binomial
// weights) products are plain convolutions.
// Shaped for register pressure, which sets how many fragments a GPU keeps in flight (the prepass
// runs this once per box fragment): the two z sides are two calls with constant corner indices, so
// a side's corners are read (cell_search.glsl: loaded from memory) just before they are summed
// and die after, and the y and z cubics are built where they are used, the second side's mirrored
// (sideCubicsMirrored) so that the compiler cannot merge them with the first side's and hold those
// through the second; only the x cubics (H0, G0, G1), b and the running d, e live through. A loop
// over the z sides that indexed the corners by sz kept all 32 corner floats and all three axes'
// cubics live at once: 128 VGPRs on RDNA1 where this needs 68 (docs/perf/render-changes-session31.md,
// render-changes-session32.md). The same polynomial; only the x sums are rearranged (H0 + H1 = 1)
// and the second side's y and z cubics mirrored, which changes float rounding, not the roots.
void restrictToSegment(vec4 corners[8], float h, vec3 u0, vec3 u1, out float b[SEGMENT_COEFFS]) {
  for (int k = 0; k < SEGMENT_COEFFS; ++k) b[k] = 0.0;
  addZSide(vec4[4](corners[0], corners[1], corners[2], corners[3]), 0, h, u0, u1, b);
  addZSide(vec4[4](corners[4], corners[5], corners[6], corners[7]), 1, h, u0, u1, b);
  fromScaledBernstein(b);
}

// Value and derivative (d/ds) of the Bernstein polynomial at s, by de Casteljau (stable in float).
vec2 bernsteinValueDerivative(float b[SEGMENT_COEFFS], float s) {
  float c[SEGMENT_COEFFS] = b;
  for (int level = SEGMENT_DEGREE; level > 1; --level)
    for (int i = 0; i < level; ++i) c[i] = mix(c[i], c[i + 1], s);
  return vec2(mix(c[0], c[1], s), float(SEGMENT_DEGREE) * (c[1] - c[0]));
}

// Splits the polynomial at s in one de Casteljau pass: c becomes its coefficients on [s, 1], left
// its coefficients on [0, s] (the first coefficient of each level).
void bernsteinSplit(inout float c[SEGMENT_COEFFS], float s, out float left[SEGMENT_COEFFS]) {
  left[0] = c[0];
  for (int level = SEGMENT_DEGREE; level > 0; --level) {
    for (int i = 0; i < level; ++i) c[i] = mix(c[i], c[i + 1], s);
    left[SEGMENT_COEFFS - level] = c[0];
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

// The root of a polynomial with exactly one root in [0,1] (end values of opposite sign, or a zero
// end, and one sign variation): the zero of its control polygon (below), then up to
// `steps` safeguarded Newton steps that keep the root bracketed. A Newton step that leaves the
// bracket is replaced by the secant of the new bracket (regula falsi), and in certified mode also
// one that does not halve it, by bisection, which guarantees convergence; certified mode stops
// once the bracket is narrower than kRootWidth. The paper's refinement is steps = r; the certified
// mode asks for 32. Counts one evaluation per step.
const float kRootWidth = 1.0 / 262144.0;

// Where the control polygon of a polynomial with one sign variation crosses zero: the linear
// interpolation between the two coefficients of different sign. It is the paper's linear
// interpolation between the interval's ends when F is linear along the interval, and follows the
// curvature of F where it is not (the polygon converges to the curve quadratically as the interval
// shrinks), so one Newton step lands closer than from the chord.
float controlPolygonRoot(float c[SEGMENT_COEFFS]) {
  float s = 0.5;
  bool found = false;
  for (int i = 0; i < SEGMENT_DEGREE; ++i) {
    bool crosses = !found && (c[i] == 0.0 || (c[i] < 0.0) != (c[i + 1] < 0.0));
    float local = c[i] == c[i + 1] ? 0.0 : c[i] / (c[i] - c[i + 1]);
    s = crosses ? (float(i) + local) / float(SEGMENT_DEGREE) : s;
    found = found || crosses;
  }
  return s;
}

float solveInBracket(float c[SEGMENT_COEFFS], uint steps, bool certified, inout uint evaluations) {
  float fa = c[0], fb = c[SEGMENT_DEGREE];
  if (fa == 0.0) return 0.0;
  if (fb == 0.0) return 1.0;
  float a = 0.0, b = 1.0;
  float s = controlPolygonRoot(c);
  float width = certified ? kRootWidth : 0.0;
  for (uint i = 0u; i < steps && b - a > width; ++i) {
    vec2 fd = bernsteinValueDerivative(c, s);
    ++evaluations;
    if (fd.x == 0.0) break;  // s is the root; a return here leaves the result unset on the loop's other paths
    float previousWidth = b - a;
    if ((fd.x < 0.0) == (fa < 0.0)) {
      a = s;
      fa = fd.x;
    } else {
      b = s;
      fb = fd.x;
    }
    float newton = fd.y != 0.0 ? s - fd.x / fd.y : -1.0;
    bool inside = newton > a && newton < b;
    bool halving = b - a < 0.5 * previousWidth;
    float secant = a + (b - a) * (fa / (fa - fb));
    s = inside && (halving || !certified) ? newton : (certified ? 0.5 * (a + b) : secant);
  }
  return s;
}

// The first root on [0,1] of the restricted polynomial b, or -1 when there is none. One walk does
// the paper's search and its certification together: [0,1] is cut into `subdivisions` equal
// intervals (the paper's n equidistant samples are their ends), visited left to right. An
// interval's coefficients (one de Casteljau split of the rest of b, which starts where the last
// interval ended) decide it:
//   - all of one strict sign: no root (convex hull), go to the next interval;
//   - end values of different sign (or a zero end) and one sign variation: exactly one root
//     (Descartes), the first; placed by linear interpolation of the ends and `refineSteps`
//     safeguarded Newton steps (certified: solved to kRootWidth of the interval);
//   - otherwise (a pair of roots between two samples, a grazing ray, three roots in a bracket):
//     halved, left half first, down to kMinWidth of the segment, where a contact (F touching zero
//     within rounding) is reported at the interval's middle; running out of kMaxSteps (adversarial
//     data) reports the current interval the same way, so the search is bounded.
// Where the samples show a simple sign change this is exactly the paper's search; elsewhere it
// never passes through a surface (docs/root-finding.md). The walk keeps no stack: the interval is
// (index, level) with width top / 2^level, and finishing a right child climbs to the parent. It is
// one loop with one body on purpose: on SIMD hardware, and on lavapipe, where every branch of the
// shader is executed for a whole block of fragments, each separate rare path costs every fragment
// (docs/perf/cells-breakdown-lavapipe.md).
const float kMinWidth = 1.0 / 65536.0;
const int kMaxSteps = 96;

float segmentFirstRoot(float b[SEGMENT_COEFFS], uint subdivisions, uint refineSteps, bool certified,
                       inout uint evaluations) {
  if (strictSign(b) != 0) return -1.0;  // the whole segment at once: most fragments stop here
  uint topCount = certified ? 1u : max(subdivisions, 1u);
  float top = 1.0 / float(topCount);
  uint index = 0u;
  int level = 0;
  float w = top, a = 0.0;
  // Set here though every step sets it before it is read: the compiler cannot see that, and an
  // unset c would live on from the last search of a fragment that walks several cells (runs,
  // bricks, tiles), 10 registers through the whole next restriction.
  float c[SEGMENT_COEFFS] = b;
  float rest[SEGMENT_COEFFS] = b;  // the polynomial on [a, 1]: every interval starts where one ended
  int outcome = 0;  // 0: no root, 1: a unique root in [a, a + w], 2: a contact at a + w / 2
  for (int step = 0; step < kMaxSteps; ++step) {
    a = float(index) * w;
    // One split of the rest gives the interval's coefficients and, should it be excluded, the rest
    // after it: half the work of cutting each interval out of b (two splits), and the intervals
    // tile [0, 1] exactly.
    float after[SEGMENT_COEFFS] = rest;
    bernsteinSplit(after, a < 1.0 ? min(w / (1.0 - a), 1.0) : 1.0, c);
    ++evaluations;
    bool excluded = strictSign(c) != 0;
    bool endsDiffer = c[0] == 0.0 || c[SEGMENT_DEGREE] == 0.0 || (c[0] < 0.0) != (c[SEGMENT_DEGREE] < 0.0);
    if (!excluded && endsDiffer && signVariations(c) <= 1) {
      outcome = 1;
      break;
    }
    if (!excluded) {
      if (w <= kMinWidth || step == kMaxSteps - 1) {
        outcome = 2;
        break;
      }
      index *= 2u;  // descend into the left half
      w *= 0.5;
      ++level;
      continue;
    }
    // The next interval; a finished right child climbs to its parent's successor (as many levels
    // as the new index has trailing zero bits, without a loop). Either way it starts at a + w.
    rest = after;
    ++index;
    int climb = min(findLSB(index), level);
    index >>= uint(climb);
    level -= climb;
    w = top * exp2(-float(level));
    if (level == 0 && index >= topCount) break;
  }
  // The placement sits outside the walk so that its loop is not part of every walk step.
  if (outcome == 1) return a + w * solveInBracket(c, certified ? 32u : refineSteps, certified, evaluations);
  return outcome == 2 ? a + 0.5 * w : -1.0;
}

#endif
