// First-root search on 1D Bernstein polynomials (the core of the reference caster).
#include "reference/root_finder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace hsdf::detail {
namespace {

// Bernstein coefficients (degree N-1) of the polynomial `scale * prod (s - r_i)` padded by degree
// elevation with factors `offset` added: p(s) = scale * prod_i (s - roots_i) + offset.
template <std::size_t N>
std::array<double, N> bernsteinFromRoots(const std::vector<double>& roots, double scale = 1.0, double offset = 0.0) {
  constexpr int n = int(N) - 1;
  std::vector<double> mono(1, scale);  // power basis, lowest first
  for (double r : roots) {
    std::vector<double> next(mono.size() + 1, 0.0);
    for (std::size_t i = 0; i < mono.size(); ++i) {
      next[i + 1] += mono[i];
      next[i] -= r * mono[i];
    }
    mono = next;
  }
  mono[0] += offset;
  mono.resize(N, 0.0);
  // b_k = sum_{j<=k} C(k,j)/C(n,j) a_j
  std::array<double, N> b{};
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= k; ++j) b[k] += binomial(k, j) / binomial(n, j) * mono[std::size_t(j)];
  return b;
}

// Tricky: the helper itself must be right, or every other test here proves nothing.
TEST(RootFinder, TestPolynomialsAreWhatTheySay) {
  const auto b = bernsteinFromRoots<10>({0.1, 0.2, 0.35, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95}, 3.0, 0.5);
  for (double s : {0.0, 0.13, 0.5, 0.77, 1.0}) {
    double expected = 3.0;
    for (double r : {0.1, 0.2, 0.35, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95}) expected *= (s - r);
    EXPECT_NEAR(bernsteinValue1D(b, s), expected + 0.5, 1e-14);
  }
}

// Tricky: nine roots in [0,1] (the maximum for degree 9): the FIRST must be returned, and to
// full double precision, although the coefficients alternate wildly.
TEST(RootFinder, FindsTheFirstOfNineRoots) {
  const auto b = bernsteinFromRoots<10>({0.9, 0.15, 0.2, 0.35, 0.5, 0.6, 0.7, 0.8, 0.95});
  const auto root = firstRootBernstein(b, 0.0);
  ASSERT_TRUE(root.has_value());
  EXPECT_NEAR(root->s, 0.15, 1e-13);
  EXPECT_FALSE(root->contact);
}

// Tricky: two simple roots 2e-7 apart: the sign is the same at both ends of the segment and the
// control polygon barely dips; a sampling method with any fixed step misses them.
TEST(RootFinder, SeparatesTwoCloseRoots) {
  const auto b = bernsteinFromRoots<10>({0.5 - 1e-7, 0.5 + 1e-7, 2.0, 3.0, -1.0, -2.0, 4.0, 5.0, -3.0});
  const auto root = firstRootBernstein(b, 1e-30);
  ASSERT_TRUE(root.has_value());
  // The roots are ill-conditioned (|p'| ~ 1e-4 there): 1e-9 is the rounding limit, far below the
  // 2e-7 separation, so the first root is clearly the one found.
  EXPECT_NEAR(root->s, 0.5 - 1e-7, 1e-9);
}

// Tricky: a double root (tangency) has no sign change at all; it must be reported as a contact at
// the touching point (within sqrt(tolerance/curvature)), while a dip that stays 1e-9 above zero
// must not be a hit.
TEST(RootFinder, ReportsTangencyAndRejectsNearMiss) {
  const double tolerance = 1e-13;
  const auto touching = bernsteinFromRoots<4>({0.4, 0.4, 2.0});
  const auto root = firstRootBernstein(touching, tolerance);
  ASSERT_TRUE(root.has_value());
  EXPECT_NEAR(root->s, 0.4, 1e-6);
  // -(s-0.4)^2 (s-2) is >= 0 on [0,1] and touches 0 at 0.4. Lowered by 1e-9 it has two close
  // roots at 0.4 -+ ~2.6e-5 (the first must be found); raised by 1e-9 it has none.
  const auto dipsBelow = bernsteinFromRoots<4>({0.4, 0.4, 2.0}, -1.0, -1e-9);
  const auto close = firstRootBernstein(dipsBelow, tolerance);
  ASSERT_TRUE(close.has_value());
  EXPECT_FALSE(close->contact);
  EXPECT_NEAR(close->s, 0.4 - std::sqrt(1e-9 / 1.6), 1e-7);
  const auto staysAbove = bernsteinFromRoots<4>({0.4, 0.4, 2.0}, -1.0, 1e-9);
  EXPECT_FALSE(firstRootBernstein(staysAbove, tolerance).has_value());
}

// Tricky: roots exactly at the interval ends, and a polynomial whose control polygon crosses
// zero although the polynomial does not (the convex hull alone cannot reject it).
TEST(RootFinder, HandlesEndpointsAndFalseHullCrossings) {
  const auto atStart = bernsteinFromRoots<4>({0.0, 3.0, 4.0});
  ASSERT_TRUE(firstRootBernstein(atStart, 0.0).has_value());
  EXPECT_EQ(firstRootBernstein(atStart, 0.0)->s, 0.0);
  const auto atEnd = bernsteinFromRoots<4>({1.0, 3.0, 4.0});
  ASSERT_TRUE(firstRootBernstein(atEnd, 0.0).has_value());
  EXPECT_NEAR(firstRootBernstein(atEnd, 0.0)->s, 1.0, 1e-12);
  const std::array<double, 4> hullCrosses = {1.0, -0.2, -0.2, 1.0};  // min value 0.55 > 0
  EXPECT_FALSE(firstRootBernstein(hullCrosses, 1e-13).has_value());
  const std::array<double, 4> allZero = {0.0, 0.0, 0.0, 0.0};
  ASSERT_TRUE(firstRootBernstein(allZero, 0.0).has_value());
  EXPECT_EQ(firstRootBernstein(allZero, 0.0)->s, 0.0);
}

}  // namespace
}  // namespace hsdf::detail
