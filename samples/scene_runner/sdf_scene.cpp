#include "sdf_scene.h"

#include <chrono>
#include <cstdio>

#include <fmt/format.h>

#include "engine/core/log.h"
#include "engine/scene/gltf_loader.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/bake_job.h"
#include "hermite_sdf/hsdf_file.h"

namespace runner {

using namespace engine;

Expected<std::shared_ptr<const hsdf::SdfAsset>> bakeSceneSdf(const scene::SceneData& data, int resolution, int padding) {
  ENGINE_TRY_ASSIGN(hsdf::BakeSource source, hsdf::BakeSource::fromScene("scene sdf", data));
  hsdf::BakeSettings settings;
  settings.resolution = resolution;
  settings.padding = padding;
  const auto start = std::chrono::steady_clock::now();
  int lastPercent = -1;
  hsdf::BakeControl control;
  control.progress = [&lastPercent](float fraction) {
    const int percent = int(fraction * 100.0f);
    if (percent / 10 != lastPercent / 10) {
      std::fprintf(stderr, "\rbaking %3d%%", percent);
      lastPercent = percent;
    }
    return true;
  };
  auto asset = hsdf::bakeAsset(source, settings, control);
  std::fprintf(stderr, "\r");
  if (!asset) return asset.error();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const hsdf::CellStats& stats = (*asset)->classification.stats;
  log::info("baked {}^3 Hermite field in {:.2f} s: {} kept cells ({} crossing, {} ambiguous), {} stored scalars",
            resolution, seconds, stats.kept(), stats.crossing, stats.ambiguous, (*asset)->cells.stored_scalars());
  return asset;
}

Expected<std::shared_ptr<const hsdf::SdfAsset>> loadSdfFile(const std::filesystem::path& path) {
  const auto contents = hsdf::loadHsdf(path);
  if (!contents) return contents.error();
  const std::string name = path.filename().string();
  // Copies, not moves, out of the optionals: GCC 12 -O3 warns (falsely) about moved-from ones.
  if (contents->dense) return hsdf::makeSdfAsset(name, *contents->dense, contents->grid.bounds());
  if (contents->cells) return hsdf::makeSdfAssetFromCells(name, *contents->cells);
  return makeError(path.string() + ": holds neither a dense field nor cells");
}

hsdf::HermiteSdfRenderable renderableFromOptions(const Options& options, std::shared_ptr<const hsdf::SdfAsset> asset) {
  hsdf::HermiteSdfRenderable renderable;
  renderable.asset = std::move(asset);
  if (options.method == "trilinear") renderable.method = hsdf::RenderMethod::TrilinearSphereTrace;
  if (options.method == "hermite") renderable.method = hsdf::RenderMethod::HermiteSphereTrace;
  renderable.subdivisions = options.subdivisions;
  renderable.refineSteps = options.refine;
  renderable.normals = options.normals == "central" ? hsdf::NormalMode::CentralDifferences : hsdf::NormalMode::Exact;
  renderable.halfPrecision = options.fp16;
  return renderable;
}

ecs::Entity addSdfEntity(ecs::Registry& registry, const hsdf::HermiteSdfRenderable& renderable, const glm::vec3& offset) {
  const ecs::Entity entity = registry.create();
  scene::Transform transform;
  transform.translation = offset;
  registry.emplace<scene::Transform>(entity, transform);
  registry.emplace<hsdf::HermiteSdfRenderable>(entity, renderable);
  registry.emplace<scene::Name>(entity, scene::Name{renderable.asset ? renderable.asset->name : "sdf"});
  return entity;
}

}  // namespace runner
