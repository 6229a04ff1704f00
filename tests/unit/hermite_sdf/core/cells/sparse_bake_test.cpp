// The sparse bake (sparse_bake.h) against the dense bake + classifyCells + extractCells: the same
// kept cells, classes, counts and bit-identical corner samples, for the analytic shapes, a box whose
// faces lie on sample planes, and the bunny; its cost growing like K^2; budget, cancel and errors.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "engine/scene/gltf/gltf_loader.h"
#include "hermite_sdf/core/analytic.h"
#include "hermite_sdf/core/bake_job.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/core/mesh_source.h"
#include "hermite_sdf/core/sparse_bake.h"
#include "../source/mesh_test_meshes.h"

namespace hsdf {
namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

struct DenseCells {
  CellStream cells;
  CellStats stats;
};

DenseCells bakeDense(const SdfSource& source, const GridSpec& grid, int refineDepth) {
  auto field = bakeHermiteField(source, grid, {});
  EXPECT_TRUE(field.ok()) << field.error().message;
  ClassifyOptions options;
  options.refineDepth = refineDepth;
  auto classes = classifyCells(*field, options);
  EXPECT_TRUE(classes.ok());
  auto cells = extractCells(*field, *classes);
  EXPECT_TRUE(cells.ok());
  return {std::move(*cells), classes->stats};
}

SparseBakeResult bakeSparse(const SdfSource& source, const GridSpec& grid, int refineDepth) {
  SparseBakeOptions options;
  options.refineDepth = refineDepth;
  auto sparse = bakeCellsSparse(source, grid, options);
  EXPECT_TRUE(sparse.ok()) << sparse.error().message;
  return sparse.ok() ? std::move(*sparse) : SparseBakeResult{};
}

void expectSameStats(const CellStats& dense, const CellStats& sparse, const std::string& what) {
  EXPECT_EQ(dense.cells, sparse.cells) << what;
  EXPECT_EQ(dense.crossing, sparse.crossing) << what;
  EXPECT_EQ(dense.ambiguous, sparse.ambiguous) << what;
  EXPECT_EQ(dense.empty, sparse.empty) << what;
  EXPECT_EQ(dense.refinedEmpty, sparse.refinedEmpty) << what;
}

// Coordinates, classes and the 8 corner samples of every record, bit for bit, in the same order;
// the first difference is named.
void expectSameRecords(const CellStream& dense, const CellStream& sparse, const std::string& what) {
  ASSERT_EQ(dense.records.size(), sparse.records.size()) << what;
  for (std::size_t r = 0; r < dense.records.size(); ++r) {
    const CellRecord &a = dense.records[r], &b = sparse.records[r];
    ASSERT_TRUE(a.x == b.x && a.y == b.y && a.z == b.z && a.cellClass == b.cellClass)
        << what << ": record " << r << " is cell (" << a.x << ", " << a.y << ", " << a.z << ") class " << a.cellClass
        << " in the dense bake, (" << b.x << ", " << b.y << ", " << b.z << ") class " << b.cellClass << " in the sparse";
    ASSERT_EQ(std::memcmp(a.corners.data(), b.corners.data(), sizeof(a.corners)), 0)
        << what << ": corners of cell (" << a.x << ", " << a.y << ", " << a.z << ") differ";
  }
}

// Tricky: the pruning margin must hold for Ambiguous cells too (kept without a corner sign change),
// and for refinement's counts; a margin too small drops exactly those. Odd K puts sample planes
// elsewhere than even K, and 16-cell bricks end inside the grid at K = 33.
TEST(SparseBake, KeepsTheDenseCellsOfEveryAnalyticShape) {
  std::uint64_t ambiguous = 0, refinedEmpty = 0;
  for (const std::string& name : analyticShapeNames()) {
    auto source = makeAnalyticSource(name);
    ASSERT_TRUE(source.ok());
    for (int k : {16, 33, 64}) {
      auto grid = fitGrid((*source)->bounds(), k, 1);
      ASSERT_TRUE(grid.ok());
      for (int refine : {0, 1}) {
        const std::string what = name + " K=" + std::to_string(k) + " refine " + std::to_string(refine);
        const DenseCells dense = bakeDense(**source, *grid, refine);
        const SparseBakeResult sparse = bakeSparse(**source, *grid, refine);
        expectSameStats(dense.stats, sparse.stats, what);
        expectSameRecords(dense.cells, sparse.cells, what);
        ambiguous += sparse.stats.ambiguous;
        refinedEmpty += sparse.stats.refinedEmpty;
      }
    }
  }
  EXPECT_GT(ambiguous, 0u) << "no ambiguous cell: the test does not exercise the margin for them";
  EXPECT_GT(refinedEmpty, 0u) << "no cell refined to empty: the test does not exercise refinement";
}

// Tricky: faces exactly on sample planes give corner values of exactly zero, which classify as
// Crossing on both sides of the face; the cells beyond such a face must be found by the sparse
// descent as well (a probe at a brick centre next to the face sees the surface at its edge).
TEST(SparseBake, KeepsTheDenseCellsOfABoxOnSamplePlanes) {
  const BoxSource box(glm::dvec3(0.5, 0.5, 0.5), glm::dvec3(0.25, 0.375, 0.125));
  for (int k : {16, 32, 41}) {
    GridSpec grid;
    grid.resolution = k;
    grid.spacing = 1.0 / 32.0;  // faces at 8/32, 24/32, 4/32, 28/32, 12/32, 20/32: on sample planes
    grid.origin = glm::dvec3(0.0);
    const DenseCells dense = bakeDense(box, grid, 0);
    const SparseBakeResult sparse = bakeSparse(box, grid, 0);
    std::size_t zeros = 0;
    for (const CellRecord& r : dense.cells.records)
      for (const HermiteSample& s : r.corners) zeros += s.f == 0.0f;
    EXPECT_GT(zeros, 0u) << "K=" << k << ": no corner on a face, the test would not exercise zeros";
    expectSameStats(dense.stats, sparse.stats, "box K=" + std::to_string(k));
    expectSameRecords(dense.cells, sparse.cells, "box K=" + std::to_string(k));
  }
}

// Tricky: a cube's triangle mesh puts many samples equally far from two faces (its medial planes),
// and the sparse bake asks the mesh in another order and through other queries (band queries per
// brick) than the dense bake's rows; each query is seeded by the previous one. Both must still pick
// the same face for such a sample (the closest triangle of lowest index), or the corner gradients
// differ between the two bakes, and between runs of either with the thread schedule.
TEST(SparseBake, KeepsTheDenseCellsOfACubeMeshWhoseSamplesTie) {
  const testing::TestMesh cube = testing::cube(2);
  auto mesh = MeshSource::create(cube.positions, cube.indices);
  ASSERT_TRUE(mesh.ok()) << mesh.error().message;
  for (int k : {24, 37}) {
    auto grid = fitGrid((*mesh)->bounds(), k, 2);
    ASSERT_TRUE(grid.ok());
    const DenseCells dense = bakeDense(**mesh, *grid, 1);
    const SparseBakeResult sparse = bakeSparse(**mesh, *grid, 1);
    expectSameStats(dense.stats, sparse.stats, "cube mesh K=" + std::to_string(k));
    expectSameRecords(dense.cells, sparse.cells, "cube mesh K=" + std::to_string(k));
  }
}

std::unique_ptr<MeshSource> loadBunny() {
  auto scene = engine::scene::loadGltf(std::string(HSDF_ASSET_DIR) + "/bunny.glb");
  EXPECT_TRUE(scene.ok()) << scene.error().message;
  if (!scene.ok()) return nullptr;
  auto mesh = MeshSource::create(engine::scene::flattenTriangles(*scene));
  EXPECT_TRUE(mesh.ok()) << mesh.error().message;
  return mesh.ok() ? std::move(*mesh) : nullptr;
}

// Tricky: the mesh answers band queries with bounds instead of distances far from the surface, and
// its sign comes from pseudonormals: the sparse bake must still reproduce the dense samples (from
// sampleRow) bit for bit on a real scan with thin ears, as hsdf_bake fits it (P = 1).
TEST(SparseBake, KeepsTheDenseCellsOfTheBunny) {
  const auto bunny = loadBunny();
  ASSERT_NE(bunny, nullptr);
  for (int k : {16, 32, 64, 100}) {
    auto grid = fitGrid(bunny->bounds(), k, 1);
    ASSERT_TRUE(grid.ok());
    const DenseCells dense = bakeDense(*bunny, *grid, 0);
    const SparseBakeResult sparse = bakeSparse(*bunny, *grid, 0);
    expectSameStats(dense.stats, sparse.stats, "bunny K=" + std::to_string(k));
    expectSameRecords(dense.cells, sparse.cells, "bunny K=" + std::to_string(k));
  }
}

// The point of the sparse bake: its work grows like the kept cells (K^2), not like K^3. Doubling K
// multiplies the kept cells by about 4; the sample queries must follow them (a dense or K^3-bound
// bake would multiply them by 8) and stay a small multiple of the kept cells.
TEST(SparseBake, WorkGrowsWithTheKeptCells) {
  const SphereSource sphere(glm::dvec3(0.0), 1.0);
  std::uint64_t previous = 0;
  for (int k : {64, 128, 256}) {
    auto grid = fitGrid(sphere.bounds(), k, 1);
    ASSERT_TRUE(grid.ok());
    const SparseBakeResult sparse = bakeSparse(sphere, *grid, 0);
    const std::uint64_t kept = sparse.stats.kept();
    ASSERT_GT(kept, 0u);
    EXPECT_LT(sparse.sampleQueries, 8 * kept) << "K=" << k;
    if (previous != 0) {
      const double growth = double(sparse.sampleQueries) / double(previous);
      EXPECT_GT(growth, 3.0) << "K=" << k;
      EXPECT_LT(growth, 5.0) << "K=" << k << ": the sample queries grow like K^3";
    }
    previous = sparse.sampleQueries;
  }
  auto grid = fitGrid(sphere.bounds(), 256, 1);
  EXPECT_LT(previous, grid->sampleCount() / 8) << "K=256 queried more than an eighth of the dense samples";
}

// Tricky: the kept cells are counted while baking, so the refusal comes mid-bake and must name the
// limit; exactly the kept count must pass (a refusal at == would turn away a field that fits).
TEST(SparseBake, KeptCellAndByteBudgetsNameTheLimit) {
  const BakeSource torus = BakeSource::fromShape("torus");
  BakeSettings settings;
  settings.resolution = 40;
  settings.band = BakeBand::Sparse;
  auto full = bakeAsset(torus, settings);
  ASSERT_TRUE(full.ok()) << full.error().message;
  const std::uint64_t kept = (*full)->cells.records.size();
  ASSERT_GT(kept, 1000u);

  settings.budget.maxKeptCells = kept - 1;
  auto refused = bakeAsset(torus, settings);
  ASSERT_FALSE(refused.ok());
  EXPECT_TRUE(contains(refused.error().message, "over the bake budget's max kept cells " + std::to_string(kept - 1)))
      << refused.error().message;
  settings.budget.maxKeptCells = kept;
  EXPECT_TRUE(bakeAsset(torus, settings).ok()) << "exactly the kept cells must fit";

  settings.budget.maxBytes = kept * kSparseBakeBytesPerKeptCell - 1;
  auto overBytes = bakeAsset(torus, settings);
  ASSERT_FALSE(overBytes.ok());
  EXPECT_TRUE(contains(overBytes.error().message, "over the bake budget's max bytes " + std::to_string(kept * kSparseBakeBytesPerKeptCell - 1)))
      << overBytes.error().message;
  settings.budget.maxBytes = kept * kSparseBakeBytesPerKeptCell;
  EXPECT_TRUE(bakeAsset(torus, settings).ok()) << "exactly the kept cells' bytes must fit";
}

// K^3 limits no longer apply to the sparse bake: K = 1024 (10^9 samples, over maxSamples) plans,
// while the dense bake of the same grid is still refused by that limit.
TEST(SparseBake, PlansResolutionsTheSampleBudgetRefuses) {
  auto prepared = prepareSource(BakeSource::fromShape("sphere"), BakeSettings{});
  ASSERT_TRUE(prepared.ok());
  BakeSettings settings;
  settings.resolution = 1024;
  auto dense = planBake(*prepared, settings);
  ASSERT_FALSE(dense.ok());
  EXPECT_TRUE(contains(dense.error().message, "max samples")) << dense.error().message;
  settings.band = BakeBand::Sparse;
  auto sparse = planBake(*prepared, settings);
  EXPECT_TRUE(sparse.ok()) << sparse.error().message;
  settings.budget.maxResolution = 512;
  auto overResolution = planBake(*prepared, settings);
  ASSERT_FALSE(overResolution.ok());
  EXPECT_TRUE(contains(overResolution.error().message, "max resolution 512")) << overResolution.error().message;
}

// The asset of a sparse bake: the dense bake's cells and counts, the grid in field.grid, and no
// dense samples (nothing K^3 was allocated); the worker thread gives the same records.
TEST(SparseBake, BakeJobMakesACellsOnlyAssetEqualToTheDenseOne) {
  BakeSettings settings;
  settings.resolution = 48;
  settings.refineDepth = 1;
  const BakeSource blob = BakeSource::fromShape("blob");
  auto dense = bakeAsset(blob, settings);
  ASSERT_TRUE(dense.ok()) << dense.error().message;
  settings.band = BakeBand::Sparse;
  BakeJob job(blob, settings);
  const BakeJob::Result sparse = job.wait();
  ASSERT_TRUE(sparse.ok()) << sparse.error().message;
  EXPECT_FLOAT_EQ(job.progress(), 1.0f);
  const SdfAsset &a = **dense, &b = **sparse;
  EXPECT_TRUE(b.field.samples.empty());
  EXPECT_EQ(b.field.grid.resolution, 48);
  EXPECT_EQ(b.field.grid.spacing, a.field.grid.spacing);
  EXPECT_EQ(b.classification.refineDepth, 1);
  EXPECT_EQ(b.surfaceBounds.min, a.surfaceBounds.min);
  expectSameStats(a.classification.stats, b.classification.stats, "blob asset");
  expectSameRecords(a.cells, b.cells, "blob asset");
  ASSERT_EQ(a.cellsHalf.records.size(), b.cellsHalf.records.size());
  EXPECT_EQ(std::memcmp(a.cellsHalf.records.data(), b.cellsHalf.records.data(),
                        a.cellsHalf.records.size() * sizeof(CellRecordHalf)),
            0);
}

TEST(SparseBake, CancelsByTokenAndByProgressCallback) {
  const SphereSource sphere(glm::dvec3(0.0), 1.0);
  auto grid = fitGrid(sphere.bounds(), 128, 1);
  ASSERT_TRUE(grid.ok());
  engine::CancelToken token;
  token.cancel();
  SparseBakeOptions byToken;
  byToken.cancel = &token;
  auto cancelled = bakeCellsSparse(sphere, *grid, byToken);
  ASSERT_FALSE(cancelled.ok());
  EXPECT_EQ(cancelled.error().message, "cancelled");

  SparseBakeOptions byCallback;
  byCallback.threads = 1;
  byCallback.progress = [](float) { return false; };
  auto stopped = bakeCellsSparse(sphere, *grid, byCallback);
  ASSERT_FALSE(stopped.ok());
  EXPECT_EQ(stopped.error().message, "cancelled");
}

// A sphere whose distance is NaN in one octant: the error must say so (never a cell of garbage).
class BrokenSphere final : public SdfSource {
 public:
  SdfSample sample(const glm::dvec3& p) const override {
    if (p.x > 0.5 && p.y > 0.5 && p.z > 0.5) return {std::numeric_limits<double>::quiet_NaN(), glm::dvec3(0.0)};
    return inner_.sample(p);
  }
  Aabb bounds() const override { return inner_.bounds(); }

 private:
  SphereSource inner_{glm::dvec3(0.0), 1.0};
};

TEST(SparseBake, RefusesNonFiniteSourcesAndBadOptions) {
  const BrokenSphere broken;
  auto grid = fitGrid(broken.bounds(), 32, 1);
  ASSERT_TRUE(grid.ok());
  auto baked = bakeCellsSparse(broken, *grid);
  ASSERT_FALSE(baked.ok());
  EXPECT_TRUE(contains(baked.error().message, "non-finite")) << baked.error().message;

  const SphereSource sphere(glm::dvec3(0.0), 1.0);
  SparseBakeOptions refine;
  refine.refineDepth = 3;
  auto badRefine = bakeCellsSparse(sphere, *grid, refine);
  ASSERT_FALSE(badRefine.ok());
  EXPECT_TRUE(contains(badRefine.error().message, "refinement depth 3")) << badRefine.error().message;
  GridSpec badGrid = *grid;
  badGrid.spacing = 0.0;
  EXPECT_FALSE(bakeCellsSparse(sphere, badGrid).ok());
}

}  // namespace
}  // namespace hsdf
