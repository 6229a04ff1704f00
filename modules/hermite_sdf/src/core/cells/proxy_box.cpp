// Proxy boxes of kept cells (cells.h): one step of Bezier clipping per axis, rounded outward.
#include <algorithm>
#include <cmath>

#include "field/parallel.h"
#include "hermite_sdf/core/cells.h"

namespace hsdf {
namespace {

// The x range, within [0, 1], of the convex hull of the control points (i/3, p[i]) where it lies on
// the zero side (below: y <= 0, else y >= 0): the hull's points there and the crossings of y = 0 by
// the segments between a point on that side and one off it (the hull's edges among them). False when
// no control point is on that side: the polynomial has no point there either.
bool hullReach(const std::array<double, 4>& p, bool below, double& first, double& last) {
  const auto on = [&](int i) { return below ? p[i] <= 0.0 : p[i] >= 0.0; };
  first = 2.0;
  last = -1.0;
  for (int i = 0; i < 4; ++i) {
    if (on(i)) {
      first = std::min(first, i / 3.0);
      last = std::max(last, i / 3.0);
    }
    for (int j = i + 1; j < 4; ++j) {
      if (on(i) == on(j)) continue;
      const double x = (i + (j - i) * (p[i] / (p[i] - p[j]))) / 3.0;  // p[i] and p[j] differ: on(i) != on(j)
      first = std::min(first, x);
      last = std::max(last, x);
    }
  }
  return first <= last;
}

// The axis's (lo, hi) in steps; the whole cell where the hulls prove nothing.
void clipAxis(const BernsteinCell<double>& b, int axis, double band, std::uint8_t& lo, std::uint8_t& hi) {
  std::array<double, 4> least{}, greatest{};
  least.fill(HUGE_VAL);
  greatest.fill(-HUGE_VAL);
  for (int c = 0; c < 4; ++c)
    for (int bb = 0; bb < 4; ++bb)
      for (int a = 0; a < 4; ++a) {
        const int i = axis == 0 ? a : (axis == 1 ? bb : c);
        const double v = b[bernsteinIndex(a, bb, c)];
        least[i] = std::min(least[i], v - band);
        greatest[i] = std::max(greatest[i], v + band);
      }
  double belowFirst, belowLast, aboveFirst, aboveLast;
  lo = 0;
  hi = kProxySteps;
  if (!hullReach(least, true, belowFirst, belowLast) || !hullReach(greatest, false, aboveFirst, aboveLast)) return;
  const double first = std::max(belowFirst, aboveFirst), last = std::min(belowLast, aboveLast);
  if (!(first <= last)) return;
  // Outward, with a millionth of a step for the rounding of the crossings above.
  const double steps = kProxySteps;
  const int l = std::clamp(int(std::floor(first * steps - 1e-6)), 0, kProxySteps - 1);
  const int u = std::clamp(int(std::ceil(last * steps + 1e-6)), l + 1, kProxySteps);
  lo = std::uint8_t(l);
  hi = std::uint8_t(u);
}

// Pair index of (lo, hi) on one axis: a = lo steps cut below, b = kProxySteps - hi cut above,
// a + b < kProxySteps; numbered by s = a + b, then b, so that the whole axis (0, 0) is 0.
constexpr int kPairsPerAxis = kProxySteps * (kProxySteps + 1) / 2;  // 21

int pairIndex(int lo, int hi) {
  const int a = lo, b = kProxySteps - hi, s = a + b;
  return s * (s + 1) / 2 + b;
}

// On all cores, in chunks of records: ~0.3 us a cell on one core, 4 s for the ~13M cells of a
// K = 2048 bunny.
template <class Stream, class Corners>
std::vector<std::uint16_t> codesOf(const Stream& cells, const Corners& corners) {
  constexpr std::size_t kChunk = 4096;
  std::vector<std::uint16_t> codes(cells.records.size());
  const std::size_t chunks = (codes.size() + kChunk - 1) / kChunk;
  const engine::Status done = detail::runParallel(chunks, BakeOptions{}, [&](std::size_t chunk) -> engine::Status {
    const std::size_t end = std::min(codes.size(), (chunk + 1) * kChunk);
    for (std::size_t i = chunk * kChunk; i < end; ++i)
      codes[i] = packProxyBox(cellProxyBox(corners(cells.records[i]), cells.grid.spacing));
    return {};
  });
  (void)done;  // no item fails and nothing can cancel: no progress callback, no token
  return codes;
}

}  // namespace

CellProxyBox cellProxyBox(const HermiteCellCorners<double>& corners, double h) {
  const BernsteinCell<double> b = toBernstein(corners, h);
  const double band = zeroToleranceFor(corners, h);
  CellProxyBox box;
  // fp16 records of values past its range hold infinities (such records are never drawn:
  // halfPrecisionFits); comparisons with NaN would clip at random.
  if (!std::isfinite(band) || !std::all_of(b.begin(), b.end(), [](double v) { return std::isfinite(v); })) return box;
  for (int axis = 0; axis < 3; ++axis) clipAxis(b, axis, band, box.lo[axis], box.hi[axis]);
  return box;
}

std::uint16_t packProxyBox(const CellProxyBox& box) {
  int code = 0;
  for (int axis = 2; axis >= 0; --axis) code = code * kPairsPerAxis + pairIndex(box.lo[axis], box.hi[axis]);
  return std::uint16_t(code);
}

CellProxyBox unpackProxyBox(std::uint16_t code) {
  CellProxyBox box;
  int rest = code;
  for (int axis = 0; axis < 3; ++axis) {
    const int pair = rest % kPairsPerAxis;
    rest /= kPairsPerAxis;
    int s = 0;
    while ((s + 1) * (s + 2) / 2 <= pair) ++s;
    const int b = pair - s * (s + 1) / 2;
    box.lo[axis] = std::uint8_t(s - b);
    box.hi[axis] = std::uint8_t(kProxySteps - b);
  }
  return box;
}

std::vector<std::uint16_t> proxyBoxCodes(const CellStream& cells) {
  return codesOf(cells, [](const CellRecord& r) { return cellCorners(r); });
}

std::vector<std::uint16_t> proxyBoxCodes(const CellStreamHalf& cells) {
  return codesOf(cells, [](const CellRecordHalf& h) { return cellCorners(toFloat(h)); });
}

}  // namespace hsdf
