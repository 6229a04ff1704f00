// Tricubic Ferguson-Hermite evaluations per second on one core (value, value + exact gradient,
// Bernstein conversion), float and double, over random cells and points.
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "hermite_sdf/core/hermite.h"

namespace hsdf::bench {
namespace {

constexpr int kCells = 256;
constexpr int kPoints = 1024;

template <class T>
struct RandomCells {
  std::vector<HermiteCellCorners<T>> cells;
  std::vector<Vec3<T>> points;
  RandomCells() {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0), t(0.0, 1.0);
    cells.resize(kCells);
    for (auto& cell : cells)
      for (auto& c : cell) c = {T(u(rng)), T(u(rng)), T(u(rng)), T(u(rng))};
    points.resize(kPoints);
    for (auto& p : points) p = Vec3<T>(T(t(rng)), T(t(rng)), T(t(rng)));
  }
};

template <class T>
void BM_HermiteValue(benchmark::State& state) {
  const RandomCells<T> data;
  std::size_t n = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(hermiteValue(data.cells[n % kCells], T(0.1), data.points[n % kPoints]));
    ++n;
  }
  state.SetItemsProcessed(std::int64_t(n));
}
BENCHMARK(BM_HermiteValue<float>);
BENCHMARK(BM_HermiteValue<double>);

template <class T>
void BM_HermiteValueGradient(benchmark::State& state) {
  const RandomCells<T> data;
  std::size_t n = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(hermiteValueGradient(data.cells[n % kCells], T(0.1), data.points[n % kPoints]));
    ++n;
  }
  state.SetItemsProcessed(std::int64_t(n));
}
BENCHMARK(BM_HermiteValueGradient<float>);
BENCHMARK(BM_HermiteValueGradient<double>);

template <class T>
void BM_ToBernstein(benchmark::State& state) {
  const RandomCells<T> data;
  std::size_t n = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(toBernstein(data.cells[n % kCells], T(0.1)));
    ++n;
  }
  state.SetItemsProcessed(std::int64_t(n));
}
BENCHMARK(BM_ToBernstein<double>);

}  // namespace
}  // namespace hsdf::bench
