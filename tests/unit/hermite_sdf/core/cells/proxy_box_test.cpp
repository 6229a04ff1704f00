// Proxy boxes (cells.h): every root of a kept cell's interpolant lies in its box, found here
// independently of the Bezier clipping, by sampling the Hermite form and bisecting each sign
// change; and the boxes are smaller than the cells where the surface leaves room.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "engine/scene/gltf/gltf_loader.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/core/mesh_source.h"
#include "hermite_sdf/core/sdf_asset.h"

namespace hsdf {
namespace {

using Corners = HermiteCellCorners<double>;

// The root on the segment a..b of the cell (F(a), F(b) of opposite signs), by bisection.
Vec3<double> bisect(const Corners& c, double h, Vec3<double> a, Vec3<double> b) {
  double fa = hermiteValue(c, h, a);
  for (int i = 0; i < 60; ++i) {
    const Vec3<double> m = (a + b) * 0.5;
    const double fm = hermiteValue(c, h, m);
    if ((fm < 0.0) == (fa < 0.0)) {
      a = m;
      fa = fm;
    } else {
      b = m;
    }
  }
  return (a + b) * 0.5;
}

bool inside(const CellProxyBox& box, const Vec3<double>& p) {
  const double step = 1.0 / kProxySteps, slack = 1e-9;
  for (int axis = 0; axis < 3; ++axis)
    if (p[axis] < box.lo[axis] * step - slack || p[axis] > box.hi[axis] * step + slack) return false;
  return true;
}

// The roots on the edges of an m^3 lattice over the cell, and its exact zeros, that lie outside the
// box (0 when the box holds them all); `roots` counts what was checked.
int rootsOutside(const Corners& c, double h, const CellProxyBox& box, int m, int& roots) {
  std::vector<double> f = sampleCellDensely(c, h, m);
  const auto at = [&](int i, int j, int k) { return f[std::size_t(i + m * (j + m * k))]; };
  const auto point = [&](int i, int j, int k) { return Vec3<double>(i, j, k) / double(m - 1); };
  int outside = 0;
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        if (at(i, j, k) == 0.0) {
          ++roots;
          outside += !inside(box, point(i, j, k));
        }
        const int next[3][3] = {{i + 1, j, k}, {i, j + 1, k}, {i, j, k + 1}};
        for (const auto& n : next) {
          if (n[0] >= m || n[1] >= m || n[2] >= m) continue;
          const double a = at(i, j, k), b = at(n[0], n[1], n[2]);
          if (a == 0.0 || b == 0.0 || (a < 0.0) == (b < 0.0)) continue;
          ++roots;
          outside += !inside(box, bisect(c, h, point(i, j, k), point(n[0], n[1], n[2])));
        }
      }
  return outside;
}

double surfaceArea(const CellProxyBox& box) {
  const double step = 1.0 / kProxySteps;
  const double x = (box.hi[0] - box.lo[0]) * step, y = (box.hi[1] - box.lo[1]) * step, z = (box.hi[2] - box.lo[2]) * step;
  return 2.0 * (x * y + y * z + z * x);
}

// A cell of F = n . (u - p) h exactly (cell-local u, unit normal n): its corners and gradients.
Corners planeCell(Vec3<double> n, Vec3<double> p, double h) {
  Corners c{};
  for (int i = 0; i < 8; ++i) {
    const Vec3<double> u{double(i & 1), double((i >> 1) & 1), double(i >> 2)};
    c[std::size_t(i)] = {dot(n, u - p) * h, n.x, n.y, n.z};
  }
  return c;
}

TEST(ProxyBox, EveryCodePacksAndUnpacksAndZeroIsTheWholeCell) {
  EXPECT_EQ(unpackProxyBox(0), CellProxyBox{});
  EXPECT_EQ(packProxyBox(CellProxyBox{}), 0);
  int boxes = 0;
  for (int a = 0; a < 21 * 21 * 21; ++a) {
    const CellProxyBox box = unpackProxyBox(std::uint16_t(a));
    for (int axis = 0; axis < 3; ++axis) ASSERT_LT(box.lo[axis], box.hi[axis]);
    ASSERT_LE(box.hi[0], kProxySteps);
    ASSERT_EQ(packProxyBox(box), a);
    ++boxes;
  }
  EXPECT_EQ(boxes, 9261);  // (6 * 7 / 2)^3 boxes: every (lo < hi) on each axis, below 2^14
  EXPECT_LT(boxes, 1 << 14);
}

// Tricky: the root of an axis-aligned plane sits at one height; the box must hold it and nothing of
// the other sixths. Tilted planes reach across the cell on two axes only.
TEST(ProxyBox, PlanesKeepOnlyTheSixthsTheyCross) {
  const double h = 0.25;
  const CellProxyBox flat = cellProxyBox(planeCell({0, 0, 1}, {0, 0, 0.3}, h), h);
  EXPECT_EQ(flat.lo, (std::array<std::uint8_t, 3>{0, 0, 1}));  // 0.3 lies in the second sixth
  EXPECT_EQ(flat.hi, (std::array<std::uint8_t, 3>{6, 6, 2}));
  for (double height : {0.0, 0.5, 1.0}) {  // exactly on a sixth: on a face, on a boundary inside
    const CellProxyBox box = cellProxyBox(planeCell({1, 0, 0}, {height, 0, 0}, h), h);
    int roots = 0;
    EXPECT_EQ(rootsOutside(planeCell({1, 0, 0}, {height, 0, 0}, h), h, box, 13, roots), 0) << height;
    EXPECT_LE(box.hi[0] - box.lo[0], 2) << height;
  }
  const Vec3<double> tilted = normalize(Vec3<double>{0.2, 0.1, 1.0});
  const CellProxyBox box = cellProxyBox(planeCell(tilted, {0.5, 0.5, 0.5}, h), h);
  int roots = 0;
  EXPECT_EQ(rootsOutside(planeCell(tilted, {0.5, 0.5, 0.5}, h), h, box, 17, roots), 0);
  EXPECT_GT(roots, 100);
  EXPECT_LT(surfaceArea(box), 6.0 * 0.7);
}

// Tricky: on faces on sample planes (a box fitted to the grid) F is 0, or a rounding error of
// either sign, on the whole face. Here F = h z (0.7 - z): a root at z = 0.7, and the face z = 0,
// where F is `noise` and rises into the cell. At +1e-17 the interpolant only touches zero there:
// the classifier (its zero band) and the CPU reference (its contact tolerance) count it as the
// surface, so the box must reach the face although no control point is at or below zero.
TEST(ProxyBox, AContactOnTheCellsFaceWithinTheZeroBandIsKept) {
  const double h = 0.1;
  for (double noise : {0.0, 1e-17, -1e-17}) {
    Corners c{};
    for (int i = 0; i < 8; ++i) {
      const double z = double(i >> 2);
      c[std::size_t(i)] = {z == 0.0 ? noise : h * z * (0.7 - z), 0.0, 0.0, 0.7 - 2.0 * z};
    }
    const CellProxyBox box = cellProxyBox(c, h);
    EXPECT_EQ(box.lo[2], 0) << noise;  // the face
    EXPECT_GE(box.hi[2], 5) << noise;  // the root at 0.7, in the fifth sixth
    EXPECT_LE(box.hi[2] - box.lo[2], 5) << noise;  // and nothing beyond it, up to the rounding to sixths
  }
}

// Tricky: fp16 records of values beyond its range hold infinities; the box must not come from NaN
// comparisons (which would clip anywhere) but be the whole cell.
TEST(ProxyBox, NonFiniteValuesKeepTheWholeCell) {
  const double h = 0.25;
  for (double bad : {HUGE_VAL, -HUGE_VAL, std::nan("")}) {
    Corners c = planeCell({0, 0, 1}, {0, 0, 0.3}, h);
    c[5].fx = bad;
    EXPECT_EQ(cellProxyBox(c, h), CellProxyBox{}) << bad;
  }
}

// The bunny (thin ears, folds) at several K, fp32 and fp16 records, and cells of random data with
// roots anywhere: no root outside its cell's box.
TEST(ProxyBox, EveryRootOfTheBunnysAndRandomCellsLiesInItsBox) {
  auto scene = engine::scene::loadGltf(std::string(HSDF_ASSET_DIR) + "/bunny.glb");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  auto mesh = MeshSource::create(engine::scene::flattenTriangles(*scene));
  ASSERT_TRUE(mesh.ok()) << mesh.error().message;
  for (int k : {12, 24, 40}) {
    auto grid = fitGrid((*mesh)->bounds(), k, 1);
    ASSERT_TRUE(grid.ok());
    auto field = bakeHermiteField(**mesh, *grid, {});
    ASSERT_TRUE(field.ok());
    auto asset = makeSdfAsset("bunny", std::move(*field), (*mesh)->bounds());
    ASSERT_TRUE(asset.ok()) << asset.error().message;
    const SdfAsset& a = **asset;
    ASSERT_EQ(a.proxyBoxes.size(), a.cells.records.size());
    ASSERT_EQ(a.proxyBoxesHalf.size(), a.cellsHalf.records.size());
    const CellStream half = toFloat(a.cellsHalf);
    int roots = 0, outside = 0;
    double area = 0.0;
    for (std::size_t i = 0; i < a.cells.records.size(); ++i) {
      const CellProxyBox box = unpackProxyBox(a.proxyBoxes[i]);
      outside += rootsOutside(cellCorners(a.cells.records[i]), grid->spacing, box, 9, roots);
      outside += rootsOutside(cellCorners(half.records[i]), grid->spacing, unpackProxyBox(a.proxyBoxesHalf[i]), 9, roots);
      area += surfaceArea(box);
    }
    EXPECT_EQ(outside, 0) << "K = " << k << ", of " << roots << " roots";
    // Why the boxes are worth drawing: on this surface they have well under the cells' area.
    EXPECT_LT(area / (6.0 * double(a.cells.records.size())), 0.75) << "K = " << k;
  }
  std::mt19937 random(20);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  int roots = 0, outside = 0;
  for (int cell = 0; cell < 3000; ++cell) {
    Corners c{};
    for (auto& corner : c) corner = {value(random) * 0.3, value(random), value(random), value(random)};
    if (classifyCell(c, 0.5) == CellClass::Empty) continue;
    outside += rootsOutside(c, 0.5, cellProxyBox(c, 0.5), 9, roots);
  }
  EXPECT_EQ(outside, 0) << "of " << roots << " roots";
  EXPECT_GT(roots, 10000);
}

}  // namespace
}  // namespace hsdf
