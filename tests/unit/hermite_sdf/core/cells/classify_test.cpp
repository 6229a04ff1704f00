// Cell classification: no false negatives, fast path vs full test, zero handling, refinement.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hermite_sdf/core/analytic.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/core/sdf_asset.h"

namespace hsdf {
namespace {

using glm::dvec3;

// A smooth non-SDF field: level c minus a sum of Gaussian bumps, plus a small trigonometric ripple,
// with its exact gradient. Its gradients are far from unit length, unlike the analytic SDFs.
class RandomSmoothSource final : public SdfSource {
 public:
  explicit RandomSmoothSource(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 6; ++i)
      bumps_.push_back({dvec3(unit(rng), unit(rng), unit(rng)) * 1.6 - 0.8, 0.15 + 0.3 * unit(rng), 0.5 + unit(rng)});
    ripple_ = dvec3(unit(rng), unit(rng), unit(rng)) * 12.0;
  }
  SdfSample sample(const dvec3& p) const override {
    SdfSample s{0.35 + 0.05 * std::sin(glm::dot(ripple_, p)), 0.05 * std::cos(glm::dot(ripple_, p)) * ripple_};
    for (const Bump& b : bumps_) {
      const dvec3 d = p - b.centre;
      const double e = b.height * std::exp(-glm::dot(d, d) / (2.0 * b.width * b.width));
      s.value -= e;
      s.gradient += e * d / (b.width * b.width);
    }
    return s;
  }
  Aabb bounds() const override { return {dvec3(-1.0), dvec3(1.0)}; }

 private:
  struct Bump {
    dvec3 centre;
    double width, height;
  };
  std::vector<Bump> bumps_;
  dvec3 ripple_;
};

// Independent of the Bernstein argument: F - sum_c f_c Hx Hy Hz = h sum_c (fx G H H + ...), and
// sum over corners of |G_s(t)| = t(1-t) <= 1/4 while the H's are a partition of unity, so
// |F - sum f_c HHH| <= (h/4)(max|fx| + max|fy| + max|fz|). If every corner value exceeds that with
// one sign, F cannot change sign in the cell. Used only to skip far cells in the dense check.
bool provablyOneSignedByCrudeBound(const HermiteCellCorners<double>& corners, double h) {
  double gx = 0.0, gy = 0.0, gz = 0.0, smallest = HUGE_VAL;
  bool positive = true, negative = true;
  for (const auto& c : corners) {
    gx = std::max(gx, std::abs(c.fx));
    gy = std::max(gy, std::abs(c.fy));
    gz = std::max(gz, std::abs(c.fz));
    smallest = std::min(smallest, std::abs(c.f));
    positive &= c.f > 0.0;
    negative &= c.f < 0.0;
  }
  return (positive || negative) && smallest > 1.001 * 0.25 * h * (gx + gy + gz);
}

struct DenseCheck {
  std::uint64_t emptyCells = 0;
  std::uint64_t sampledDensely = 0;
  std::uint64_t falseNegatives = 0;
};

// Every Empty cell either is one-signed by the crude bound or shows one strict sign at 17^3 points.
// With `skip`, cells already checked (Empty there too) are not checked again.
DenseCheck checkEmptyCellsDensely(const HermiteField& field, const CellClassification& cells,
                                  const CellClassification* skip = nullptr) {
  DenseCheck check;
  const int n = field.grid.cellsPerAxis();
  for (int cz = 0; cz < n; ++cz)
    for (int cy = 0; cy < n; ++cy)
      for (int cx = 0; cx < n; ++cx) {
        if (cells.at(cx, cy, cz) != CellClass::Empty) continue;
        ++check.emptyCells;
        if (skip != nullptr && skip->at(cx, cy, cz) == CellClass::Empty) continue;
        const auto corners = field.cellCorners<double>(cx, cy, cz);
        if (provablyOneSignedByCrudeBound(corners, field.grid.spacing)) continue;
        ++check.sampledDensely;
        check.falseNegatives += denseSamplingFindsSurface(corners, field.grid.spacing, 17);
      }
  return check;
}

// Checks the plain classification, then the cells that refinement (depth 2) drops in addition.
void expectNoFalseNegatives(const HermiteField& field, const std::string& what) {
  auto plain = classifyCells(field, {});
  ClassifyOptions refine;
  refine.refineDepth = 2;
  auto refined = classifyCells(field, refine);
  ASSERT_TRUE(plain.ok() && refined.ok());
  const DenseCheck check = checkEmptyCellsDensely(field, *plain);
  EXPECT_EQ(check.falseNegatives, 0u) << what;
  EXPECT_GT(check.emptyCells, 0u) << what;
  EXPECT_GT(plain->stats.kept(), 0u) << what;
  // Only far-away cells may skip the dense check; near-surface empties must have been sampled.
  if (field.grid.resolution >= 32) {
    EXPECT_GT(check.sampledDensely, 0u) << what;
  }
  const DenseCheck refinedCheck = checkEmptyCellsDensely(field, *refined, &*plain);
  EXPECT_EQ(refinedCheck.falseNegatives, 0u) << what << " (refined)";
}

// Tricky: the analytic shapes include flat box faces lying exactly on sample planes (zero values),
// the concave torus hole and a smooth union blend; every Empty cell near the surface is sampled at
// 17^3 points, with and without de Casteljau refinement. Zero false negatives, not few.
TEST(Classification, NoFalseNegativesOnAnalyticShapes) {
  for (const std::string& name : analyticShapeNames()) {
    auto source = makeAnalyticSource(name);
    ASSERT_TRUE(source.ok());
    for (int k : {16, 32, 64}) {
      auto grid = fitGrid((*source)->bounds(), k, 1);
      ASSERT_TRUE(grid.ok());
      auto field = bakeHermiteField(**source, *grid, {});
      ASSERT_TRUE(field.ok());
      expectNoFalseNegatives(*field, name + " K=" + std::to_string(k));
    }
  }
}

// Why: classifying a large grid takes long after the field is baked (the bunny at K = 256: 0.7 s on 2
// cores), and a cancelled bake had to wait for all of it, the frame that finished the cancelled job
// with it. A token cancelled before (or during) the classification stops it between slabs with
// "cancelled"; one never cancelled changes nothing.
TEST(Classification, StopsWhenCancelled) {
  auto source = makeAnalyticSource("torus");
  ASSERT_TRUE(source.ok());
  auto grid = fitGrid((*source)->bounds(), 24, 1);
  ASSERT_TRUE(grid.ok());
  auto field = bakeHermiteField(**source, *grid, {});
  ASSERT_TRUE(field.ok());
  engine::CancelToken token;
  ClassifyOptions options;
  options.cancel = &token;
  auto whole = classifyCells(*field, options);
  ASSERT_TRUE(whole.ok());
  EXPECT_GT(whole->stats.kept(), 0u);
  token.cancel();
  auto stopped = classifyCells(*field, options);
  ASSERT_FALSE(stopped.ok());
  EXPECT_EQ(stopped.error().message, "cancelled");
  auto asset = makeSdfAsset("torus", std::move(*field), (*source)->bounds(), options);
  ASSERT_FALSE(asset.ok());
  EXPECT_NE(asset.error().message.find("cancelled"), std::string::npos) << asset.error().message;
}

// Tricky: gradients of a non-distance field are far from unit length, so cells far (in value)
// from the surface can still be ambiguous; covers many Bernstein sign patterns the SDFs never make.
TEST(Classification, NoFalseNegativesOnRandomSmoothFields) {
  for (std::uint64_t seed : {21u, 22u, 23u}) {
    const RandomSmoothSource source(seed);
    for (int k : {16, 32, 64}) {
      auto grid = fitGrid(source.bounds(), k, 0);
      ASSERT_TRUE(grid.ok());
      auto field = bakeHermiteField(source, *grid, {});
      ASSERT_TRUE(field.ok());
      expectNoFalseNegatives(*field, "smooth seed " + std::to_string(seed) + " K=" + std::to_string(k));
    }
  }
}

HermiteField randomHermiteField(int k, std::uint64_t seed, double zeroFraction) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_real_distribution<double> coin(0.0, 1.0);
  HermiteField field;
  field.grid.resolution = k;
  field.grid.spacing = 0.1;
  field.samples.resize(field.grid.sampleCount());
  for (int z = 0; z < k; ++z)
    for (int y = 0; y < k; ++y)
      for (int x = 0; x < k; ++x) {
        // Values: a coherent wave plus noise (so whole regions share a sign); gradients: noise
        // unrelated to the values, up to (h/3)|g|_1 = 0.4, so many cells are near misses.
        const double wave = 0.3 * std::sin(0.7 * x + 1.3 * y) * std::cos(0.9 * z);
        HermiteSample& s = field.samples[field.grid.sampleIndex(x, y, z)];
        s = {float(wave + 0.1 * unit(rng)), float(4.0 * unit(rng)), float(4.0 * unit(rng)), float(4.0 * unit(rng))};
        if (coin(rng) < zeroFraction) s.f = 0.0f;
      }
  return field;
}

// Tricky: arbitrary (non-SDF, discontinuous-looking) Hermite data with some exact zeros: the
// Bernstein test alone must still never drop a cell whose interpolant changes sign or touches 0.
TEST(Classification, NoFalseNegativesOnRandomHermiteData) {
  for (int k : {16, 32}) expectNoFalseNegatives(randomHermiteField(k, 31 + std::uint64_t(k), 0.02), "random data");
}

// Tricky: a cell with only positive corners whose interpolant dips below zero in the middle: the
// fast path cannot see it, the Bernstein test must keep it (and dense sampling confirms a crossing).
TEST(Classification, KeepsACellWhoseSurfaceMissesAllCorners) {
  HermiteCellCorners<double> corners{};
  for (int c = 0; c < 8; ++c) {
    const double sx = (c & 1) ? 1.0 : -1.0;  // gradients point outwards: a dip in the middle
    corners[c] = {0.05, 1.0 * sx, 0.0, 0.0};
  }
  ASSERT_FALSE(cornersCrossSurface(corners));
  ASSERT_TRUE(denseSamplingFindsSurface(corners, 1.0, 17));
  EXPECT_EQ(classifyCell(corners, 1.0), CellClass::Ambiguous);
  EXPECT_EQ(classifyCell(corners, 1.0, 2), CellClass::Ambiguous);
}

// Tricky: zeros exactly at a corner, and a Bernstein coefficient exactly zero (the interpolant may
// touch the surface there), must never be dropped by the plain test; a coefficient positive by a
// rounding-sized amount counts as zero too.
TEST(Classification, IsConservativeAtZero) {
  HermiteCellCorners<double> corners{};
  for (auto& c : corners) c = {1.0, 0.0, 0.0, 0.0};
  EXPECT_EQ(classifyCell(corners, 0.5), CellClass::Empty);
  corners[5].f = 0.0;
  EXPECT_EQ(classifyCell(corners, 0.5), CellClass::Crossing);
  corners[5].f = -0.0;
  EXPECT_EQ(classifyCell(corners, 0.5), CellClass::Crossing);
  corners[5].f = 1.0;
  corners[1].fx = 3.0 / 0.5;  // b(2,0,0) = f - (h/3) fx = 0 exactly
  EXPECT_EQ(toBernstein(corners, 0.5)[bernsteinIndex(2, 0, 0)], 0.0);
  EXPECT_EQ(classifyCell(corners, 0.5), CellClass::Ambiguous);
  corners[1].fx = 3.0 / 0.5 * (1.0 - 1e-14);  // positive by a rounding-sized amount: still "zero"
  EXPECT_EQ(classifyCell(corners, 0.5), CellClass::Ambiguous);
  corners[1].fx = 3.0 / 0.5 * 0.9;
  EXPECT_EQ(classifyCell(corners, 0.5), CellClass::Empty);
}

// Tricky: F = (x - 1/2)^2 touches zero on the plane x = 1/2 without changing sign and no corner is
// zero. Subdivision puts exact zeros on the children's shared face, so refinement must keep it.
TEST(Classification, KeepsATangentSurfaceAtEveryRefinementDepth) {
  HermiteCellCorners<double> corners{};
  for (int c = 0; c < 8; ++c) corners[c] = {0.25, (c & 1) ? 1.0 : -1.0, 0.0, 0.0};
  ASSERT_TRUE(denseSamplingFindsSurface(corners, 1.0, 17));  // u = 1/2 is a sample point: F = 0
  for (int depth : {0, 1, 2}) EXPECT_EQ(classifyCell(corners, 1.0, depth), CellClass::Ambiguous) << depth;
}

// Tricky: the fast path and the cheap "obviously empty" shortcut must never disagree with the
// full Bernstein test: every corner-crossing cell has mixed coefficients, and every cell the
// classifier drops has all 64 coefficients strictly one-signed.
TEST(Classification, FastPathAgreesWithTheFullBernsteinTest) {
  const HermiteField field = randomHermiteField(24, 41, 0.01);
  const double h = field.grid.spacing;
  std::uint64_t crossing = 0, ambiguous = 0, empty = 0;
  for (int cz = 0; cz < 23; ++cz)
    for (int cy = 0; cy < 23; ++cy)
      for (int cx = 0; cx < 23; ++cx) {
        const auto corners = field.cellCorners<double>(cx, cy, cz);
        const bool fullTestKeeps = bernsteinMayContainSurface(toBernstein(corners, h), zeroToleranceFor(corners, h));
        const CellClass c = classifyCell(corners, h);
        if (cornersCrossSurface(corners)) {
          ASSERT_TRUE(fullTestKeeps);
          ASSERT_EQ(c, CellClass::Crossing);
          ++crossing;
        } else {
          ASSERT_EQ(c, fullTestKeeps ? CellClass::Ambiguous : CellClass::Empty);
          ++(fullTestKeeps ? ambiguous : empty);
        }
      }
  EXPECT_GT(crossing, 100u);  // the data exercise all three outcomes
  EXPECT_GT(ambiguous, 100u);
  EXPECT_GT(empty, 100u);
}

// Tricky: a cell that the plain test keeps (a coefficient slightly negative) but whose interpolant
// stays positive: one level of de Casteljau subdivision must prove it empty and count it.
TEST(Classification, RefinementDropsFalsePositivesAndCountsThem) {
  HermiteCellCorners<double> corners{};
  for (auto& c : corners) c = {1.0, 0.0, 0.0, 0.0};
  corners[1].fx = 3.3;  // b(2,0,0) = 1 - 3.3/3 = -0.1 with h = 1
  ASSERT_LT(toBernstein(corners, 1.0)[bernsteinIndex(2, 0, 0)], 0.0);
  ASSERT_FALSE(denseSamplingFindsSurface(corners, 1.0, 33));
  EXPECT_EQ(classifyCell(corners, 1.0, 0), CellClass::Ambiguous);
  EXPECT_EQ(classifyCell(corners, 1.0, 1), CellClass::Empty);

  HermiteField field;
  field.grid.resolution = 2;
  field.grid.spacing = 1.0;
  for (int c = 0; c < 8; ++c) field.samples.push_back({float(corners[c].f), float(corners[c].fx), 0.0f, 0.0f});
  ClassifyOptions options;
  options.refineDepth = 1;
  auto refined = classifyCells(field, options);
  ASSERT_TRUE(refined.ok());
  EXPECT_EQ(refined->stats.empty, 1u);
  EXPECT_EQ(refined->stats.refinedEmpty, 1u);
  auto plain = classifyCells(field, {});
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ(plain->stats.ambiguous, 1u);
  EXPECT_EQ(plain->stats.refinedEmpty, 0u);
  options.refineDepth = 3;
  EXPECT_FALSE(classifyCells(field, options).ok());
}

// Tricky: a field whose sample count does not match its grid must be refused, not read out of bounds.
TEST(Classification, RejectsInconsistentFields) {
  HermiteField field;
  field.grid.resolution = 4;
  field.grid.spacing = 1.0;
  field.samples.resize(10);
  auto cells = classifyCells(field, {});
  ASSERT_FALSE(cells.ok());
  EXPECT_NE(cells.error().message.find("10 samples"), std::string::npos) << cells.error().message;
}

// Tricky: the separable dense evaluator used for false-positive counts must be the same function
// as the direct Hermite evaluation, at every grid point including the cell faces.
TEST(Classification, DenseSamplerEqualsHermiteEvaluation) {
  const HermiteField field = randomHermiteField(3, 51, 0.0);
  const auto corners = field.cellCorners<double>(1, 0, 1);
  const std::vector<double> values = sampleCellDensely(corners, 0.1, 5);
  ASSERT_EQ(values.size(), 125u);
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 5; ++i)
        EXPECT_NEAR(values[std::size_t(i + 5 * (j + 5 * k))], hermiteValue(corners, 0.1, Vec3<double>(i, j, k) / 4.0),
                    1e-12);
}

// Prints the statistics the issue asks for (per class counts, false positives with and without
// refinement) and checks their invariants. Tricky: refinement may only move cells from Ambiguous
// to Empty, never touch Crossing cells, and false positives can only come from Ambiguous cells.
TEST(CellStatistics, AnalyticShapesTable) {
  std::printf("| shape | K | cells | crossing | ambiguous | empty | false pos. | FP %% of kept | "
              "kept (refine 2) | FP (refine 2) | FP %% (refine 2) |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& name : analyticShapeNames()) {
    auto source = makeAnalyticSource(name);
    ASSERT_TRUE(source.ok());
    for (int k : {16, 32, 64, 128}) {
      auto grid = fitGrid((*source)->bounds(), k, 1);
      ASSERT_TRUE(grid.ok());
      auto field = bakeHermiteFieldNarrowBand(**source, *grid, {});
      ASSERT_TRUE(field.ok());
      auto plain = classifyCells(*field, {});
      ClassifyOptions refine;
      refine.refineDepth = 2;
      auto refined = classifyCells(*field, refine);
      ASSERT_TRUE(plain.ok() && refined.ok());
      const CellStats& p = plain->stats;
      const CellStats& r = refined->stats;
      EXPECT_EQ(p.crossing + p.ambiguous + p.empty, p.cells);
      EXPECT_EQ(r.crossing, p.crossing);
      EXPECT_EQ(r.ambiguous + r.refinedEmpty, p.ambiguous);
      const FalsePositiveReport fp = countFalsePositives(*field, *plain, 17);
      const FalsePositiveReport fpRefined = countFalsePositives(*field, *refined, 17);
      EXPECT_LE(fp.falsePositives, p.ambiguous);
      EXPECT_LE(fpRefined.falsePositives, fp.falsePositives);
      std::printf("| %s | %d | %llu | %llu | %llu | %llu | %llu | %.2f | %llu | %llu | %.2f |\n", name.c_str(), k,
                  (unsigned long long)p.cells, (unsigned long long)p.crossing, (unsigned long long)p.ambiguous,
                  (unsigned long long)p.empty, (unsigned long long)fp.falsePositives, 100.0 * fp.rate(),
                  (unsigned long long)r.kept(), (unsigned long long)fpRefined.falsePositives, 100.0 * fpRefined.rate());
    }
  }
}

}  // namespace
}  // namespace hsdf
