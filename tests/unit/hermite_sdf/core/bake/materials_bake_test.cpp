// Multi-material bakes (hermite_sdf/core/materials.h): every sample records the material slot of
// its closest triangle, the kept cells carry their corners' slots, and a mesh of one material
// bakes exactly as before.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <string>

#include <fmt/format.h>

#include <gtest/gtest.h>

#include "engine/scene/gltf/gltf_loader.h"
#include "hermite_sdf/core/bake_job.h"
#include "hermite_sdf/core/materials.h"
#include "hermite_sdf/core/sparse_bake.h"
#include "two_material_box.h"

namespace hsdf {
namespace {

using hsdftest::twoMaterialBoxScene;

// Squared distance from p to triangle (a, b, c), written plainly as the test's own reference
// (projection onto the plane when it falls inside, else the nearest of the three edges), not the
// Voronoi-region code the mesh source uses.
double segmentDistance2(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
  const glm::dvec3 d = p - (a + t * ab);
  return glm::dot(d, d);
}

double triangleDistance2(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const glm::dvec3 q = p - glm::dot(p - a, n) / glm::dot(n, n) * n;
  const bool inside = glm::dot(glm::cross(b - a, q - a), n) >= 0.0 && glm::dot(glm::cross(c - b, q - b), n) >= 0.0 &&
                      glm::dot(glm::cross(a - c, q - c), n) >= 0.0;
  if (inside) return glm::dot(p - q, p - q);
  return std::min({segmentDistance2(p, a, b), segmentDistance2(p, b, c), segmentDistance2(p, c, a)});
}

BakeSource twoMaterialSource(bool twoMaterials = true, const glm::vec3& half = hsdftest::kBoxHalf) {
  auto source = BakeSource::fromScene("box", twoMaterialBoxScene(twoMaterials, half));
  EXPECT_TRUE(source) << source.error().message;
  return source ? std::move(*source) : BakeSource{};
}

std::shared_ptr<const SdfAsset> bake(const BakeSource& source, int resolution, BakeBand band, unsigned threads = 0) {
  BakeSettings settings;
  settings.resolution = resolution;
  settings.band = band;
  settings.threads = threads;
  auto asset = bakeAsset(source, settings);
  EXPECT_TRUE(asset) << asset.error().message;
  return asset ? *asset : nullptr;
}

// The glTF materials become the palette in the order the primitives first use them.
TEST(MaterialsBake, PaletteHoldsTheMaterialsInTheOrderOfFirstUse) {
  const BakeSource source = twoMaterialSource();
  ASSERT_TRUE(source.materials);
  ASSERT_EQ(source.materials->palette.size(), 2u);
  EXPECT_EQ(source.materials->palette[0].baseColor, hsdftest::kRed);
  EXPECT_EQ(source.materials->palette[1].baseColor, hsdftest::kBlue);
  EXPECT_FLOAT_EQ(source.materials->palette[1].roughness, 0.7f);
  const auto asset = bake(source, 16, BakeBand::Dense);
  ASSERT_TRUE(asset);
  EXPECT_EQ(asset->palette, source.materials->palette);
}

// Counts the samples whose closest triangles are of one material (clear) and of both (tied), and
// checks every sample's slot against them.
void checkClosestMaterials(const BakeSource& source, const SdfAsset& asset, int& clear, int& tied);

// Tricky: the closest triangle is what the BVH query found from a seed the thread's previous
// queries left; a slot taken from the seed, from the wrong index space (input order vs BVH order
// vs the order after dropping) or from the first triangle tested would match here only by chance.
// Samples equidistant from both materials (on the split plane's extension, at edges) may take
// either; the test counts that most samples have one clear answer, so it is not vacuous.
TEST(MaterialsBake, EverySampleTakesItsClosestTrianglesMaterial) {
  const BakeSource source = twoMaterialSource();
  const auto asset = bake(source, 20, BakeBand::Dense);
  ASSERT_TRUE(asset);
  int clear = 0, tied = 0;
  checkClosestMaterials(source, *asset, clear, tied);
  std::printf("[ materials ] %d samples with one closest material, %d tied between both\n", clear, tied);
  EXPECT_GT(clear, 7000);
  const HermiteField& field = asset->field;
  // Both materials present (slot 0 everywhere would pass the checks above only with one).
  EXPECT_TRUE(std::count(field.materials.begin(), field.materials.end(), 1) > 1000);
  EXPECT_TRUE(std::count(field.materials.begin(), field.materials.end(), 0) > 1000);
}

// Tricky: a box whose caps (red top, blue bottom) are its nearest faces, at an odd K: the samples of
// its medial plane y = 0 are exactly as close to a red and a blue triangle. Their slot is the tie
// rule's (the lowest BVH index), the same whatever the thread schedule; a slot from the seed (the
// thread's previous query) would follow the schedule.
TEST(MaterialsBake, SamplesEquallyCloseToTwoMaterialsTakeTheSameSlotWhateverTheThreads) {
  const BakeSource source = twoMaterialSource(true, glm::vec3(1.0f, 0.5f, 0.9f));
  const auto one = bake(source, 21, BakeBand::Dense, 1);
  ASSERT_TRUE(one);
  int clear = 0, tied = 0;
  checkClosestMaterials(source, *one, clear, tied);
  std::printf("[ materials, ties ] %d samples with one closest material, %d tied between both\n", clear, tied);
  EXPECT_GT(tied, 20);
  for (const unsigned threads : {2u, 3u, 7u}) {
    const auto many = bake(source, 21, BakeBand::Dense, threads);
    ASSERT_TRUE(many);
    EXPECT_TRUE(many->field.materials == one->field.materials) << threads << " threads";
  }
}

void checkClosestMaterials(const BakeSource& source, const SdfAsset& asset, int& clear, int& tied) {
  const HermiteField& field = asset.field;
  ASSERT_EQ(field.materials.size(), field.samples.size());
  const engine::scene::TriangleSoup& soup = *source.triangles;
  for (int k = 0; k < field.grid.resolution; ++k)
    for (int j = 0; j < field.grid.resolution; ++j)
      for (int i = 0; i < field.grid.resolution; ++i) {
        const glm::dvec3 p = field.grid.samplePosition(i, j, k);
        double best = std::numeric_limits<double>::infinity();
        std::vector<double> d2(soup.indices.size() / 3);
        for (std::size_t t = 0; t < d2.size(); ++t) {
          d2[t] = triangleDistance2(p, soup.positions[soup.indices[3 * t]], soup.positions[soup.indices[3 * t + 1]],
                                    soup.positions[soup.indices[3 * t + 2]]);
          best = std::min(best, d2[t]);
        }
        std::set<int> allowed;  // the slots of every triangle as close as the closest, to rounding
        for (std::size_t t = 0; t < d2.size(); ++t)
          if (d2[t] <= best * (1.0 + 1e-9) + 1e-24) allowed.insert(soup.triangleMaterials[t]);
        (allowed.size() == 1 ? clear : tied)++;
        const int slot = field.materials[field.grid.sampleIndex(i, j, k)];
        ASSERT_TRUE(allowed.contains(slot)) << "sample (" << i << ", " << j << ", " << k << ") has slot " << slot;
      }
}

// Each kept cell's corner slots are the slots of its 8 corner samples, in corner order x + 2y + 4z,
// in the fp32 and fp16 streams alike: the GPU's "nearest corner" reads them by corner index.
TEST(MaterialsBake, KeptCellsCarryTheirCornersSlots) {
  const auto asset = bake(twoMaterialSource(), 20, BakeBand::Dense);
  ASSERT_TRUE(asset);
  const CellStream& cells = asset->cells;
  ASSERT_EQ(cells.materials.size(), cells.records.size());
  EXPECT_EQ(asset->cellsHalf.materials, cells.materials);
  bool both = false;
  for (std::size_t r = 0; r < cells.records.size(); ++r) {
    const CellRecord& record = cells.records[r];
    for (int c = 0; c < 8; ++c) {
      const std::size_t s = asset->field.grid.sampleIndex(record.x + (c & 1), record.y + ((c >> 1) & 1), record.z + ((c >> 2) & 1));
      ASSERT_EQ(cells.materials[r][std::size_t(c)], asset->field.materials[s]) << "record " << r << " corner " << c;
    }
    both = both || std::set<MaterialSlot>(cells.materials[r].begin(), cells.materials[r].end()).size() > 1;
  }
  EXPECT_TRUE(both) << "no cell straddles the split: the corner order would not be tested";
}

// Tricky: the sparse bake takes its samples from band queries cached per brick and assembles the
// records slab by slab in sorted order; slots cached beside the wrong sample or not reordered with
// their records differ from the dense bake's here. The narrow band's two passes likewise.
TEST(MaterialsBake, SparseAndNarrowBandBakesRecordTheDenseBakesSlots) {
  const BakeSource source = twoMaterialSource();
  const auto dense = bake(source, 24, BakeBand::Dense);
  const auto sparse = bake(source, 24, BakeBand::Sparse);
  const auto narrow = bake(source, 24, BakeBand::NarrowBand);
  ASSERT_TRUE(dense && sparse && narrow);
  ASSERT_EQ(sparse->cells.records.size(), dense->cells.records.size());
  EXPECT_TRUE(sparse->cells.materials == dense->cells.materials);
  EXPECT_TRUE(narrow->cells.materials == dense->cells.materials);
  EXPECT_EQ(sparse->palette, dense->palette);
}

// Tricky: the seed of each closest-point query comes from the thread's previous queries, so a
// slot taken from anything but the tie-broken closest triangle changes with the thread count.
TEST(MaterialsBake, SlotsDoNotDependOnTheThreadCount) {
  const BakeSource source = twoMaterialSource();
  const auto one = bake(source, 28, BakeBand::Dense, 1);
  ASSERT_TRUE(one);
  for (const unsigned threads : {2u, 3u, 7u}) {
    const auto many = bake(source, 28, BakeBand::Dense, threads);
    ASSERT_TRUE(many);
    EXPECT_TRUE(many->field.materials == one->field.materials) << threads << " threads";
    EXPECT_TRUE(many->cells.materials == one->cells.materials) << threads << " threads";
    const auto sparse = bake(source, 28, BakeBand::Sparse, threads);
    ASSERT_TRUE(sparse);
    EXPECT_TRUE(sparse->cells.materials == one->cells.materials) << threads << " threads, sparse";
  }
}

// A mesh of one material (two primitives, one material) bakes no slots and no palette, and the
// same samples and records, byte for byte, as the same triangles with no materials at all.
TEST(MaterialsBake, OneMaterialBakesExactlyAsBefore) {
  const BakeSource single = twoMaterialSource(false);
  EXPECT_FALSE(single.materials);
  engine::scene::TriangleSoup bare = *single.triangles;
  bare.triangleMaterials.clear();
  const auto a = bake(single, 20, BakeBand::Dense);
  const auto b = bake(BakeSource::fromTriangles("box", bare), 20, BakeBand::Dense);
  ASSERT_TRUE(a && b);
  EXPECT_TRUE(a->palette.empty());
  EXPECT_TRUE(a->field.materials.empty());
  EXPECT_TRUE(a->cells.materials.empty());
  EXPECT_TRUE(a->cellsHalf.materials.empty());
  ASSERT_EQ(a->field.samples.size(), b->field.samples.size());
  EXPECT_EQ(std::memcmp(a->field.samples.data(), b->field.samples.data(), a->field.samples.size() * sizeof(HermiteSample)), 0);
  ASSERT_EQ(a->cells.records.size(), b->cells.records.size());
  EXPECT_EQ(std::memcmp(a->cells.records.data(), b->cells.records.data(), a->cells.records.size() * sizeof(CellRecord)), 0);
  // And the two-material bake's geometry is that one too: materials change no value.
  const auto two = bake(twoMaterialSource(), 20, BakeBand::Dense);
  ASSERT_TRUE(two);
  EXPECT_EQ(std::memcmp(two->field.samples.data(), b->field.samples.data(), b->field.samples.size() * sizeof(HermiteSample)), 0);
}

// A slot is one byte: the 257th material is refused by name, not wrapped to slot 0.
TEST(MaterialsBake, MoreMaterialsThanASlotHoldsAreRefused) {
  engine::scene::SceneData scene;
  engine::scene::MeshData mesh;
  for (int m = 0; m < 257; ++m) {
    scene.materials.push_back({"m", glm::vec4(1.0f), 0.0f, 0.5f});
    engine::scene::MeshPrimitiveData p;
    const float x = float(m);
    p.positions = {{x, 0, 0}, {x + 1, 0, 0}, {x, 1, 0}, {x, 0, 1}};
    p.normals.assign(4, glm::vec3(0, 1, 0));
    p.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    p.material = m;
    mesh.primitives.push_back(p);
  }
  scene.meshes.push_back(mesh);
  scene.nodes.push_back({"n", -1, glm::mat4(1.0f), glm::mat4(1.0f), 0, -1, {}});
  auto source = BakeSource::fromScene("many", scene);
  ASSERT_FALSE(source);
  EXPECT_NE(source.error().message.find("257 materials"), std::string::npos) << source.error().message;
  EXPECT_NE(source.error().message.find("256"), std::string::npos) << source.error().message;
}

// Slots past the palette, or slots without one, are refused when an asset is made.
TEST(MaterialsBake, AssetsRefuseSlotsOutsideTheirPalette) {
  const auto asset = bake(twoMaterialSource(), 12, BakeBand::Dense);
  ASSERT_TRUE(asset);
  CellStream cells = asset->cells;
  auto noPalette = makeSdfAssetFromCells("x", cells);
  ASSERT_FALSE(noPalette);
  EXPECT_NE(noPalette.error().message.find("no palette"), std::string::npos) << noPalette.error().message;
  cells.materials.front()[3] = 2;
  auto past = makeSdfAssetFromCells("x", cells, asset->palette);
  ASSERT_FALSE(past);
  EXPECT_NE(past.error().message.find("past the palette"), std::string::npos) << past.error().message;
}

// The shading rule's nearest corner: 0.5 goes up, as in the shaders.
TEST(MaterialsBake, NearestCornerRoundsHalfUp) {
  EXPECT_EQ(nearestCorner({0.49, 0.49, 0.49}), 0);
  EXPECT_EQ(nearestCorner({0.5, 0.0, 0.0}), 1);
  EXPECT_EQ(nearestCorner({0.0, 0.5, 0.0}), 2);
  EXPECT_EQ(nearestCorner({0.2, 0.7, 0.9}), 6);
  EXPECT_EQ(nearestCorner({1.0, 1.0, 1.0}), 7);
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Tricky: a slot is 1 byte a sample against a sample's 16, so a budget that holds the same grid's
// bake of one material exactly is pushed over by the slots alone: the two-material bake must be
// refused naming the bytes with its slots (they were allocated past the budget, uncounted), the
// one-material bake of the same box (same grid) still fits, and the slots' bytes are enough.
TEST(MaterialsBake, TheBakeBudgetCountsTheMaterialSlots) {
  const BakeSource two = twoMaterialSource(true), one = twoMaterialSource(false);
  auto prepared = prepareSource(two, BakeSettings{});
  ASSERT_TRUE(prepared) << prepared.error().message;
  for (const BakeBand band : {BakeBand::Dense, BakeBand::NarrowBand}) {
    BakeSettings settings;
    settings.resolution = 16;
    settings.band = band;
    auto grid = planBake(*prepared, settings);
    ASSERT_TRUE(grid) << grid.error().message;
    const std::uint64_t without = estimateBakeBytes(*grid, band), with = estimateBakeBytes(*grid, band, true);
    EXPECT_EQ(with - without, grid->sampleCount()) << "one slot byte a sample";
    settings.budget.maxBytes = without;
    const auto refused = bakeAsset(two, settings);
    ASSERT_FALSE(refused) << "band " << int(band);
    EXPECT_TRUE(contains(refused.error().message, fmt::format("needs {} bytes", with))) << refused.error().message;
    EXPECT_TRUE(contains(refused.error().message, fmt::format("over the bake budget's max bytes {} ", without)))
        << refused.error().message;
    EXPECT_TRUE(bakeAsset(one, settings)) << "one material: no slots, the same budget holds it";
    settings.budget.maxBytes = with;
    EXPECT_TRUE(bakeAsset(two, settings)) << "the slots' bytes are all the two-material bake needs more";
  }
}

// Tricky: the field bakes check the budget themselves (a caller of bakeHermiteField has no bake
// job): a field whose samples fit exactly is refused once its slots are counted, both bakes.
TEST(MaterialsBake, TheFieldBudgetCountsTheMaterialSlots) {
  auto prepared = prepareSource(twoMaterialSource(true), BakeSettings{});
  ASSERT_TRUE(prepared) << prepared.error().message;
  BakeSettings settings;
  settings.resolution = 12;
  auto grid = planBake(*prepared, settings);
  ASSERT_TRUE(grid) << grid.error().message;
  BakeOptions options;
  options.memoryBudgetBytes = estimateFieldBytes(*grid, FieldKind::Hermite);
  for (auto bakeField : {&bakeHermiteField, &bakeHermiteFieldNarrowBand}) {
    options.memoryBudgetBytes = estimateFieldBytes(*grid, FieldKind::Hermite);
    const auto refused = bakeField(*prepared->source, *grid, options);
    ASSERT_FALSE(refused);
    EXPECT_TRUE(contains(refused.error().message, "samples and their material slots) needs " +
                                                      std::to_string(estimateFieldBytes(*grid, FieldKind::Hermite, true))))
        << refused.error().message;
    options.memoryBudgetBytes = estimateFieldBytes(*grid, FieldKind::Hermite, true);
    EXPECT_TRUE(bakeField(*prepared->source, *grid, options));
  }
}

// Tricky: the sparse bake's budget is per kept cell, known only while it bakes; a two-material
// bake holds each kept cell's 8 corner slots twice (slab and stream) on top of the records.
TEST(MaterialsBake, TheSparseBudgetCountsTheCornerSlots) {
  const BakeSource two = twoMaterialSource(true);
  BakeSettings settings;
  settings.resolution = 20;
  settings.band = BakeBand::Sparse;
  const auto full = bakeAsset(two, settings);
  ASSERT_TRUE(full) << full.error().message;
  const std::uint64_t kept = (*full)->cells.records.size();
  ASSERT_GT(kept, 100u);
  EXPECT_EQ(sparseBakeBytesPerKeptCell(true), kSparseBakeBytesPerKeptCell + 2 * sizeof(CellMaterialSlots));
  settings.budget.maxBytes = kept * kSparseBakeBytesPerKeptCell;
  const auto refused = bakeAsset(two, settings);
  ASSERT_FALSE(refused);
  EXPECT_TRUE(contains(refused.error().message, fmt::format("at {} bytes a cell", sparseBakeBytesPerKeptCell(true))))
      << refused.error().message;
  settings.budget.maxBytes = kept * sparseBakeBytesPerKeptCell(true);
  EXPECT_TRUE(bakeAsset(two, settings)) << "exactly the kept cells' bytes with their slots must fit";
}

}  // namespace
}  // namespace hsdf
