// CPU reference ray caster (hsdf::renderReference): 256x256 images of the bunny at K = 64 and 128
// and of the torus at K = 16, from the scene runner's first orbit view (engine::platform::
// framingOrbit), fields fitted as the GPU tests fit them (fitGrid(bounds, K, 1), default bake).
// The GPU tests spend most of their time here, and the perf capture's image metrics need it at
// larger K and image sizes.
#include <memory>

#include <benchmark/benchmark.h>

#include "bench_common.h"
#include "engine/core/math.h"
#include "engine/platform/camera_controller.h"
#include "hermite_sdf/core/analytic.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/core/reference.h"

namespace hsdf::bench {
namespace {

constexpr int kImageSide = 256;
constexpr float kFovY = 0.8f;  // the scene runner's

struct Camera {
  glm::mat4 view, proj;
};

// The scene runner's default camera for an object with these surface bounds (view 0 of 8).
Camera orbitCamera(const Aabb& bounds) {
  const glm::vec3 lo(bounds.min), hi(bounds.max);
  const engine::platform::OrbitController orbit = engine::platform::framingOrbit(lo, hi, kFovY, 0);
  const float znear = 0.01f * glm::length(hi - lo);
  return {engine::math::lookAt(orbit.eye(), orbit.target, {0.0f, 1.0f, 0.0f}),
          engine::math::perspectiveReverseZInfinite(kFovY, 1.0f, znear)};
}

const SdfSource& torusSource() {
  static const std::unique_ptr<SdfSource> torus = [] {
    auto source = makeAnalyticSource("torus");
    require(source.ok(), source.ok() ? "" : source.error().message);
    return std::move(source.value());
  }();
  return *torus;
}

// The torus at K = 16, as hermite_cells_gpu_tests bakes it.
const HermiteField& torusField16() {
  static const HermiteField field = [] {
    auto grid = fitGrid(torusSource().bounds(), 16, kDefaultPaddingCells);
    require(grid.ok(), grid.ok() ? "" : grid.error().message);
    auto baked = bakeHermiteField(torusSource(), *grid);
    require(baked.ok(), baked.ok() ? "" : baked.error().message);
    return std::move(*baked);
  }();
  return field;
}

// Renders the reference image in every iteration; counts rays per second and hit pixels.
void renderLoop(benchmark::State& state, const HermiteField& field, const Aabb& bounds,
                const CellClassification* cells) {
  const Camera camera = orbitCamera(bounds);
  std::int64_t hits = 0;
  for (auto _ : state) {
    auto image = renderReference(field, camera.view, camera.proj, {kImageSide, kImageSide}, cells);
    require(image.ok(), image.ok() ? "" : image.error().message);
    hits = 0;
    for (std::uint8_t h : image->hit) hits += h;
    benchmark::DoNotOptimize(image->depth.data());
  }
  state.counters["hit_pixels"] = double(hits);
  state.counters["rays_per_s"] =
      benchmark::Counter(double(kImageSide) * kImageSide, benchmark::Counter::kIsIterationInvariantRate);
}

// All cells: what hermite_cells_gpu_tests asks for.
void BM_ReferenceBunny(benchmark::State& state) {
  renderLoop(state, bunnyField(int(state.range(0))), bunnySource().bounds(), nullptr);
}
BENCHMARK(BM_ReferenceBunny)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();

// Kept cells only: what hermite_sphere_trace_gpu_tests asks for.
void BM_ReferenceBunnyKeptCells(benchmark::State& state) {
  const HermiteField& field = bunnyField(int(state.range(0)));
  auto cells = classifyCells(field);
  require(cells.ok(), cells.ok() ? "" : cells.error().message);
  renderLoop(state, field, bunnySource().bounds(), &*cells);
}
BENCHMARK(BM_ReferenceBunnyKeptCells)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ReferenceTorus16(benchmark::State& state) {
  renderLoop(state, torusField16(), torusSource().bounds(), nullptr);
}
BENCHMARK(BM_ReferenceTorus16)->Unit(benchmark::kMillisecond)->UseRealTime();

// The trilinear interpolant of the same samples (the sphere-tracing baseline's reference).
void BM_ReferenceTrilinearBunny(benchmark::State& state) {
  const HermiteField& hermite = bunnyField(int(state.range(0)));
  TrilinearField field;
  field.grid = hermite.grid;
  for (const HermiteSample& s : hermite.samples) field.values.push_back(s.f);
  const Camera camera = orbitCamera(bunnySource().bounds());
  for (auto _ : state) {
    auto image = renderReference(field, camera.view, camera.proj, {kImageSide, kImageSide});
    require(image.ok(), image.ok() ? "" : image.error().message);
    benchmark::DoNotOptimize(image->depth.data());
  }
  state.counters["rays_per_s"] =
      benchmark::Counter(double(kImageSide) * kImageSide, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_ReferenceTrilinearBunny)->Arg(64)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace hsdf::bench
