// The mesh source on its own: building it, and single-threaded queries in grid order (the access
// pattern of a bake), per point and per row.
#include <vector>

#include <benchmark/benchmark.h>

#include "bench_common.h"

namespace hsdf::bench {
namespace {

void BM_MeshSourceBuildBunny(benchmark::State& state) {
  const engine::scene::TriangleSoup& soup = bunnySoup();
  for (auto _ : state) {
    auto source = MeshSource::create(soup);
    require(source.ok(), "build failed");
    benchmark::DoNotOptimize(source.value().get());
  }
  state.counters["triangles"] = double(soup.indices.size() / 3);
}
BENCHMARK(BM_MeshSourceBuildBunny)->Unit(benchmark::kMillisecond);

// Every `stride`-th z slab of the grid, so a benchmark iteration stays short at high K while
// still covering the whole height of the model.
constexpr int kSlabStride = 8;

void BM_MeshSamplePerPointBunny(benchmark::State& state) {
  const GridSpec grid = bunnyGrid(int(state.range(0)));
  const MeshSource& source = bunnySource();
  std::int64_t samples = 0;
  for (auto _ : state) {
    for (int k = 0; k < grid.resolution; k += kSlabStride)
      for (int j = 0; j < grid.resolution; ++j)
        for (int i = 0; i < grid.resolution; ++i) benchmark::DoNotOptimize(source.sample(grid.samplePosition(i, j, k)));
    samples += std::int64_t(grid.resolution) * grid.resolution * ((grid.resolution + kSlabStride - 1) / kSlabStride);
  }
  state.SetItemsProcessed(samples);
}
BENCHMARK(BM_MeshSamplePerPointBunny)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);

void BM_MeshSampleRowBunny(benchmark::State& state) {
  const GridSpec grid = bunnyGrid(int(state.range(0)));
  const MeshSource& source = bunnySource();
  std::vector<SdfSample> row(std::size_t(grid.resolution));
  std::int64_t samples = 0;
  for (auto _ : state) {
    for (int k = 0; k < grid.resolution; k += kSlabStride)
      for (int j = 0; j < grid.resolution; ++j) {
        source.sampleRow(grid.samplePosition(0, j, k), {grid.spacing, 0.0, 0.0}, row);
        benchmark::DoNotOptimize(row.data());
      }
    samples += std::int64_t(grid.resolution) * grid.resolution * ((grid.resolution + kSlabStride - 1) / kSlabStride);
  }
  state.SetItemsProcessed(samples);
}
BENCHMARK(BM_MeshSampleRowBunny)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);

// The winding number alone, at every point (what a sign costs without reuse).
void BM_MeshWindingNumberBunny(benchmark::State& state) {
  const GridSpec grid = bunnyGrid(64);
  const MeshSource& source = bunnySource();
  std::int64_t samples = 0;
  for (auto _ : state) {
    for (int k = 0; k < grid.resolution; k += kSlabStride)
      for (int j = 0; j < grid.resolution; ++j)
        for (int i = 0; i < grid.resolution; ++i)
          benchmark::DoNotOptimize(source.windingNumber(grid.samplePosition(i, j, k)));
    samples += std::int64_t(grid.resolution) * grid.resolution * ((grid.resolution + kSlabStride - 1) / kSlabStride);
  }
  state.SetItemsProcessed(samples);
}
BENCHMARK(BM_MeshWindingNumberBunny)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hsdf::bench
