// Compressed and quantized glTF files (tests/data/gltf/bunny_small_*.glb, see its README) bake the
// same distance field as their plain original, through the module's own source preparation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "engine/scene/gltf/gltf_loader.h"
#include "hermite_sdf/core/bake_job.h"

namespace hsdf {
namespace {

const std::string kGltfDir = std::string(HSDF_TEST_DATA_DIR) + "/gltf/";

std::vector<glm::vec3> worldVertices(const std::string& file) {
  const auto scene = engine::scene::loadGltf(kGltfDir + file);
  EXPECT_TRUE(scene.ok()) << scene.error().message;
  return scene.ok() ? engine::scene::flattenTriangles(*scene).positions : std::vector<glm::vec3>{};
}

// How far the encoding moved the vertices: the largest distance from a decoded vertex to the
// nearest plain one (the loader tests prove that nearest vertex is its original).
double largestVertexShift(const std::vector<glm::vec3>& plain, const std::vector<glm::vec3>& packed) {
  double worst = 0.0;
  for (const auto& q : packed) {
    double best = INFINITY;
    for (const auto& p : plain) best = std::min(best, double(glm::distance(p, q)));
    worst = std::max(worst, best);
  }
  return worst;
}

engine::Expected<PreparedSource> prepare(const std::string& file) {
  ENGINE_TRY_ASSIGN(const BakeSource source, BakeSource::fromPathOrShape(kGltfDir + file));
  return prepareSource(source, BakeSettings{});
}

class CompressedBunnyBake : public ::testing::TestWithParam<const char*> {};

// Tricky because a bake only looks at triangles: it would hide a loader that decodes the right
// vertices but the wrong node transform (the meshopt and quantized files need their node's scale
// and translation) or that mis-signs the field (flipped winding). Both files are baked on the SAME
// grid (fitted to the plain mesh), and every sample must agree within the bound the vertex shift
// allows: moving each vertex by at most d moves every point of every triangle by at most d, so the
// distance changes by at most d, and twice that where the sign may flip (|f| <= d). Rounding to
// float adds 1e-5 of the grid's extent at most.
TEST_P(CompressedBunnyBake, BakesThePlainField) {
  auto plain = prepare("bunny_small.glb");
  auto packed = prepare(GetParam());
  ASSERT_TRUE(plain.ok()) << plain.error().message;
  ASSERT_TRUE(packed.ok()) << packed.error().message;
  const double shift = largestVertexShift(worldVertices("bunny_small.glb"), worldVertices(GetParam()));
  ASSERT_GT(shift, 0.0);  // quantized: not bit-identical, so the comparison below is not trivial

  const auto grid = fitGrid(plain->source->bounds(), 24, 1);
  ASSERT_TRUE(grid.ok()) << grid.error().message;
  const auto plainField = bakeHermiteField(*plain->source, *grid);
  const auto packedField = bakeHermiteField(*packed->source, *grid);
  ASSERT_TRUE(plainField.ok() && packedField.ok());

  const double extent = grid->spacing * double(grid->resolution - 1);
  const double bound = 2.0 * shift + 1e-5 * extent;
  double worst = 0.0;
  int insidePlain = 0, insidePacked = 0;
  for (std::size_t s = 0; s < plainField->samples.size(); ++s) {
    const double a = plainField->samples[s].f, b = packedField->samples[s].f;
    worst = std::max(worst, std::abs(a - b));
    insidePlain += a < 0.0;
    insidePacked += b < 0.0;
  }
  EXPECT_LE(worst, bound) << GetParam();
  EXPECT_GT(insidePlain, 100);  // the bunny encloses volume at K = 24
  EXPECT_NEAR(insidePacked, insidePlain, insidePlain / 50);
  std::printf("%s: vertex shift %.3g, largest field difference %.3g (bound %.3g, grid spacing %.3g)\n", GetParam(), shift,
              worst, bound, grid->spacing);
}

INSTANTIATE_TEST_SUITE_P(GltfFiles, CompressedBunnyBake,
                         ::testing::Values("bunny_small_draco.glb", "bunny_small_meshopt.glb", "bunny_small_quantized.glb"));

}  // namespace
}  // namespace hsdf
