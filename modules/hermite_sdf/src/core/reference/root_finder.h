#pragma once
// First root of a 1D polynomial in Bernstein form on [0,1], by subdivision with convex-hull
// exclusion, Descartes isolation and bisection (algorithm and tolerances in hermite_sdf/core/reference.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>

#include "hermite_sdf/core/hermite.h"

namespace hsdf::detail {

struct SegmentRoot {
  double s = 0.0;
  bool contact = false;  // |F| <= tolerance without a resolved sign change
};

inline constexpr double kMinIntervalWidth = 0x1p-44;
inline constexpr int kMaxIntervalVisits = 20000;  // a safety net; real polynomials need far fewer

// Sign changes along the coefficient sequence, zeros skipped.
template <std::size_t N>
int signVariations(const std::array<double, N>& c) {
  int variations = 0;
  double previous = 0.0;
  for (double v : c) {
    if (v == 0.0) continue;
    if (previous != 0.0 && (v < 0.0) != (previous < 0.0)) ++variations;
    previous = v;
  }
  return variations;
}

// The unique root in (0,1) of a polynomial whose end values have strictly opposite signs.
template <std::size_t N>
double bisectUniqueRoot(const std::array<double, N>& c) {
  double a = 0.0, b = 1.0;
  const bool startNegative = c[0] < 0.0;
  for (int i = 0; i < 64 && b - a > 0x1p-53; ++i) {
    const double m = 0.5 * (a + b);
    const double fm = bernsteinValue1D(c, m);
    if (fm == 0.0) return m;
    ((fm < 0.0) == startNegative ? a : b) = m;
  }
  return 0.5 * (a + b);
}

// What to do with an interval that has shrunk to the minimum width and still straddles zero.
template <std::size_t N>
std::optional<SegmentRoot> resolveTinyInterval(const std::array<double, N>& c, double s0, double s1, double tolerance) {
  const double first = c[0], last = c[N - 1];
  if (std::abs(bernsteinValue1D(c, 0.5)) <= tolerance) return SegmentRoot{0.5 * (s0 + s1), true};
  if (first != 0.0 && last != 0.0 && (first < 0.0) != (last < 0.0))
    return SegmentRoot{s0 + (s1 - s0) * first / (first - last), false};
  if (std::abs(last) <= tolerance) return SegmentRoot{s1, last != 0.0};
  return std::nullopt;
}

template <std::size_t N>
std::optional<SegmentRoot> firstRootBernstein(const std::array<double, N>& coeffs, double tolerance) {
  struct Interval {
    std::array<double, N> c;
    double s0, s1;
  };
  // Depth-first, left half first; right halves wait on the stack (at most one per level).
  std::array<Interval, 64> stack;
  int top = 0;
  stack[top++] = {coeffs, 0.0, 1.0};
  for (int visits = 0; top > 0 && visits < kMaxIntervalVisits; ++visits) {
    const Interval iv = stack[--top];
    const auto [lo, hi] = std::minmax_element(iv.c.begin(), iv.c.end());
    // Convex hull: no root here. Only beyond the contact tolerance: a root on a face two cells
    // share is a rounding error from the end of one segment and the start of the next, and may
    // round to the wrong side in both; within the tolerance it is a contact, found below.
    if (*lo > tolerance || *hi < -tolerance) continue;
    const double first = iv.c[0], last = iv.c[N - 1];
    if (std::abs(first) <= tolerance) return SegmentRoot{iv.s0, first != 0.0};
    if (last != 0.0 && (first < 0.0) != (last < 0.0) && signVariations(iv.c) == 1)
      return SegmentRoot{iv.s0 + (iv.s1 - iv.s0) * bisectUniqueRoot(iv.c), false};
    if (iv.s1 - iv.s0 <= kMinIntervalWidth) {
      if (auto root = resolveTinyInterval(iv.c, iv.s0, iv.s1, tolerance)) return root;
      continue;
    }
    Interval left{{}, iv.s0, 0.5 * (iv.s0 + iv.s1)}, right{{}, left.s1, iv.s1};
    subdivideBernstein1D(iv.c, 0.5, left.c, right.c);
    stack[top++] = right;
    stack[top++] = left;
  }
  return std::nullopt;
}

}  // namespace hsdf::detail
