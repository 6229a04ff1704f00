// OpenVDB's meshToSignedDistanceField on the bunny with a 3-voxel band (exterior and interior) on
// exactly our grid (voxel size h, voxel (i,j,k) at origin + h*(i,j,k)), for side-by-side
// comparison with BM_BakeNarrowBandBunny in the same run. Built only with HSDF_WITH_OPENVDB.
#include <vector>

#include <benchmark/benchmark.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include "bench_common.h"

namespace hsdf::bench {
namespace {

constexpr float kBandVoxels = 3.0f;

void BM_OpenVdbNarrowBandBunny(benchmark::State& state) {
  openvdb::initialize();
  const GridSpec grid = bunnyGrid(int(state.range(0)));
  const engine::scene::TriangleSoup& soup = bunnySoup();
  openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(grid.spacing);
  transform->postTranslate(openvdb::Vec3d(grid.origin.x, grid.origin.y, grid.origin.z));
  // Points stay in world space; the transform puts the voxels on our sample positions.
  std::vector<openvdb::Vec3s> points;
  points.reserve(soup.positions.size());
  for (const glm::vec3& p : soup.positions) points.emplace_back(p.x, p.y, p.z);
  std::vector<openvdb::Vec3I> triangles;
  triangles.reserve(soup.indices.size() / 3);
  for (std::size_t t = 0; t + 2 < soup.indices.size(); t += 3)
    triangles.emplace_back(soup.indices[t], soup.indices[t + 1], soup.indices[t + 2]);
  const std::vector<openvdb::Vec4I> quads;
  std::size_t voxels = 0;
  for (auto _ : state) {
    openvdb::FloatGrid::Ptr sdf = openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(
        *transform, points, triangles, quads, kBandVoxels, kBandVoxels);
    voxels = sdf->activeVoxelCount();
    benchmark::DoNotOptimize(sdf.get());
  }
  state.counters["active_voxels"] = double(voxels);
}
BENCHMARK(BM_OpenVdbNarrowBandBunny)->Arg(64)->Arg(128)->Arg(256)->Arg(512)->Arg(1024)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace hsdf::bench
