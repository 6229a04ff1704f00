// The Stanford bunny (samples/assets/bunny.glb) through the mesh source: no false negatives in the
// classification, the narrow-band bake equal to the dense one, and the storage table of the paper.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "engine/scene/gltf/gltf_loader.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/core/mesh_source.h"

namespace hsdf {
namespace {

std::unique_ptr<MeshSource> loadBunny() {
  auto scene = engine::scene::loadGltf(std::string(HSDF_ASSET_DIR) + "/bunny.glb");
  EXPECT_TRUE(scene.ok()) << scene.error().message;
  if (!scene.ok()) return nullptr;
  auto mesh = MeshSource::create(engine::scene::flattenTriangles(*scene));
  EXPECT_TRUE(mesh.ok()) << mesh.error().message;
  return mesh.ok() ? std::move(*mesh) : nullptr;
}

// Independent sufficient condition for "no sign change in the cell" (see classify_test.cpp):
// |F - sum f_c HHH| <= (h/4)(max|fx| + max|fy| + max|fz|).
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

// Tricky: a real scanned mesh (thin ears, concave folds) fitted as hsdf_bake fits it (P = 1); every
// Empty cell not far from the surface is sampled at 17^3 points, with and without refinement.
// Zero false negatives. K = 128 uses the narrow-band bake (identical classes, tested below).
TEST(BunnyClassification, NoFalseNegatives) {
  const auto bunny = loadBunny();
  ASSERT_NE(bunny, nullptr);
  for (int k : {16, 32, 64, 128}) {
    auto grid = fitGrid(bunny->bounds(), k, 1);
    ASSERT_TRUE(grid.ok());
    auto field = k < 128 ? bakeHermiteField(*bunny, *grid, {}) : bakeHermiteFieldNarrowBand(*bunny, *grid, {});
    ASSERT_TRUE(field.ok()) << field.error().message;
    auto plain = classifyCells(*field, {});
    ClassifyOptions refine;
    refine.refineDepth = 2;
    auto refined = classifyCells(*field, refine);
    ASSERT_TRUE(plain.ok() && refined.ok());
    std::uint64_t sampled = 0, falseNegatives = 0;
    const int n = grid->cellsPerAxis();
    for (int cz = 0; cz < n; ++cz)
      for (int cy = 0; cy < n; ++cy)
        for (int cx = 0; cx < n; ++cx) {
          // Empty after refinement covers every cell the plain test drops, and more.
          if (refined->at(cx, cy, cz) != CellClass::Empty) continue;
          const auto corners = field->cellCorners<double>(cx, cy, cz);
          if (provablyOneSignedByCrudeBound(corners, grid->spacing)) continue;
          ++sampled;
          falseNegatives += denseSamplingFindsSurface(corners, grid->spacing, 17);
        }
    EXPECT_EQ(falseNegatives, 0u) << "K=" << k;
    EXPECT_GT(sampled, 0u) << "K=" << k;
    EXPECT_GE(refined->stats.empty, plain->stats.empty);
  }
}

// Tricky: the mesh source answers far band queries with bounds from its own (BVH) reasoning, not
// with the analytic shapes' exact values; the narrow band must still keep exactly the dense
// field's cells with bit-identical corner samples.
TEST(BunnyClassification, NarrowBandKeepsTheDenseCells) {
  const auto bunny = loadBunny();
  ASSERT_NE(bunny, nullptr);
  for (int k : {32, 64}) {
    auto grid = fitGrid(bunny->bounds(), k, 1);
    ASSERT_TRUE(grid.ok());
    auto dense = bakeHermiteField(*bunny, *grid, {});
    auto band = bakeHermiteFieldNarrowBand(*bunny, *grid, {});
    ASSERT_TRUE(dense.ok() && band.ok());
    auto denseCells = classifyCells(*dense, {});
    auto bandCells = classifyCells(*band, {});
    ASSERT_TRUE(denseCells.ok() && bandCells.ok());
    EXPECT_EQ(denseCells->classes, bandCells->classes) << "K=" << k;
    auto denseStream = extractCells(*dense, *denseCells);
    auto bandStream = extractCells(*band, *bandCells);
    ASSERT_TRUE(denseStream.ok() && bandStream.ok());
    ASSERT_EQ(denseStream->records.size(), bandStream->records.size());
    EXPECT_EQ(std::memcmp(denseStream->records.data(), bandStream->records.data(), denseStream->stored_bytes()), 0)
        << "K=" << k;
  }
}

// Prints the paper's storage comparison for the bunny: scalars of a dense trilinear field (K^3), a
// dense Hermite field (4 K^3) and the Hermite cell stream (32 per kept cell), plus false positives.
// Tricky: the cell stream must stay below the dense Hermite field from K = 32 on (it grows with
// K^2, not K^3): the paper's whole point about storage.
TEST(BunnyClassification, StorageTable) {
  const auto bunny = loadBunny();
  ASSERT_NE(bunny, nullptr);
  std::printf("| K | kept cells | crossing | ambiguous | trilinear scalars | Hermite scalars | Hermite cell scalars | "
              "false pos. | FP %% | FP (refine 2) |\n|---|---|---|---|---|---|---|---|---|---|\n");
  for (int k : {16, 32, 64, 128}) {
    auto grid = fitGrid(bunny->bounds(), k, 1);
    ASSERT_TRUE(grid.ok());
    auto field = bakeHermiteFieldNarrowBand(*bunny, *grid, {});
    ASSERT_TRUE(field.ok());
    auto cells = classifyCells(*field, {});
    ClassifyOptions refine;
    refine.refineDepth = 2;
    auto refined = classifyCells(*field, refine);
    ASSERT_TRUE(cells.ok() && refined.ok());
    auto stream = extractCells(*field, *cells);
    ASSERT_TRUE(stream.ok());
    const FalsePositiveReport fp = countFalsePositives(*field, *cells, 17);
    const FalsePositiveReport fpRefined = countFalsePositives(*field, *refined, 17);
    const std::uint64_t k3 = grid->sampleCount();
    if (k >= 32) {
      EXPECT_LT(stream->stored_scalars(), 4 * k3);
    }
    std::printf("| %d | %llu | %llu | %llu | %llu | %llu | %llu | %llu | %.2f | %llu |\n", k,
                (unsigned long long)cells->stats.kept(), (unsigned long long)cells->stats.crossing,
                (unsigned long long)cells->stats.ambiguous, (unsigned long long)k3, (unsigned long long)(4 * k3),
                (unsigned long long)stream->stored_scalars(), (unsigned long long)fp.falsePositives, 100.0 * fp.rate(),
                (unsigned long long)fpRefined.falsePositives);
  }
}

}  // namespace
}  // namespace hsdf
