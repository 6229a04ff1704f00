// Baking the bunny: dense Hermite fields (what the sphere-tracing baselines need), the narrow
// band, and the sparse bake (what the cell path needs). Targets (2-core machine): dense K=128 under 2 s; narrow band
// no slower than OpenVDB's meshToSignedDistanceField (openvdb_bench.cpp) on the same grid.
#include <thread>

#include <benchmark/benchmark.h>

#include "bench_common.h"
#include "hermite_sdf/core/sparse_bake.h"

namespace hsdf::bench {
namespace {

void reportSamples(benchmark::State& state, const GridSpec& grid) {
  const double samples = double(grid.sampleCount());
  state.counters["samples"] = samples;
  state.counters["samples_per_s"] = benchmark::Counter(samples, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["threads"] = double(std::thread::hardware_concurrency());
}

void BM_BakeDenseBunny(benchmark::State& state) {
  const GridSpec grid = bunnyGrid(int(state.range(0)));
  const MeshSource& source = bunnySource();
  for (auto _ : state) {
    auto field = bakeHermiteField(source, grid);
    require(field.ok(), field.ok() ? "" : field.error().message);
    benchmark::DoNotOptimize(field->samples.data());
  }
  reportSamples(state, grid);
}
BENCHMARK(BM_BakeDenseBunny)->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_BakeNarrowBandBunny(benchmark::State& state) {
  const GridSpec grid = bunnyGrid(int(state.range(0)));
  const MeshSource& source = bunnySource();
  for (auto _ : state) {
    auto field = bakeHermiteFieldNarrowBand(source, grid);
    require(field.ok(), field.ok() ? "" : field.error().message);
    benchmark::DoNotOptimize(field->samples.data());
  }
  reportSamples(state, grid);
}
BENCHMARK(BM_BakeNarrowBandBunny)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();

// The cells straight from the mesh (bakeCellsSparse): the cell path of hsdf_bake --cells, with the
// classification included (the lines above stop at the field). Compare with OpenVDB at the same K.
void BM_BakeSparseBunny(benchmark::State& state) {
  const GridSpec grid = bunnyGrid(int(state.range(0)));
  const MeshSource& source = bunnySource();
  std::uint64_t kept = 0, queries = 0;
  for (auto _ : state) {
    auto cells = bakeCellsSparse(source, grid);
    require(cells.ok(), cells.ok() ? "" : cells.error().message);
    kept = cells->stats.kept();
    queries = cells->sampleQueries + cells->brickProbes;
    benchmark::DoNotOptimize(cells->cells.records.data());
  }
  state.counters["kept_cells"] = double(kept);
  state.counters["source_queries"] = double(queries);
  state.counters["threads"] = double(std::thread::hardware_concurrency());
}
BENCHMARK(BM_BakeSparseBunny)->Arg(64)->Arg(128)->Arg(256)->Arg(512)->Arg(1024)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace hsdf::bench
