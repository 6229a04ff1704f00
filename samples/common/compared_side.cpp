#include "compared_side.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "engine/core/log.h"
#include "engine/render/components.h"
#include "sdf_stats.h"

namespace samples {

using namespace engine;

void ComparedSide::createOverlay(const gpu::Context& context, std::uint32_t framesInFlight) {
  overlay_ = std::make_unique<ImageOverlay>(context, framesInFlight);
}

void ComparedSide::release() {
  job_.reset();
  overlay_.reset();
}

// The main asset at the same key (K, padding, shell) is the same field: it is shared, not baked twice.
void ComparedSide::updateBake(const TuningState& tuning, const hsdf::BakeSource* source, const MainField& main,
                              const hsdf::BakeBudget& budget) {
  if (!comparing(tuning) || drawsCells(tuning.compareMethod) || !source) return;
  const BakeKey wanted = bakeKey(compareTuning(tuning));
  const bool have = asset_ && key_ == wanted;
  const bool baking = job_ && bakeKey(job_->settings()) == wanted;
  if (baking || (have && !job_)) return;
  job_.reset();  // cancels a bake for a K no longer asked for
  if (have || failed_ == wanted) return;
  // Shared when it has the dense field the compared tracer needs (a sparse cell bake has none).
  if (main.asset && !main.asset->field.samples.empty() && wanted == main.key) {
    asset_ = main.asset;
    key_ = wanted;
    return;
  }
  hsdf::BakeSettings settings;
  setBakeKey(wanted, settings);
  settings.budget = budget;
  bakeError_.clear();
  job_ = std::make_unique<hsdf::BakeJob>(*source, settings);
}

void ComparedSide::finishBake() {
  hsdf::BakeJob::Result result = job_->wait();
  const hsdf::BakeSettings settings = job_->settings();
  job_.reset();
  if (!result) {
    bakeError_ = result.error().withContext(fmt::format("baking the compared side at resolution {}", settings.resolution)).message;
    failed_ = bakeKey(settings);
    log::warn("{}", bakeError_);
    return;
  }
  log::info("compared side baked at resolution {}: {}", settings.resolution, describeSdfStats(sdfStats(**result)));
  asset_ = std::move(*result);
  key_ = bakeKey(settings);
}

void ComparedSide::cancelBake() {
  if (job_) job_->cancel();
}

int ComparedSide::resolutionDrawn(const TuningState& tuning, int mainResolution) const {
  if (drawsCells(tuning.compareMethod) || !asset_) return mainResolution;
  return key_.resolution;
}

// Its own bake, or the main asset (a compared method of cells, a .hsdf file, or while the first
// compared bake runs).
std::shared_ptr<const hsdf::SdfAsset> ComparedSide::asset(const TuningState& tuning,
                                                          const std::shared_ptr<const hsdf::SdfAsset>& main) const {
  if (drawsCells(tuning.compareMethod) || !asset_) return main;
  return asset_;
}

std::vector<render::ViewRegion> ComparedSide::splitRegions(const TuningState& tuning, VkExtent2D e,
                                                           const std::shared_ptr<const hsdf::SdfAsset>& main,
                                                           const std::shared_ptr<const hsdf::SdfAsset>& baked) const {
  const bool vertical = tuning.split == SplitMode::Vertical;
  const auto divider = std::uint32_t(std::lround(double(tuning.splitPosition) * (vertical ? e.width : e.height)));
  VkRect2D first{{0, 0}, e}, second{{0, 0}, e};
  if (vertical) {
    first.extent.width = divider;
    second.offset.x = std::int32_t(divider);
    second.extent.width = e.width - divider;
  } else {
    first.extent.height = divider;
    second.offset.y = std::int32_t(divider);
    second.extent.height = e.height - divider;
  }
  const TuningState compared = compareTuning(tuning);
  const std::shared_ptr<const hsdf::SdfAsset> other = asset(tuning, baked);
  return {{first, [show = showState_, tuning, main] { show(tuning, main); }},
          {second, [show = showState_, compared, other] { show(compared, other); }}};
}

// One frame of the normals view with `tuning` and `asset`, read back.
NormalsFrame ComparedSide::renderNormals(const TuningState& tuning, const std::shared_ptr<const hsdf::SdfAsset>& asset,
                                         ecs::Registry& registry, render::Renderer& renderer,
                                         const render::CameraView& camera) {
  showState_(tuning, asset);
  render::FrameSettings settings;
  settings.debugView = DEBUG_VIEW_NORMALS;
  renderer.renderFrame(registry, camera, settings);
  NormalsFrame frame;
  frame.rgba = renderer.readbackColor();
  frame.visibility = renderer.readbackVisibility();
  return frame;
}

// Meshes and the ground would count as covered by both sides: they are out of the normals frames.
// Needs an SDF method on the main side (then the scene's meshes are already hidden, see
// Viewer::updateVisibility).
Status ComparedSide::renderDifference(const TuningState& tuning, const std::shared_ptr<const hsdf::SdfAsset>& main,
                                      const std::shared_ptr<const hsdf::SdfAsset>& baked, ecs::Registry& registry,
                                      render::Renderer& renderer, const render::CameraView& camera) {
  std::vector<std::pair<ecs::Entity, render::MeshRenderable>> meshes;
  registry.view<render::MeshRenderable>().each(
      [&meshes](ecs::Entity entity, const render::MeshRenderable& mesh) { meshes.emplace_back(entity, mesh); });
  for (const auto& entry : meshes) registry.remove<render::MeshRenderable>(entry.first);
  const NormalsFrame a = renderNormals(tuning, main, registry, renderer, camera);
  const NormalsFrame b = renderNormals(compareTuning(tuning), asset(tuning, baked), registry, renderer, camera);
  for (const auto& [entity, mesh] : meshes) registry.emplace<render::MeshRenderable>(entity, mesh);
  showState_(tuning, main);
  const VkExtent2D extent = renderer.extent();
  ENGINE_TRY_ASSIGN(NormalDifference d, compareNormals(a, b, extent.width, extent.height));
  overlay_->setImage(heatMapImage(d, range_), extent.width, extent.height);
  difference_ = std::move(d);
  return {};
}

render::OverlayPass* ComparedSide::overlay(render::OverlayPass* next) {
  overlay_->setNext(next);
  return overlay_.get();
}

}  // namespace samples
