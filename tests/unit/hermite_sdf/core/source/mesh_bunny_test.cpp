// MeshSource on the real asset: the Stanford bunny imported through the glTF loader.
#include <random>

#include <gtest/gtest.h>

#include "engine/scene/gltf/gltf_loader.h"
#include "hermite_sdf/core/mesh_source.h"
#include "mesh_test_meshes.h"

namespace hsdf {
namespace {

struct Bunny {
  engine::scene::TriangleSoup soup;
  std::unique_ptr<MeshSource> source;
};

Bunny loadBunny() {
  auto scene = engine::scene::loadGltf(std::string(HSDF_ASSET_DIR) + "/bunny.glb");
  EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().message);
  Bunny bunny;
  bunny.soup = engine::scene::flattenTriangles(*scene);
  auto source = MeshSource::create(bunny.soup);
  EXPECT_TRUE(source.ok()) << (source.ok() ? "" : source.error().message);
  bunny.source = std::move(source.value());
  return bunny;
}

// Tricky: the asset goes through import (possibly split vertices, node transforms) before it
// reaches the source; the bunny is documented as watertight, so it must come out closed with all
// 3674 triangles, which is what makes sign reuse exact for it.
TEST(MeshBunny, ImportsClosedWithAllTriangles) {
  const Bunny bunny = loadBunny();
  EXPECT_EQ(bunny.source->stats().triangles, 3674u);
  EXPECT_EQ(bunny.source->stats().droppedZeroArea, 0u);
  EXPECT_TRUE(bunny.source->stats().closed);
  EXPECT_FALSE(bunny.source->stats().selfIntersecting);
  EXPECT_TRUE(bunny.source->stats().pseudoNormalSign);
}

// Tricky: a scanned model has thin parts (ears), concavities and a medial axis everywhere; the
// fast distance and the fast sign must match brute force and the exact winding number.
TEST(MeshBunny, DistanceAndSignMatchBruteForce) {
  const Bunny bunny = loadBunny();
  testing::TestMesh mesh{bunny.soup.positions, bunny.soup.indices};
  const Aabb box = bunny.source->bounds();
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(-0.1, 1.1);
  int inside = 0;
  for (int i = 0; i < 150; ++i) {
    const glm::dvec3 p = box.min + glm::dvec3(u(rng), u(rng), u(rng)) * box.size();
    const SdfSample s = bunny.source->sample(p);
    EXPECT_NEAR(std::abs(s.value), testing::bruteForceDistance(mesh, p), 1e-9);
    EXPECT_EQ(s.value < 0.0, bunny.source->windingNumberExact(p) >= 0.5);
    inside += s.value < 0.0;
  }
  EXPECT_GT(inside, 10);
}

}  // namespace
}  // namespace hsdf
