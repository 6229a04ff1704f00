#pragma once
// Cell maths: tricubic Ferguson–Hermite interpolation, its Bernstein form, trilinear interpolation,
// and the restriction of a cell to a ray segment. Plain templates over float/double so that the
// CPU reference, the tests and (re-implemented literally) the GLSL shaders share one formulation.
//
// Conventions (see DESIGN.md):
// - A cell has 8 corners; corner index = x + 2y + 4z with x,y,z in {0,1}.
// - Cell-local coordinates u in [0,1]^3; world x = o + h*(c + u).
// - Corner data are the value f and the gradient (fx,fy,fz) in WORLD units; the basis functions
//   work in u, so derivative data are scaled by h, and grad_world F = (1/h) dF/du.
// - 1D cubic Hermite basis: H0 = 2t^3-3t^2+1, H1 = -2t^3+3t^2, G0 = t^3-2t^2+t, G1 = t^3-t^2.
// - Ferguson (zero twist) tricubic:
//     F(u) = sum_c f_c Hx Hy Hz + h (fx_c Gx Hy Hz + fy_c Hx Gy Hz + fz_c Hx Hy Gz)
//   with each factor the basis function of corner c's side on that axis.
// - Bernstein form: F = sum b[a + 4b + 16c] B_a(ux) B_b(uy) B_c(uz) with cubic Bernstein B.
//   Derivation: a 1D cubic with end values p0,p1 and end derivatives d0,d1 (w.r.t. t) has
//   Bernstein coefficients (p0, p0 + d0/3, p1 - d1/3, p1), so H0 = B0+B1, H1 = B2+B3,
//   G0 = B1/3, G1 = -B2/3. Multiplying out the tensor products, every coefficient (a,b,c) comes
//   from the single corner (a>=2, b>=2, c>=2) and, with s(0)=s(3)=0, s(1)=+1, s(2)=-1,
//     b_abc = f_corner + (h/3) (s(a) fx + s(b) fy + s(c) fz).
//   (The twist terms that would mix axes are zero by the Ferguson assumption.)
#include <array>
#include <cstddef>

#include <glm/glm.hpp>

namespace hsdf {

template <class T>
using Vec3 = glm::vec<3, T, glm::defaultp>;

// One corner's data: value and world-space gradient. For T = float the layout equals HermiteSample.
template <class T>
struct HermiteCorner {
  T f = T(0);
  T fx = T(0);
  T fy = T(0);
  T fz = T(0);
};

template <class T>
using HermiteCellCorners = std::array<HermiteCorner<T>, 8>;

template <class T>
using TrilinearCellCorners = std::array<T, 8>;

// 64 Bernstein coefficients of a tricubic cell, index a + 4b + 16c (a along x).
template <class T>
using BernsteinCell = std::array<T, 64>;

template <class T>
struct ValueGradient {
  T value = T(0);
  Vec3<T> gradient{T(0)};  // world units
};

constexpr int cornerIndex(int x, int y, int z) { return x + 2 * y + 4 * z; }
constexpr int bernsteinIndex(int a, int b, int c) { return a + 4 * b + 16 * c; }

// The four 1D Hermite basis functions (or their derivatives) at one parameter value.
template <class T>
struct HermiteBasis1D {
  T h0, h1, g0, g1;
  T value(int side) const { return side == 0 ? h0 : h1; }
  T slope(int side) const { return side == 0 ? g0 : g1; }
};

template <class T>
constexpr HermiteBasis1D<T> hermiteBasis(T t) {
  const T t2 = t * t;
  const T t3 = t2 * t;
  return {T(2) * t3 - T(3) * t2 + T(1), T(-2) * t3 + T(3) * t2, t3 - T(2) * t2 + t, t3 - t2};
}

template <class T>
constexpr HermiteBasis1D<T> hermiteBasisDerivative(T t) {
  const T t2 = t * t;
  return {T(6) * t2 - T(6) * t, T(-6) * t2 + T(6) * t, T(3) * t2 - T(4) * t + T(1), T(3) * t2 - T(2) * t};
}

// Ferguson–Hermite value at cell-local u.
template <class T>
T hermiteValue(const HermiteCellCorners<T>& corners, T h, const Vec3<T>& u) {
  const HermiteBasis1D<T> bx = hermiteBasis(u.x), by = hermiteBasis(u.y), bz = hermiteBasis(u.z);
  T sum = T(0);
  for (int c = 0; c < 8; ++c) {
    const int sx = c & 1, sy = (c >> 1) & 1, sz = (c >> 2) & 1;
    const HermiteCorner<T>& k = corners[c];
    const T hx = bx.value(sx), hy = by.value(sy), hz = bz.value(sz);
    sum += k.f * hx * hy * hz +
           h * (k.fx * bx.slope(sx) * hy * hz + k.fy * hx * by.slope(sy) * hz + k.fz * hx * hy * bz.slope(sz));
  }
  return sum;
}

// Ferguson–Hermite value and exact gradient (world units) at cell-local u.
template <class T>
ValueGradient<T> hermiteValueGradient(const HermiteCellCorners<T>& corners, T h, const Vec3<T>& u) {
  const HermiteBasis1D<T> b[3] = {hermiteBasis(u.x), hermiteBasis(u.y), hermiteBasis(u.z)};
  const HermiteBasis1D<T> d[3] = {hermiteBasisDerivative(u.x), hermiteBasisDerivative(u.y),
                                  hermiteBasisDerivative(u.z)};
  ValueGradient<T> out;
  Vec3<T> dFdu(T(0));
  for (int c = 0; c < 8; ++c) {
    const int side[3] = {c & 1, (c >> 1) & 1, (c >> 2) & 1};
    const HermiteCorner<T>& k = corners[c];
    const T slope[3] = {h * k.fx, h * k.fy, h * k.fz};  // derivative data in u units
    // Each corner term is a sum of 4 triple products; along axis `a` the factor is either the
    // value basis H (for f and for slopes of other axes) or the slope basis G (for slope a).
    for (int term = 0; term < 4; ++term) {  // term 0: f, term 1..3: slope along axis term-1
      const T weight = term == 0 ? k.f : slope[term - 1];
      T factor[3], dfactor[3];
      for (int a = 0; a < 3; ++a) {
        const bool useSlope = term - 1 == a;
        factor[a] = useSlope ? b[a].slope(side[a]) : b[a].value(side[a]);
        dfactor[a] = useSlope ? d[a].slope(side[a]) : d[a].value(side[a]);
      }
      out.value += weight * factor[0] * factor[1] * factor[2];
      dFdu.x += weight * dfactor[0] * factor[1] * factor[2];
      dFdu.y += weight * factor[0] * dfactor[1] * factor[2];
      dFdu.z += weight * factor[0] * factor[1] * dfactor[2];
    }
  }
  out.gradient = dFdu / h;
  return out;
}

// The 64 Bernstein coefficients of a cell (formula and derivation in the header comment).
template <class T>
BernsteinCell<T> toBernstein(const HermiteCellCorners<T>& corners, T h) {
  constexpr int kSlopeSign[4] = {0, 1, -1, 0};
  const T third = h / T(3);
  BernsteinCell<T> out{};
  for (int c = 0; c < 4; ++c)
    for (int b = 0; b < 4; ++b)
      for (int a = 0; a < 4; ++a) {
        const HermiteCorner<T>& k = corners[cornerIndex(a >= 2, b >= 2, c >= 2)];
        out[bernsteinIndex(a, b, c)] =
            k.f + third * (T(kSlopeSign[a]) * k.fx + T(kSlopeSign[b]) * k.fy + T(kSlopeSign[c]) * k.fz);
      }
  return out;
}

// One de Casteljau reduction of N+1 coefficients at t (the value of a degree-N Bernstein polynomial).
// Unrolled (GCC leaves the triangular loop rolled, through memory: 4-5x slower at degree 9); the
// reference caster's root search evaluates this ~50 times per hit.
template <class T, std::size_t N>
T bernsteinValue1D(std::array<T, N> p, T t) {
#pragma GCC unroll 16
  for (std::size_t level = 1; level < N; ++level)
#pragma GCC unroll 16
    for (std::size_t i = 0; i + level < N; ++i) p[i] = (T(1) - t) * p[i] + t * p[i + 1];
  return p[0];
}

// Value of the tricubic Bernstein form at u by de Casteljau along x, then y, then z.
template <class T>
T bernsteinValue(const BernsteinCell<T>& coeffs, const Vec3<T>& u) {
  std::array<T, 4> alongZ{};
  for (int c = 0; c < 4; ++c) {
    std::array<T, 4> alongY{};
    for (int b = 0; b < 4; ++b) {
      const std::array<T, 4> row = {coeffs[bernsteinIndex(0, b, c)], coeffs[bernsteinIndex(1, b, c)],
                                    coeffs[bernsteinIndex(2, b, c)], coeffs[bernsteinIndex(3, b, c)]};
      alongY[b] = bernsteinValue1D(row, u.x);
    }
    alongZ[c] = bernsteinValue1D(alongY, u.y);
  }
  return bernsteinValue1D(alongZ, u.z);
}

// Splits 1D Bernstein coefficients at t into the coefficients of [0,t] and [t,1] (rescaled to [0,1]).
template <class T, std::size_t N>
void subdivideBernstein1D(const std::array<T, N>& p, T t, std::array<T, N>& left, std::array<T, N>& right) {
  std::array<T, N> work = p;
  left[0] = work[0];
  right[N - 1] = work[N - 1];
#pragma GCC unroll 16
  for (std::size_t level = 1; level < N; ++level) {
#pragma GCC unroll 16
    for (std::size_t i = 0; i + level < N; ++i) work[i] = (T(1) - t) * work[i] + t * work[i + 1];
    left[level] = work[0];
    right[N - 1 - level] = work[N - 1 - level];
  }
}

// Splits a tricubic Bernstein cell at u = 1/2 on every axis into 8 children, child index
// x + 2y + 4z (x = 1: upper half along x). Each child is again in Bernstein form on [0,1]^3.
template <class T>
std::array<BernsteinCell<T>, 8> subdivideBernsteinCell(const BernsteinCell<T>& coeffs) {
  // Split along one axis at a time: stride of that axis in the 4x4x4 coefficient block.
  auto splitAxis = [](const BernsteinCell<T>& in, int stride, BernsteinCell<T>& lo, BernsteinCell<T>& hi) {
    for (int base = 0; base < 64; ++base) {
      if ((base / stride) % 4 != 0) continue;  // visit each line along the axis once
      const std::array<T, 4> line = {in[base], in[base + stride], in[base + 2 * stride], in[base + 3 * stride]};
      std::array<T, 4> l{}, r{};
      subdivideBernstein1D(line, T(0.5), l, r);
      for (int i = 0; i < 4; ++i) {
        lo[base + i * stride] = l[i];
        hi[base + i * stride] = r[i];
      }
    }
  };
  std::array<BernsteinCell<T>, 2> halvesX{};
  splitAxis(coeffs, 1, halvesX[0], halvesX[1]);
  std::array<BernsteinCell<T>, 8> children{};
  for (int x = 0; x < 2; ++x) {
    BernsteinCell<T> lowY{}, highY{};
    splitAxis(halvesX[x], 4, lowY, highY);
    splitAxis(lowY, 16, children[cornerIndex(x, 0, 0)], children[cornerIndex(x, 0, 1)]);
    splitAxis(highY, 16, children[cornerIndex(x, 1, 0)], children[cornerIndex(x, 1, 1)]);
  }
  return children;
}

// Trilinear value at cell-local u.
template <class T>
T trilinearValue(const TrilinearCellCorners<T>& f, const Vec3<T>& u) {
  const T x00 = f[0] + u.x * (f[1] - f[0]);
  const T x10 = f[2] + u.x * (f[3] - f[2]);
  const T x01 = f[4] + u.x * (f[5] - f[4]);
  const T x11 = f[6] + u.x * (f[7] - f[6]);
  const T y0 = x00 + u.y * (x10 - x00);
  const T y1 = x01 + u.y * (x11 - x01);
  return y0 + u.z * (y1 - y0);
}

// Trilinear value and its gradient (world units, cell spacing h) at cell-local u.
template <class T>
ValueGradient<T> trilinearValueGradient(const TrilinearCellCorners<T>& f, T h, const Vec3<T>& u) {
  ValueGradient<T> out;
  out.value = trilinearValue(f, u);
  for (int axis = 0; axis < 3; ++axis) {
    // d/du_axis of a trilinear function is the bilinear interpolation of the edge differences.
    const int stride = 1 << axis;
    T diff[4];  // edge differences along `axis`, ordered by the two other axes (lower axis first)
    int n = 0;
    for (int c = 0; c < 8; ++c)
      if ((c & stride) == 0) diff[n++] = f[c + stride] - f[c];
    const int first = axis == 0 ? 1 : 0, second = axis == 2 ? 1 : 2;
    const T a = diff[0] + u[first] * (diff[1] - diff[0]);
    const T b = diff[2] + u[first] * (diff[3] - diff[2]);
    out.gradient[axis] = (a + u[second] * (b - a)) / h;
  }
  return out;
}

constexpr double binomial(int n, int k) {
  double r = 1.0;
  for (int i = 1; i <= k; ++i) r = r * double(n - k + i) / double(i);
  return r;
}

// Restriction of a tensor-product Bernstein cell of degree N per axis (N = 3: tricubic, N = 1:
// trilinear, coefficients = corner values) to the segment u(s) = (1-s) u0 + s u1, s in [0,1]:
// the result is a 1D polynomial of degree 3N, returned as its 3N+1 Bernstein coefficients in s.
//
// How: B_a(u_x(s)) is a degree-N polynomial in s whose Bernstein coefficients are blossom values
// of B_a at (u0 x (N-j) times, u1 x j times); call them M_x[a][j] (all >= 0, columns sum to 1).
// Then F(s) = sum_ijk T_ijk B_i(s) B_j(s) B_k(s) with T = coeffs transformed by M_x, M_y, M_z,
// and B^N_i B^N_j B^N_k = C(N,i)C(N,j)C(N,k)/C(3N,i+j+k) B^{3N}_{i+j+k}. Every output
// coefficient is a convex combination of the input ones, so strict signs carry over.
// The reference caster calls this for every cell a ray searches, so it is written for speed:
// the blossoms of all N+1 basis functions run side by side (one de Casteljau lane each, from the
// unit vectors) and share their levels at u0; strides are compile-time constants. Every value
// goes through the same floating-point operations in the same order as the plain formulation
// (de Casteljau per basis function and j, sums over a from 0, outputs accumulated k, j, i), so
// the results are bit for bit those of the plain loops.
template <int N, class T>
std::array<T, 3 * N + 1> restrictToSegment(const std::array<T, (N + 1) * (N + 1) * (N + 1)>& coeffs,
                                           const Vec3<T>& u0, const Vec3<T>& u1) {
  constexpr int n1 = N + 1;
  using Lanes = std::array<std::array<T, n1>, n1>;  // [i][a]: de Casteljau entry i of basis function a
  // blossom[axis][j][a] = M_axis[a][j]
  T blossom[3][n1][n1];
  for (int axis = 0; axis < 3; ++axis) {
    const T t0 = u0[axis], t1 = u1[axis];
    std::array<Lanes, n1> atU0{};  // after `level` levels at u0
    for (int a = 0; a < n1; ++a) atU0[0][a][a] = T(1);
    for (int level = 1; level <= N; ++level)
      for (int i = 0; i + level < n1; ++i)
        for (int a = 0; a < n1; ++a)
          atU0[level][i][a] = (T(1) - t0) * atU0[level - 1][i][a] + t0 * atU0[level - 1][i + 1][a];
    for (int j = 0; j < n1; ++j) {  // N-j levels at u0, then j at u1
      Lanes p = atU0[N - j];
      for (int level = N - j + 1; level <= N; ++level)
        for (int i = 0; i + level < n1; ++i)
          for (int a = 0; a < n1; ++a) p[i][a] = (T(1) - t1) * p[i][a] + t1 * p[i + 1][a];
      for (int a = 0; a < n1; ++a) blossom[axis][j][a] = p[0][a];
    }
  }
  // Transform axis by axis (index a + n1*b + n1*n1*c throughout): x, then y, then z.
  constexpr int n2 = n1 * n1;
  T alongX[n2 * n1], alongY[n2 * n1], alongZ[n2 * n1];
  for (int bc = 0; bc < n2; ++bc)
    for (int j = 0; j < n1; ++j) {
      T sum = T(0);
      for (int a = 0; a < n1; ++a) sum += coeffs[std::size_t(a + n1 * bc)] * blossom[0][j][a];
      alongX[j + n1 * bc] = sum;
    }
  for (int c = 0; c < n1; ++c)
    for (int j = 0; j < n1; ++j)
      for (int i = 0; i < n1; ++i) {
        T sum = T(0);
        for (int b = 0; b < n1; ++b) sum += alongX[i + n1 * b + n2 * c] * blossom[1][j][b];
        alongY[i + n1 * j + n2 * c] = sum;
      }
  for (int k = 0; k < n1; ++k)
    for (int ij = 0; ij < n2; ++ij) {
      T sum = T(0);
      for (int c = 0; c < n1; ++c) sum += alongY[ij + n2 * c] * blossom[2][k][c];
      alongZ[ij + n2 * k] = sum;
    }
  struct Weights {
    double w[n1][n1][n1];  // [k][j][i]
  };
  static constexpr Weights kWeights = [] {
    Weights out{};
    for (int k = 0; k < n1; ++k)
      for (int j = 0; j < n1; ++j)
        for (int i = 0; i < n1; ++i)
          out.w[k][j][i] = binomial(N, i) * binomial(N, j) * binomial(N, k) / binomial(3 * N, i + j + k);
    return out;
  }();
  std::array<T, 3 * N + 1> out{};
  for (int k = 0; k < n1; ++k)
    for (int j = 0; j < n1; ++j)
      for (int i = 0; i < n1; ++i)
        out[std::size_t(i + j + k)] += T(kWeights.w[k][j][i]) * alongZ[i + n1 * j + n2 * k];
  return out;
}

}  // namespace hsdf
