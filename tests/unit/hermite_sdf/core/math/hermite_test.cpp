// Tricubic Ferguson–Hermite, Bernstein and trilinear cell maths.
#include "hermite_sdf/core/hermite.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace hsdf {
namespace {

using dvec3 = Vec3<double>;

HermiteCellCorners<double> randomCorners(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  HermiteCellCorners<double> corners{};
  for (auto& c : corners) c = {value(rng), 3.0 * value(rng), 3.0 * value(rng), 3.0 * value(rng)};
  return corners;
}

dvec3 randomU(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  return {unit(rng), unit(rng), unit(rng)};
}

// Tricky: the gradient must come out in world units (divided by h) and each corner's slope must
// pick the right side of the basis; a swapped G0/G1 or a missing 1/h breaks it for h != 1.
TEST(HermiteCell, InterpolatesCornerValuesAndGradients) {
  std::mt19937_64 rng(1);
  for (int trial = 0; trial < 50; ++trial) {
    const auto corners = randomCorners(rng);
    const double h = 0.37;
    for (int c = 0; c < 8; ++c) {
      const dvec3 u(c & 1, (c >> 1) & 1, (c >> 2) & 1);
      const ValueGradient<double> vg = hermiteValueGradient(corners, h, u);
      EXPECT_NEAR(vg.value, corners[c].f, 1e-12);
      EXPECT_NEAR(hermiteValue(corners, h, u), corners[c].f, 1e-12);
      EXPECT_NEAR(vg.gradient.x, corners[c].fx, 1e-12);
      EXPECT_NEAR(vg.gradient.y, corners[c].fy, 1e-12);
      EXPECT_NEAR(vg.gradient.z, corners[c].fz, 1e-12);
    }
  }
}

// Tricky: continuity must hold for arbitrary (non-SDF) data, for the gradient as well as the value,
// across faces normal to each of the three axes; it fails if any basis derivative at 0/1 is wrong.
TEST(HermiteCell, IsC1AcrossSharedFaces) {
  std::mt19937_64 rng(2);
  const double h = 0.8;
  for (int axis = 0; axis < 3; ++axis) {
    for (int trial = 0; trial < 40; ++trial) {
      // Three samples along `axis` (cells A = [0,1], B = [1,2]) times 2x2 across it.
      HermiteCellCorners<double> lower = randomCorners(rng), upper = randomCorners(rng);
      for (int c = 0; c < 8; ++c)
        if (c & (1 << axis)) upper[c - (1 << axis)] = lower[c];  // shared face
      dvec3 u = randomU(rng);
      u[axis] = 1.0;
      dvec3 v = u;
      v[axis] = 0.0;
      const auto a = hermiteValueGradient(lower, h, u);
      const auto b = hermiteValueGradient(upper, h, v);
      EXPECT_NEAR(a.value, b.value, 1e-12);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.gradient[k], b.gradient[k], 1e-12) << "axis " << axis << " k " << k;
    }
  }
}

// Tricky: proves the closed-form coefficient formula (one corner per coefficient, s = 0,+1,-1,0)
// against the Hermite definition at random interior points, where every coefficient matters.
TEST(BernsteinCell, AgreesWithHermiteTo1e12) {
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    const auto corners = randomCorners(rng);
    const double h = 0.05 + 2.0 * std::uniform_real_distribution<double>(0.0, 1.0)(rng);
    const BernsteinCell<double> b = toBernstein(corners, h);
    for (int p = 0; p < 20; ++p) {
      const dvec3 u = randomU(rng);
      EXPECT_NEAR(bernsteinValue(b, u), hermiteValue(corners, h, u), 1e-12);
    }
  }
}

// Tricky: the float instantiation must be the same formula (the GPU works in float).
TEST(BernsteinCell, FloatInstantiationMatchesDouble) {
  std::mt19937_64 rng(4);
  for (int trial = 0; trial < 50; ++trial) {
    const auto cd = randomCorners(rng);
    HermiteCellCorners<float> cf{};
    for (int c = 0; c < 8; ++c)
      cf[c] = {float(cd[c].f), float(cd[c].fx), float(cd[c].fy), float(cd[c].fz)};
    const dvec3 u = randomU(rng);
    const Vec3<float> uf(u);
    const double reference = hermiteValue(cd, 0.5, u);
    EXPECT_NEAR(double(hermiteValue(cf, 0.5f, uf)), reference, 1e-5);
    EXPECT_NEAR(double(bernsteinValue(toBernstein(cf, 0.5f), uf)), reference, 1e-5);
    const auto gf = hermiteValueGradient(cf, 0.5f, uf);
    const auto gd = hermiteValueGradient(cd, 0.5, u);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(double(gf.gradient[k]), gd.gradient[k], 1e-4);
  }
}

struct Cubic {
  double c0, c1, c2, c3;
  double value(double x) const { return c0 + x * (c1 + x * (c2 + x * c3)); }
  double slope(double x) const { return c1 + x * (2.0 * c2 + 3.0 * x * c3); }
};

// Tricky: the cell sits at an arbitrary world origin with h != 1, so local/world scaling of the
// derivative data must be right; separable cubics are exactly the functions zero twists reproduce.
TEST(HermiteCell, ReproducesSeparableCubicsExactly) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> coef(-2.0, 2.0);
  for (int trial = 0; trial < 30; ++trial) {
    const Cubic a{coef(rng), coef(rng), coef(rng), coef(rng)}, b{coef(rng), coef(rng), coef(rng), coef(rng)},
        c{coef(rng), coef(rng), coef(rng), coef(rng)};
    const dvec3 origin(coef(rng), coef(rng), coef(rng));
    const double h = 0.3 + 0.2 * coef(rng);
    auto f = [&](const dvec3& x) { return a.value(x.x) + b.value(x.y) + c.value(x.z); };
    auto g = [&](const dvec3& x) { return dvec3(a.slope(x.x), b.slope(x.y), c.slope(x.z)); };
    HermiteCellCorners<double> corners{};
    for (int k = 0; k < 8; ++k) {
      const dvec3 x = origin + h * dvec3(k & 1, (k >> 1) & 1, (k >> 2) & 1);
      corners[k] = {f(x), g(x).x, g(x).y, g(x).z};
    }
    for (int p = 0; p < 30; ++p) {
      const dvec3 u = randomU(rng);
      const dvec3 x = origin + h * u;
      const auto vg = hermiteValueGradient(corners, h, u);
      EXPECT_NEAR(vg.value, f(x), 1e-11);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(vg.gradient[k], g(x)[k], 1e-10);
    }
  }
}

// Tricky: pins down the Ferguson (zero twist) choice. f = xy has twist f_xy = 1; a full bicubic
// would reproduce it, Ferguson misses sum_c G_sx(x) G_sy(y) = g(x) g(y) with g(t) = t(2t-1)(t-1).
// That term vanishes at the cell centre, so the check uses u = (1/4, 1/4).
TEST(HermiteCell, DropsTwistTermsAsFergusonDefines) {
  HermiteCellCorners<double> corners{};
  for (int k = 0; k < 8; ++k) {
    const double x = k & 1, y = (k >> 1) & 1;
    corners[k] = {x * y, y, x, 0.0};
  }
  auto g = [](double t) { return t * (2.0 * t - 1.0) * (t - 1.0); };
  const dvec3 u(0.25, 0.25, 0.5);
  EXPECT_NEAR(hermiteValue(corners, 1.0, u), u.x * u.y - g(u.x) * g(u.y), 1e-12);
  EXPECT_GT(std::abs(g(u.x) * g(u.y)), 1e-3);  // the check above really distinguishes the two
}

// Tricky: trilinear gradient per axis uses differently ordered edge differences; an ordering
// mistake only shows for functions with xy, yz, xz and xyz terms.
TEST(TrilinearCell, ReproducesTrilinearFunctions) {
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> coef(-2.0, 2.0);
  for (int trial = 0; trial < 30; ++trial) {
    double k[8];
    for (double& v : k) v = coef(rng);
    const double h = 0.25;
    auto f = [&](const dvec3& u) {
      return k[0] + k[1] * u.x + k[2] * u.y + k[3] * u.z + k[4] * u.x * u.y + k[5] * u.y * u.z +
             k[6] * u.x * u.z + k[7] * u.x * u.y * u.z;
    };
    auto grad = [&](const dvec3& u) {  // d/du, divide by h for world units
      return dvec3(k[1] + k[4] * u.y + k[6] * u.z + k[7] * u.y * u.z, k[2] + k[4] * u.x + k[5] * u.z + k[7] * u.x * u.z,
                   k[3] + k[5] * u.y + k[6] * u.x + k[7] * u.x * u.y) /
             h;
    };
    TrilinearCellCorners<double> corners{};
    for (int c = 0; c < 8; ++c) corners[c] = f(dvec3(c & 1, (c >> 1) & 1, (c >> 2) & 1));
    for (int p = 0; p < 20; ++p) {
      const dvec3 u = randomU(rng);
      const auto vg = trilinearValueGradient(corners, h, u);
      EXPECT_NEAR(vg.value, f(u), 1e-12);
      EXPECT_NEAR(trilinearValue(corners, u), f(u), 1e-12);
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(vg.gradient[a], grad(u)[a], 1e-11);
    }
  }
}

// Tricky: children are indexed x + 2y + 4z and each must be re-parameterised to [0,1]^3;
// a swapped axis or child order only shows at points away from the cell centre.
TEST(BernsteinCell, SubdivisionChildrenMatchParent) {
  std::mt19937_64 rng(7);
  const auto corners = randomCorners(rng);
  const BernsteinCell<double> parent = toBernstein(corners, 0.7);
  const auto children = subdivideBernsteinCell(parent);
  for (int child = 0; child < 8; ++child) {
    const dvec3 offset(child & 1, (child >> 1) & 1, (child >> 2) & 1);
    for (int p = 0; p < 20; ++p) {
      const dvec3 v = randomU(rng);
      EXPECT_NEAR(bernsteinValue(children[child], v), bernsteinValue(parent, 0.5 * (offset + v)), 1e-12);
    }
  }
}

// Tricky: segments with components going backwards (u1 < u0) and degenerate (u0 == u1 on an axis)
// exercise the blossom; the 1D degree-9 polynomial must equal F along the segment everywhere.
TEST(SegmentRestriction, TricubicEqualsCellAlongSegment) {
  std::mt19937_64 rng(8);
  for (int trial = 0; trial < 100; ++trial) {
    const auto corners = randomCorners(rng);
    const BernsteinCell<double> b = toBernstein(corners, 0.6);
    const dvec3 u0 = randomU(rng);
    dvec3 u1 = randomU(rng);
    if (trial % 10 == 0) u1.y = u0.y;
    const std::array<double, 10> line = restrictToSegment<3, double>(b, u0, u1);
    for (int p = 0; p <= 10; ++p) {
      const double s = p / 10.0;
      EXPECT_NEAR(bernsteinValue1D(line, s), hermiteValue(corners, 0.6, (1.0 - s) * u0 + s * u1), 1e-12);
    }
  }
}

// Tricky: the trilinear restriction reuses the same template with N = 1 (degree 3 along the ray).
TEST(SegmentRestriction, TrilinearEqualsCellAlongSegment) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  for (int trial = 0; trial < 100; ++trial) {
    TrilinearCellCorners<double> corners{};
    for (double& v : corners) v = value(rng);
    const dvec3 u0 = randomU(rng), u1 = randomU(rng);
    const std::array<double, 4> line = restrictToSegment<1, double>(corners, u0, u1);
    for (int p = 0; p <= 8; ++p) {
      const double s = p / 8.0;
      EXPECT_NEAR(bernsteinValue1D(line, s), trilinearValue(corners, (1.0 - s) * u0 + s * u1), 1e-12);
    }
  }
}

// Tricky: the halves must be exact re-parameterisations, including at the split point itself.
TEST(Bernstein1D, SubdivisionHalvesMatchWhole) {
  const std::array<double, 10> p = {0.3, -1.0, 2.0, 0.5, -0.25, 1.5, -2.0, 0.1, 0.9, -0.4};
  std::array<double, 10> left{}, right{};
  subdivideBernstein1D(p, 0.3, left, right);
  for (int i = 0; i <= 10; ++i) {
    const double s = i / 10.0;
    EXPECT_NEAR(bernsteinValue1D(left, s), bernsteinValue1D(p, 0.3 * s), 1e-13);
    EXPECT_NEAR(bernsteinValue1D(right, s), bernsteinValue1D(p, 0.3 + 0.7 * s), 1e-13);
  }
}

}  // namespace
}  // namespace hsdf
