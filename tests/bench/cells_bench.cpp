// Classification and extraction of the bunny's cells from a dense field (target at K=128: < 0.1 s).
#include <benchmark/benchmark.h>

#include "bench_common.h"
#include "hermite_sdf/core/cells.h"

namespace hsdf::bench {
namespace {

void BM_ClassifyAndExtractBunny(benchmark::State& state) {
  const HermiteField& field = bunnyField(int(state.range(0)));
  std::uint64_t kept = 0;
  for (auto _ : state) {
    auto classes = classifyCells(field);
    require(classes.ok(), classes.ok() ? "" : classes.error().message);
    auto stream = extractCells(field, *classes);
    require(stream.ok(), stream.ok() ? "" : stream.error().message);
    kept = stream->records.size();
    benchmark::DoNotOptimize(stream->records.data());
  }
  const double cells = double(field.grid.cellsPerAxis()) * field.grid.cellsPerAxis() * field.grid.cellsPerAxis();
  state.counters["kept_cells"] = double(kept);
  state.counters["cells_per_s"] = benchmark::Counter(cells, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_ClassifyAndExtractBunny)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ClassifyOnlyBunny(benchmark::State& state) {
  const HermiteField& field = bunnyField(int(state.range(0)));
  for (auto _ : state) {
    auto classes = classifyCells(field);
    require(classes.ok(), classes.ok() ? "" : classes.error().message);
    benchmark::DoNotOptimize(classes->classes.data());
  }
}
BENCHMARK(BM_ClassifyOnlyBunny)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace hsdf::bench
