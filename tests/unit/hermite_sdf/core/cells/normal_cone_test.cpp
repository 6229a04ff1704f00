// Normal cones of cells and bricks, and the brick culling tests (normal_cone.h): every gradient of
// the interpolant lies in its cell's and brick's cone (dense sampling of the Hermite form, which
// does not use the Bernstein conversion the cone is built from); a brick the cone test culls has no
// point and cone direction facing the eye (brute force); a box the frustum test culls has no point
// in the frustum; cone culling is allowed only for fields positive on the whole grid boundary.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <random>
#include <span>

#include "cells/cell_bricks.h"
#include "engine/core/math.h"
#include "hermite_sdf/core/analytic.h"
#include "hermite_sdf/core/normal_cone.h"
#include "hermite_sdf/render/renderable.h"
#include "hermite_sdf/core/sparse_bake.h"

namespace hsdf {
namespace {

bool neverCulls(const shader::CellBrickCone& cone) { return cone.axisCutoff.w >= 1.0f; }

// Largest angle (radians) between the cone's axis and a gradient of the cell sampled at m^3 grid
// points and 200 random points; -1 if a sampled gradient is zero.
double widestSampledAngle(const CellRecord& record, double h, const glm::dvec3& axis, std::mt19937& rng, int m = 9) {
  const HermiteCellCorners<double> corners = cellCorners(record);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double widest = 0.0;
  auto visit = [&](const glm::dvec3& u) {
    const glm::dvec3 g = hermiteValueGradient(corners, h, u).gradient;
    if (glm::length(g) == 0.0) return false;
    widest = std::max(widest, std::acos(std::clamp(glm::dot(glm::normalize(g), axis), -1.0, 1.0)));
    return true;
  };
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i)
        if (!visit(glm::dvec3(i, j, k) / double(m - 1))) return -1.0;
  for (int s = 0; s < 200; ++s)
    if (!visit({unit(rng), unit(rng), unit(rng)})) return -1.0;
  return widest;
}

double halfAngle(const shader::CellBrickCone& cone) { return std::asin(double(cone.axisCutoff.w)); }
glm::dvec3 axisOf(const shader::CellBrickCone& cone) { return glm::dvec3(glm::vec3(cone.axisCutoff)); }

// A record of a field near the plane through the cell with normal `dir`: values and gradients off
// by up to `spread` (values in units of h, so that value and derivative terms stay comparable).
CellRecord randomRecord(std::mt19937& rng, const glm::dvec3& dir, double spread, double h) {
  std::uniform_real_distribution<double> sym(-1.0, 1.0);
  const double offset = sym(rng) * h;
  CellRecord record;
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 corner(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    const glm::dvec3 g = dir + spread * glm::dvec3(sym(rng), sym(rng), sym(rng));
    const double f = offset + h * (glm::dot(dir, corner) + spread * sym(rng));
    record.corners[std::size_t(c)] = {float(f), float(g.x), float(g.y), float(g.z)};
  }
  return record;
}

glm::dvec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  return glm::normalize(glm::dvec3(normal(rng), normal(rng), normal(rng)));
}

// Tricky: gradients of a tricubic reach outside the hull of the corner gradients (the value terms
// tilt them), most in cells with large value differences; random h scales the mix of value and
// derivative terms. A cone that only held the corner gradients, or forgot the degree elevation,
// fails here. Narrow spreads must give cones that cull (w < 1), or the test could pass vacuously.
TEST(NormalCone, RandomCellsHoldEverySampledGradient) {
  std::mt19937 rng(20);
  std::uniform_real_distribution<double> spacing(0.01, 2.0), spreadDist(0.0, 0.8);
  int culling = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const double h = spacing(rng);
    const CellRecord record = randomRecord(rng, randomUnit(rng), trial % 4 == 0 ? 0.02 : spreadDist(rng), h);
    const shader::CellBrickCone cone = cellGradientCone(record, h);
    EXPECT_NEAR(glm::length(axisOf(cone)), 1.0, 1e-6);
    if (neverCulls(cone)) continue;
    ++culling;
    const double widest = widestSampledAngle(record, h, axisOf(cone), rng);
    ASSERT_GE(widest, 0.0) << trial;
    EXPECT_LE(widest, halfAngle(cone)) << "trial " << trial << " h " << h;
  }
  EXPECT_GT(culling, 150);
}

// A linear field's gradient is constant: its cone is the direction itself (within the margin).
TEST(NormalCone, PlaneCellHasTheNarrowestCone) {
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
  CellRecord record;
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 p(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    record.corners[std::size_t(c)] = {float(glm::dot(n, p * 0.5) - 0.2), float(n.x), float(n.y), float(n.z)};
  }
  const shader::CellBrickCone cone = cellGradientCone(record, 0.5);
  EXPECT_LT(glm::length(axisOf(cone) - n), 1e-6);
  EXPECT_NEAR(halfAngle(cone), kConeAngleMargin, 1e-5);
}

// Gradients all around (a point source inside the cell) or a zero gradient: no cone can cull.
TEST(NormalCone, SpreadOrVanishingGradientsNeverCull) {
  CellRecord around;
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(c & 1, (c >> 1) & 1, (c >> 2) & 1) - glm::dvec3(0.5));
    around.corners[std::size_t(c)] = {0.5f, float(d.x), float(d.y), float(d.z)};
  }
  EXPECT_TRUE(neverCulls(cellGradientCone(around, 1.0)));
  CellRecord flat;  // constant field: every gradient is zero
  for (HermiteSample& s : flat.corners) s = {1.0f, 0.0f, 0.0f, 0.0f};
  EXPECT_TRUE(neverCulls(cellGradientCone(flat, 1.0)));
}

std::shared_ptr<const SdfAsset> bakedAsset(const SdfSource& source, int k, double extent) {
  GridSpec grid;
  grid.resolution = k;
  grid.spacing = 2.0 * extent / double(k - 1);
  grid.origin = glm::dvec3(-extent);
  auto field = bakeHermiteField(source, grid);
  EXPECT_TRUE(field.ok());
  auto asset = makeSdfAsset("shape", std::move(field.value()), source.bounds());
  EXPECT_TRUE(asset.ok());
  return asset.value();
}

// Real baked cells: every cell's gradients in its cell cone and in its brick's cone (bricks of
// several cells merge their control vectors); most bricks of a sphere at K = 40 are narrow enough
// to cull.
void expectConesHoldBakedGradients(const SdfAsset& asset) {
  std::mt19937 rng(7);
  const double h = asset.cells.grid.spacing;
  for (const CellRecord& record : asset.cells.records) {
    const shader::CellBrickCone cone = cellGradientCone(record, h);
    if (neverCulls(cone)) continue;
    EXPECT_LE(widestSampledAngle(record, h, axisOf(cone), rng, 5), halfAngle(cone));
  }
  const CellBricks bricks = buildCellBricks(asset.cells).value();
  const auto conesOr = brickGradientCones(asset.cells, bricks.bricks, bricks.cellRecords);
  ASSERT_TRUE(conesOr.ok()) << conesOr.error().message;
  const std::vector<shader::CellBrickCone>& cones = conesOr.value();
  ASSERT_EQ(cones.size(), bricks.bricks.size());
  std::size_t culling = 0;
  for (std::size_t b = 0; b < cones.size(); ++b) {
    if (neverCulls(cones[b])) continue;
    ++culling;
    const shader::CellBrickGpu& brick = bricks.bricks[b];
    const int count = std::popcount(brick.maskLo) + std::popcount(brick.maskHi);
    for (int i = 0; i < count; ++i) {
      const CellRecord& record = asset.cells.records[bricks.cellRecords[brick.firstIndex + std::uint32_t(i)]];
      EXPECT_LE(widestSampledAngle(record, h, axisOf(cones[b]), rng, 5), halfAngle(cones[b])) << "brick " << b;
    }
  }
  EXPECT_GT(culling, cones.size() / 2) << culling << " of " << cones.size();
}

TEST(NormalCone, BakedSphereAndTorusCellsAndBricks) {
  expectConesHoldBakedGradients(*bakedAsset(SphereSource({0.1, -0.05, 0.0}, 1.0), 40, 1.4));
  expectConesHoldBakedGradients(*bakedAsset(TorusSource({0.0, 0.0, 0.0}, 0.9, 0.35), 40, 1.4));
}

// The stream's cones on worker threads (cellGradientCones, the cell culling pass's: chunks of 4096
// records) are each record's own cone, in record order, on one thread and on three.
TEST(NormalCone, StreamConesAreEachRecordsConeInOrder) {
  const auto asset = bakedAsset(SphereSource({0.1, -0.05, 0.0}, 1.0), 96, 1.4);
  ASSERT_GT(asset->cells.records.size(), 2u * 4096u) << "several chunks";
  for (const unsigned threads : {1u, 3u}) {
    const std::vector<shader::CellBrickCone> cones = cellGradientCones(asset->cells, threads).value();
    ASSERT_EQ(cones.size(), asset->cells.records.size());
    for (std::size_t i = 0; i < cones.size(); ++i)
      ASSERT_EQ(cones[i].axisCutoff, cellGradientCone(asset->cells.records[i], asset->cells.grid.spacing).axisCutoff)
          << "record " << i << ", " << threads << " threads";
  }
}

// The bricks' cones on worker threads (brickGradientCones, the brick culling pass's, made by the
// bake job: chunks of 256 bricks) are each brick's own cone of its own cells, in brick order, on one
// thread and on three.
TEST(NormalCone, BrickConesAreEachBricksConeInOrder) {
  const auto asset = bakedAsset(SphereSource({0.1, -0.05, 0.0}, 1.0), 96, 1.4);
  const CellBricks bricks = buildCellBricks(asset->cells).value();
  ASSERT_GT(bricks.bricks.size(), 2u * 256u) << "several chunks";
  for (const unsigned threads : {1u, 3u}) {
    const std::vector<shader::CellBrickCone> cones =
        brickGradientCones(asset->cells, bricks.bricks, bricks.cellRecords, threads).value();
    ASSERT_EQ(cones.size(), bricks.bricks.size());
    for (std::size_t b = 0; b < cones.size(); ++b) {
      const shader::CellBrickGpu& brick = bricks.bricks[b];
      const auto count = std::size_t(std::popcount(brick.maskLo) + std::popcount(brick.maskHi));
      const std::span<const std::uint32_t> cells = std::span(bricks.cellRecords).subspan(brick.firstIndex, count);
      ASSERT_EQ(cones[b].axisCutoff, brickGradientCone(asset->cells, cells).axisCutoff)
          << "brick " << b << ", " << threads << " threads";
    }
  }
}

// Bricks that point past the index list or at records that do not exist are refused by name.
TEST(NormalCone, BadBricksAreRefusedByName) {
  const auto asset = bakedAsset(SphereSource({0.0, 0.0, 0.0}, 1.0), 16, 1.4);
  CellBricks bricks = buildCellBricks(asset->cells).value();
  bricks.bricks.back().firstIndex = std::uint32_t(bricks.cellRecords.size());
  auto past = brickGradientCones(asset->cells, bricks.bricks, bricks.cellRecords);
  ASSERT_FALSE(past.ok());
  EXPECT_NE(past.error().message.find("of a list of"), std::string::npos) << past.error().message;
  bricks = buildCellBricks(asset->cells).value();
  bricks.cellRecords.front() = std::uint32_t(asset->cells.records.size());
  auto missing = brickGradientCones(asset->cells, bricks.bricks, bricks.cellRecords);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("brick 0: record index"), std::string::npos) << missing.error().message;
}

// ---- The cull test --------------------------------------------------------------------------------

// Tricky: boxes near and far, cones up to 85 degrees, eyes beside and inside the box. Every culled
// case is checked against sampled box points (corners included) and cone directions (its rim and
// axis); enough cases must cull for the check to mean something.
TEST(BrickCull, ConeTestNeverCullsABrickThatCanFaceTheEye) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> pos(-2.0, 2.0), side(0.01, 1.0), eyeDist(-5.0, 5.0), angle(0.0, 1.48),
      unit(0.0, 1.0);
  int culled = 0;
  const int trials = 4000;
  for (int trial = 0; trial < trials; ++trial) {
    BrickBox box;
    box.lo = glm::vec3(pos(rng), pos(rng), pos(rng));
    box.hi = box.lo + glm::vec3(side(rng), side(rng), side(rng));
    const glm::dvec3 axis = randomUnit(rng);
    const double theta = angle(rng);
    const shader::CellBrickCone cone{glm::vec4(glm::vec3(axis), float(std::sin(theta)))};
    const glm::vec3 eye(eyeDist(rng), eyeDist(rng), eyeDist(rng));
    // A zero matrix puts every corner on every frustum plane: only the cone test decides.
    if (brickVerdict(glm::mat4(0.0f), box, cone, eye, true) == BrickVerdict::Kept) continue;
    ASSERT_EQ(brickVerdict(glm::mat4(0.0f), box, cone, eye, true), BrickVerdict::ConeCulled);
    ++culled;
    // A direction on the rim: axis rotated by theta towards a random perpendicular.
    const glm::dvec3 helper = std::abs(axis.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 e1 = glm::normalize(glm::cross(axis, helper)), e2 = glm::cross(axis, e1);
    for (int s = 0; s < 64; ++s) {
      const double phi = 6.283185307 * unit(rng);
      const glm::dvec3 n = s == 0 ? axis
                                  : std::cos(theta) * axis + std::sin(theta) * (std::cos(phi) * e1 + std::sin(phi) * e2);
      const glm::dvec3 p = s < 8 ? glm::dvec3((s & 1) ? box.hi.x : box.lo.x, (s & 2) ? box.hi.y : box.lo.y,
                                              (s & 4) ? box.hi.z : box.lo.z)
                                 : glm::mix(glm::dvec3(box.lo), glm::dvec3(box.hi), glm::dvec3(unit(rng), unit(rng), unit(rng)));
      ASSERT_GT(glm::dot(n, p - glm::dvec3(eye)), 0.0) << "trial " << trial;
    }
  }
  EXPECT_GT(culled, trials / 20);
  // The cone that never culls, even for a tiny brick straight ahead along its axis.
  const shader::CellBrickCone never{glm::vec4(0.0f, 0.0f, 1.0f, kNeverCullCutoff)};
  const BrickBox ahead{{-1e-6f, -1e-6f, 10.0f}, {1e-6f, 1e-6f, 10.000001f}};
  EXPECT_FALSE(coneCullsBox(never, ahead, glm::vec3(0.0f)));
  EXPECT_TRUE(coneCullsBox({glm::vec4(0.0f, 0.0f, 1.0f, 0.0f)}, ahead, glm::vec3(0.0f)));
  // The box test is exact for the box: a cone of 44 degrees culls a thin box seen within 45.5
  // degrees of its axis (its bounding sphere would hold the eye).
  const float t = std::tan(0.0175f * 45.5f) * 10.0f;
  const BrickBox wide{{-t, -0.01f, 10.0f}, {t, 0.01f, 10.0f}};
  const shader::CellBrickCone cone44{glm::vec4(0.0f, 0.0f, 1.0f, std::sin(0.0175f * 44.0f))};
  EXPECT_TRUE(coneCullsBox(cone44, wide, glm::vec3(0.0f)));
}

bool insideFrustum(const glm::mat4& objectToClip, const glm::vec3& p) {
  const glm::vec4 c = objectToClip * glm::vec4(p, 1.0f);
  return c.w > 0.0f && std::abs(c.x) <= c.w && std::abs(c.y) <= c.w && c.z <= c.w;
}

// Boxes around, behind and beside a camera, under a sheared model matrix: a culled box has no
// sampled point in the frustum; a box holding a visible sample is never culled.
TEST(BrickCull, FrustumTestNeverCullsAVisibleBox) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> pos(-6.0, 6.0), side(0.05, 2.0), unit(0.0, 1.0);
  const glm::mat4 view = engine::math::lookAt({0.5f, 1.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f});
  const glm::mat4 proj = engine::math::perspectiveReverseZInfinite(0.9f, 1.5f, 0.1f);
  glm::mat4 model(1.0f);
  model[1][0] = 0.3f;  // shear
  model[3] = glm::vec4(0.2f, -0.1f, 0.3f, 1.0f);
  const glm::mat4 objectToClip = proj * view * model;
  int culled = 0, kept = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    BrickBox box;
    box.lo = glm::vec3(pos(rng), pos(rng), pos(rng));
    box.hi = box.lo + glm::vec3(side(rng), side(rng), side(rng));
    bool visible = false;
    for (int s = 0; s < 300 && !visible; ++s)
      visible = insideFrustum(objectToClip, glm::mix(box.lo, box.hi, glm::vec3(unit(rng), unit(rng), unit(rng))));
    const bool outside = boxOutsideFrustum(objectToClip, box);
    if (visible) {
      EXPECT_FALSE(outside) << trial;
    }
    (outside ? culled : kept)++;
  }
  EXPECT_GT(culled, 300);
  EXPECT_GT(kept, 300);
}

// ---- When cone culling is valid -----------------------------------------------------------------

TEST(BrickCull, ConeCullingNeedsAPositiveGridBoundaryAndTheNearPlaneOutside) {
  const SphereSource sphere({0.0, 0.0, 0.0}, 1.0);
  const auto inGrid = bakedAsset(sphere, 24, 1.4);
  EXPECT_TRUE(inGrid->boundaryPositive);
  // The sphere cut by the grid's boundary: kept cells touch it, negative on their boundary faces.
  EXPECT_FALSE(bakedAsset(sphere, 24, 0.9)->boundaryPositive);
  // A grid 3 % wider than the sphere: kept cells touch the boundary, positive on it (as the
  // bunny's at padding 1, K = 16).
  const auto tight = bakedAsset(sphere, 24, 1.03);
  EXPECT_TRUE(tight->boundaryPositive);
  EXPECT_TRUE(std::any_of(tight->cells.records.begin(), tight->cells.records.end(),
                          [](const CellRecord& r) { return r.x == 0 || r.y == 22 || r.z == 0; }));
  // Inside out: negative on the whole boundary (no kept cell touches it).
  HermiteField negated = inGrid->field;
  for (HermiteSample& s : negated.samples) s = {-s.f, -s.fx, -s.fy, -s.fz};
  const auto inverted = makeSdfAsset("inverted", std::move(negated), sphere.bounds());
  ASSERT_TRUE(inverted.ok());
  EXPECT_FALSE(inverted.value()->boundaryPositive);
  // Sparse bakes and cells-only assets (loaded files) decide from their kept cells alike.
  auto sparse = bakeCellsSparse(sphere, inGrid->cells.grid);
  ASSERT_TRUE(sparse.ok());
  auto sparseAsset = makeSdfAssetFromSparseBake("sparse", sparse->cells, sparse->stats, 0, sphere.bounds());
  ASSERT_TRUE(sparseAsset.ok());
  EXPECT_TRUE(sparseAsset.value()->boundaryPositive);
  auto cellsOnly = makeSdfAssetFromCells("file", inverted.value()->cells);
  ASSERT_TRUE(cellsOnly.ok());
  EXPECT_FALSE(cellsOnly.value()->boundaryPositive);
  auto cellsOnlyPositive = makeSdfAssetFromCells("file", inGrid->cells);
  ASSERT_TRUE(cellsOnlyPositive.ok());
  EXPECT_TRUE(cellsOnlyPositive.value()->boundaryPositive);

  const GridSpec& grid = inGrid->cells.grid;  // [-1.4, 1.4]^3
  EXPECT_TRUE(brickConeCullAllowed(true, {0.0, 0.0, 5.0}, 0.1, grid));
  EXPECT_FALSE(brickConeCullAllowed(false, {0.0, 0.0, 5.0}, 0.1, grid));
  EXPECT_FALSE(brickConeCullAllowed(true, {0.0, 0.0, 1.0}, 0.1, grid));   // eye inside the grid box
  EXPECT_FALSE(brickConeCullAllowed(true, {0.0, 0.0, 1.45}, 0.1, grid));  // near plane reaches into it
  EXPECT_TRUE(brickConeCullAllowed(true, {0.0, 0.0, 1.55}, 0.1, grid));
}

}  // namespace
}  // namespace hsdf
