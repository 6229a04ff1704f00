// Grids, dense and narrow-band bakes: fitting, budgets, errors, threads, progress, cancellation.
#include "hermite_sdf/core/field.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <random>
#include <thread>

#include "hermite_sdf/core/analytic.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/core/mesh_source.h"
#include "../source/mesh_test_meshes.h"

namespace hsdf {
namespace {

using glm::dvec3;

// Tricky: the box is not a cube and not centred at the origin; the longest side (y) must span
// exactly K-1-2P cells with P cells of padding on both ends, and the grid must be centred.
TEST(FitGrid, LongestSideSpansTheCellsBetweenThePadding) {
  const Aabb box{{1.0, -2.0, 0.5}, {2.0, 3.0, 1.5}};
  auto grid = fitGrid(box, 34, 2);
  ASSERT_TRUE(grid.ok()) << grid.error().message;
  EXPECT_EQ(grid->resolution, 34);
  EXPECT_DOUBLE_EQ(grid->spacing, 5.0 / 29.0);
  EXPECT_NEAR(grid->origin.y + 2.0 * grid->spacing, -2.0, 1e-12);             // P cells below
  EXPECT_NEAR(grid->bounds().max.y - 2.0 * grid->spacing, 3.0, 1e-12);        // P cells above
  const dvec3 centre = grid->bounds().center();
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(centre[a], box.center()[a], 1e-12);
}

// Tricky: each bad input must be refused with a message naming the problem, including the
// edge K-1-2P = 0 and a flat (but not empty) box, which is fine.
TEST(FitGrid, RejectsBadInputWithClearErrors) {
  const Aabb unit{{0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}};
  auto expectError = [](const engine::Expected<GridSpec>& r, const char* words) {
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find(words), std::string::npos) << r.error().message;
  };
  expectError(fitGrid(unit, 1, 0), "resolution 1");
  expectError(fitGrid(unit, 5, 2), "leaves 0 cells");
  // 2 * P overflows int here; computed in int it wrapped to a positive span and "fitted" a grid.
  expectError(fitGrid(unit, 16, 2000000000), "leaves -3999999985 cells");
  expectError(fitGrid(unit, 16, std::numeric_limits<int>::max()), "padding cells per side leaves");
  expectError(fitGrid(unit, 8, -1), "padding -1");
  expectError(fitGrid({{0.0, 0.0, 0.0}, {std::nan(""), 1.0, 1.0}}, 8, 1), "not finite");
  expectError(fitGrid({{0.0, 0.0, 0.0}, {HUGE_VAL, 1.0, 1.0}}, 8, 1), "not finite");
  expectError(fitGrid({{1.0, 0.0, 0.0}, {0.0, 1.0, 1.0}}, 8, 1), "inverted");
  expectError(fitGrid({{1.0, 1.0, 1.0}, {1.0, 1.0, 1.0}}, 8, 1), "no extent");
  expectError(fitGrid(unit, kMaxResolution + 1, 1), "resolution");
  EXPECT_TRUE(fitGrid({{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}}, 2, 0).ok());  // flat box, single cell
}

// Tricky: sizes near and above 2^32 bytes must not overflow.
TEST(FieldBytes, EstimateCountsEverySample) {
  GridSpec grid;
  grid.resolution = 256;
  EXPECT_EQ(estimateFieldBytes(grid, FieldKind::Hermite), 256ull * 256 * 256 * 16);
  EXPECT_EQ(estimateFieldBytes(grid, FieldKind::Trilinear), 256ull * 256 * 256 * 4);
  grid.resolution = 4096;
  EXPECT_EQ(estimateFieldBytes(grid, FieldKind::Hermite), 4096ull * 4096 * 4096 * 16);
}

GridSpec gridFor(const SdfSource& source, int k) {
  auto grid = fitGrid(source.bounds(), k, 1);
  EXPECT_TRUE(grid.ok());
  return *grid;
}

// Tricky: with several threads the slabs are written concurrently; every sample must still hold
// the source's value and gradient at its own position (a slab/index mix-up shows immediately).
TEST(DenseBake, StoresTheSourceAtEverySamplePosition) {
  auto torus = makeAnalyticSource("torus");
  ASSERT_TRUE(torus.ok());
  const GridSpec grid = gridFor(**torus, 21);
  BakeOptions options;
  options.threads = 3;
  auto field = bakeHermiteField(**torus, grid, options);
  ASSERT_TRUE(field.ok()) << field.error().message;
  ASSERT_EQ(field->samples.size(), 21u * 21 * 21);
  auto trilinear = bakeTrilinearField(**torus, grid, options);
  ASSERT_TRUE(trilinear.ok());
  for (int k = 0; k < 21; ++k)
    for (int j = 0; j < 21; ++j)
      for (int i = 0; i < 21; ++i) {
        const SdfSample s = (*torus)->sample(grid.samplePosition(i, j, k));
        const HermiteSample& h = field->at(i, j, k);
        ASSERT_EQ(h.f, float(s.value));
        ASSERT_EQ(h.fx, float(s.gradient.x));
        ASSERT_EQ(h.fy, float(s.gradient.y));
        ASSERT_EQ(h.fz, float(s.gradient.z));
        ASSERT_EQ(trilinear->at(i, j, k), float(s.value));
      }
}

// Tricky: a mesh's samples are answered by closest-point searches seeded by the thread's previous
// queries, and which slabs a thread bakes one after the other depends on the thread count and the
// schedule. A cube's grid holds many points equally far from two faces (its medial planes), where a
// seed-dependent answer changes the gradient: the bake must be the same byte for byte with 1, 2
// and 5 threads.
TEST(DenseBake, SameFieldWhateverTheThreadCount) {
  const testing::TestMesh cube = testing::cube(2);
  auto source = MeshSource::create(cube.positions, cube.indices);
  ASSERT_TRUE(source.ok()) << source.error().message;
  const GridSpec grid = gridFor(**source, 24);
  std::vector<HermiteField> fields;
  for (unsigned threads : {1u, 2u, 5u}) {
    BakeOptions options;
    options.threads = threads;
    auto field = bakeHermiteField(**source, grid, options);
    ASSERT_TRUE(field.ok()) << field.error().message;
    fields.push_back(std::move(*field));
  }
  for (std::size_t f = 1; f < fields.size(); ++f) {
    ASSERT_EQ(fields[f].samples.size(), fields[0].samples.size());
    EXPECT_EQ(std::memcmp(fields[f].samples.data(), fields[0].samples.data(),
                          fields[0].samples.size() * sizeof(HermiteSample)),
              0)
        << "threads run " << f;
  }
}

// Tricky: the refusal must happen before allocating (K = 4096 would need 1 TiB) and name both
// the needed bytes and the budget; K = 2 (a single cell) is the smallest valid field.
TEST(DenseBake, RefusesFieldsOverTheBudget) {
  const SphereSource sphere({0.0, 0.0, 0.0}, 1.0);
  BakeOptions options;
  options.memoryBudgetBytes = 1000;
  auto tooBig = bakeHermiteField(sphere, gridFor(sphere, 8), options);  // 8^3 * 16 = 8192 bytes
  ASSERT_FALSE(tooBig.ok());
  EXPECT_NE(tooBig.error().message.find("8192 bytes"), std::string::npos) << tooBig.error().message;
  EXPECT_NE(tooBig.error().message.find("1000 bytes"), std::string::npos) << tooBig.error().message;
  EXPECT_TRUE(bakeTrilinearField(sphere, gridFor(sphere, 6), options).ok());  // 6^3 * 4 = 864 bytes fits
  auto huge = bakeHermiteFieldNarrowBand(sphere, gridFor(sphere, 4096), BakeOptions{});
  ASSERT_FALSE(huge.ok());
  EXPECT_NE(huge.error().message.find("budget"), std::string::npos);
  auto singleGrid = fitGrid(sphere.bounds(), 2, 0);
  ASSERT_TRUE(singleGrid.ok());
  auto single = bakeHermiteField(sphere, *singleGrid, BakeOptions{});
  ASSERT_TRUE(single.ok());
  EXPECT_EQ(single->samples.size(), 8u);
}

// A source that returns NaN in one spot, to check the error names the sample.
class PoisonedSource final : public SdfSource {
 public:
  SdfSample sample(const glm::dvec3& p) const override {
    if (p.x > 0.4 && p.x < 0.6 && p.y > 0.4 && p.y < 0.6 && p.z > 0.4 && p.z < 0.6) return {std::nan(""), dvec3(0.0)};
    return {glm::length(p) - 0.5, glm::normalize(p + 1e-9)};
  }
  Aabb bounds() const override { return {dvec3(-1.0), dvec3(1.0)}; }
};

// Tricky: the bad sample sits in the middle of the grid while other threads keep working; the
// error must name the sample index and position, for the dense and the narrow-band bake alike.
TEST(DenseBake, NonFiniteSourceValueIsAnErrorNamingTheSample) {
  const PoisonedSource source;
  GridSpec grid;
  grid.resolution = 11;
  grid.spacing = 0.2;
  grid.origin = dvec3(-0.9);  // sample (7,7,7) lies at (0.5,0.5,0.5), the only one in the NaN region
  auto field = bakeHermiteField(source, grid, BakeOptions{});
  ASSERT_FALSE(field.ok());
  EXPECT_NE(field.error().message.find("sample (7, 7, 7)"), std::string::npos) << field.error().message;
  EXPECT_NE(field.error().message.find("non-finite"), std::string::npos);
  auto band = bakeHermiteFieldNarrowBand(source, grid, BakeOptions{});
  ASSERT_FALSE(band.ok());
  EXPECT_NE(band.error().message.find("non-finite"), std::string::npos) << band.error().message;
  auto trilinear = bakeTrilinearField(source, grid, BakeOptions{});
  ASSERT_FALSE(trilinear.ok());
}

// Tricky: invalid grids (zero spacing, K = 1) reach the bake directly, without fitGrid.
TEST(DenseBake, RejectsInvalidGrids) {
  const SphereSource sphere({0.0, 0.0, 0.0}, 1.0);
  GridSpec grid;
  grid.resolution = 8;
  grid.spacing = 0.0;
  EXPECT_FALSE(bakeHermiteField(sphere, grid, {}).ok());
  grid.spacing = 0.1;
  grid.resolution = 1;
  auto r = bakeHermiteField(sphere, grid, {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("resolution 1"), std::string::npos);
}

// A source that is slow enough for cancellation to land mid-bake.
class SlowSphere final : public SdfSource {
 public:
  SdfSample sample(const glm::dvec3& p) const override {
    calls.fetch_add(1);
    std::this_thread::sleep_for(std::chrono::microseconds(20));
    return {glm::length(p) - 0.5, dvec3(1.0, 0.0, 0.0)};
  }
  Aabb bounds() const override { return {dvec3(-1.0), dvec3(1.0)}; }
  mutable std::atomic<std::uint64_t> calls{0};
};

// Tricky: the callback must only ever run on the calling thread (UI code is not thread-safe),
// report non-decreasing fractions ending at 1, and returning false must stop the workers early.
TEST(DenseBake, ReportsProgressFromTheCallingThreadAndCanBeCancelled) {
  SlowSphere source;
  GridSpec grid = gridFor(source, 20);
  std::vector<float> fractions;
  std::atomic<bool> wrongThread{false};
  const auto caller = std::this_thread::get_id();
  BakeOptions options;
  options.threads = 2;
  options.progress = [&](float f) {
    if (std::this_thread::get_id() != caller) wrongThread = true;
    fractions.push_back(f);
    return true;
  };
  auto field = bakeTrilinearField(source, grid, options);
  ASSERT_TRUE(field.ok());
  EXPECT_FALSE(wrongThread.load());
  ASSERT_FALSE(fractions.empty());
  EXPECT_EQ(fractions.back(), 1.0f);
  for (std::size_t i = 1; i < fractions.size(); ++i) EXPECT_LE(fractions[i - 1], fractions[i]);

  source.calls = 0;
  options.progress = [&](float) { return false; };
  auto cancelled = bakeHermiteField(source, grid, options);
  ASSERT_FALSE(cancelled.ok());
  EXPECT_EQ(cancelled.error().message, "cancelled");
  EXPECT_LT(source.calls.load(), grid.sampleCount());  // stopped before the end
}

// Tricky: a token cancelled from another thread mid-bake, and one cancelled before the bake, both
// stop it; the narrow-band bake honours the token too.
TEST(DenseBake, CancelTokenStopsTheBake) {
  SlowSphere source;
  const GridSpec grid = gridFor(source, 20);
  engine::CancelToken token;
  BakeOptions options;
  options.cancel = &token;
  std::thread canceller([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    token.cancel();
  });
  auto field = bakeHermiteField(source, grid, options);
  canceller.join();
  ASSERT_FALSE(field.ok());
  EXPECT_EQ(field.error().message, "cancelled");
  EXPECT_LT(source.calls.load(), grid.sampleCount());
  source.calls = 0;
  auto band = bakeHermiteFieldNarrowBand(source, grid, options);
  ASSERT_FALSE(band.ok());
  EXPECT_EQ(band.error().message, "cancelled");
  EXPECT_EQ(source.calls.load(), 0u);
}

// Tricky: the narrow band must (1) keep exactly the dense field's cells, (2) with bit-identical
// corner samples, (3) store sign-correct safe bounds elsewhere, and (4) really skip most samples
// (else the test would pass trivially with a dense bake). Box faces fall on sample planes, so
// zero values are exercised too.
TEST(NarrowBandBake, KeepsExactlyTheDenseCellsWithIdenticalSamples) {
  for (const std::string& name : analyticShapeNames()) {
    auto source = makeAnalyticSource(name);
    ASSERT_TRUE(source.ok());
    for (int k : {16, 33, 64}) {
      const GridSpec grid = gridFor(**source, k);
      auto dense = bakeHermiteField(**source, grid, {});
      auto band = bakeHermiteFieldNarrowBand(**source, grid, {});
      ASSERT_TRUE(dense.ok() && band.ok());
      auto denseCells = classifyCells(*dense);
      auto bandCells = classifyCells(*band);
      ASSERT_TRUE(denseCells.ok() && bandCells.ok());
      ASSERT_EQ(denseCells->classes, bandCells->classes) << name << " K=" << k;
      const int n = grid.cellsPerAxis();
      for (int cz = 0; cz < n; ++cz)
        for (int cy = 0; cy < n; ++cy)
          for (int cx = 0; cx < n; ++cx) {
            if (!denseCells->kept(cx, cy, cz)) continue;
            for (int c = 0; c < 8; ++c) {
              const int i = cx + (c & 1), j = cy + ((c >> 1) & 1), l = cz + ((c >> 2) & 1);
              ASSERT_EQ(std::memcmp(&dense->at(i, j, l), &band->at(i, j, l), sizeof(HermiteSample)), 0)
                  << name << " K=" << k << " sample " << i << "," << j << "," << l;
            }
          }
      std::size_t bounded = 0;
      for (std::size_t s = 0; s < dense->samples.size(); ++s) {
        const HermiteSample &d = dense->samples[s], &b = band->samples[s];
        if (std::memcmp(&d, &b, sizeof(HermiteSample)) == 0) continue;
        ++bounded;
        ASSERT_EQ(b.fx, 0.0f);
        ASSERT_EQ(std::signbit(b.f), std::signbit(d.f)) << name;
        ASSERT_LE(std::abs(b.f), std::abs(d.f) * (1.0f + 1e-6f)) << name;  // a lower bound of |distance|
        ASSERT_GE(std::abs(b.f), float(kNarrowBandExactCells * grid.spacing));
      }
      if (k == 64) {
        EXPECT_GT(bounded, dense->samples.size() / 3) << name << ": the band should skip most samples";
      }
    }
  }
}

}  // namespace
}  // namespace hsdf

namespace hsdf {
namespace {

// Tricky: K = 256 (16.7M samples, 256 MiB of Hermite samples) must bake within the default
// budget; the narrow band keeps it fast, and samples at both ends of the index range must be right
// (an int overflow in the sample index would scramble the upper slabs).
TEST(NarrowBandBake, HandlesResolution256) {
  const SphereSource sphere({0.0, 0.0, 0.0}, 1.0);
  auto grid = fitGrid(sphere.bounds(), 256, 1);
  ASSERT_TRUE(grid.ok());
  auto field = bakeHermiteFieldNarrowBand(sphere, *grid, {});
  ASSERT_TRUE(field.ok()) << field.error().message;
  ASSERT_EQ(field->samples.size(), 256u * 256 * 256);
  for (const glm::ivec3 s : {glm::ivec3(127, 127, 1), glm::ivec3(128, 127, 254), glm::ivec3(1, 128, 128),
                             glm::ivec3(254, 128, 127)}) {
    const SdfSample exact = sphere.sample(grid->samplePosition(s.x, s.y, s.z));
    EXPECT_EQ(field->at(s.x, s.y, s.z).f, float(exact.value)) << "near-surface sample must be exact";
  }
  EXPECT_GT(field->at(0, 0, 0).f, 0.0f);
  EXPECT_LT(field->at(128, 128, 128).f, 0.0f);
}

}  // namespace
}  // namespace hsdf
