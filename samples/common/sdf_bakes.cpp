#include "sdf_bakes.h"

#include <algorithm>
#include <utility>

#include <fmt/format.h>

#include "engine/core/log.h"
#include "engine/render/renderer.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/render/lod.h"
#include "hermite_sdf/render/sphere_trace_feature.h"
#include "sdf_stats.h"

namespace samples {

using namespace engine;

void SdfBakes::add(std::shared_ptr<const hsdf::SdfAsset> asset, const glm::vec3& offset) {
  hsdf::HermiteSdfRenderable renderable;
  renderable.asset = std::move(asset);
  if (color_) renderable.color = *color_;
  applyTuning(tuning_, renderable);
  const ecs::Entity entity = registry_.create();
  scene::Transform transform;
  transform.translation = offset;
  registry_.emplace<scene::Transform>(entity, transform);
  registry_.emplace<scene::Name>(entity, scene::Name{renderable.asset->name});
  registry_.emplace<hsdf::HermiteSdfRenderable>(entity, std::move(renderable));
  entity_ = entity;
}

hsdf::BakeSettings SdfBakes::settings() const {
  hsdf::BakeSettings settings;
  setBakeKey(bakeKey(tuning_), settings);
  settings.band = bakeBandFor(tuning_.method, tuning_.resolution);
  settings.budget = budget_;
  return settings;
}

hsdf::HermiteSdfRenderable* SdfBakes::renderable() {
  if (hidden_) return &*hidden_;
  if (!entity_) return nullptr;
  return &registry_.get<hsdf::HermiteSdfRenderable>(*entity_);
}

const hsdf::SdfAsset* SdfBakes::asset() const {
  if (hidden_) return hidden_->asset.get();
  if (!entity_) return nullptr;
  return registry_.get<hsdf::HermiteSdfRenderable>(*entity_).asset.get();
}

std::shared_ptr<const hsdf::SdfAsset> SdfBakes::bakedAsset() {
  const hsdf::HermiteSdfRenderable* r = renderable();
  const hsdf::HermiteSdfLod* lod = entity_ ? registry_.tryGet<hsdf::HermiteSdfLod>(*entity_) : nullptr;
  return lod && !lod->levels.empty() ? lod->levels.front() : r ? r->asset : nullptr;
}

void SdfBakes::setShown(bool shown) {
  if (!entity_ || shown != hidden_.has_value()) return;
  if (shown) {
    registry_.emplace<hsdf::HermiteSdfRenderable>(*entity_, std::move(*hidden_));
    hidden_.reset();
  } else {
    hidden_ = registry_.get<hsdf::HermiteSdfRenderable>(*entity_);
    registry_.remove<hsdf::HermiteSdfRenderable>(*entity_);
  }
}

void SdfBakes::followTuning() {
  if (!source_ || (!entity_ && !isSdfMethod(tuning_.method) && !comparing(tuning_))) return;
  if (!entity_) {
    if (!job_) start();
    return;
  }
  // Compared with what is being baked, else with what is drawn.
  const BakeKey current = job_ ? bakeKey(job_->settings()) : baked_;
  // A sparse bake (the cells past K = 256) has no dense field: a dense tracer needs a re-bake.
  const hsdf::SdfAsset* drawn = asset();
  const bool sparse = job_ ? job_->settings().band == hsdf::BakeBand::Sparse : drawn && drawn->field.samples.empty();
  const bool needsDense = needsDenseField(tuning_.method);
  if (bakeKey(tuning_) != current || (sparse && needsDense)) start();
}

void SdfBakes::start() {
  error_.clear();
  job_.reset();  // cancels a re-bake for settings that are already outdated
  job_ = std::make_unique<hsdf::BakeJob>(*source_, settings());
}

// The panel's cancel stands beside the bake it names: the re-bake at a new K when there is one (the
// levels of the field drawn go on baking), else the level of detail being baked.
void SdfBakes::cancel() {
  if (job_) job_->cancel();
  else if (levelJob_) levelJob_->cancel();
}

void SdfBakes::stop() {
  job_.reset();
  levelJob_.reset();
}

// A failed re-bake leaves the old asset and puts the tuning back to the K drawn (or to the meshes,
// when there is no SDF yet), so that the panel shows what is on screen.
Status SdfBakes::finish() {
  hsdf::BakeJob::Result result = job_->wait();
  const hsdf::BakeSettings settings = job_->settings();
  job_.reset();
  if (!result) {
    const Error error = result.error().withContext(fmt::format("re-baking at resolution {}", settings.resolution));
    error_ = error.message;
    if (entity_) {
      setBakeKey(baked_, tuning_);
    } else {
      tuning_.method = Method::Mesh;
    }
    return error;
  }
  log::info("re-baked at resolution {}: {}", settings.resolution, describeSdfStats(sdfStats(**result)));
  if (entity_) {
    hsdf::HermiteSdfRenderable& sdf = *renderable();
    // With levels of detail the renderable holds the level drawn; the bake replaced level 0.
    replaced_ = {bakedAsset(), baked_};
    sdf.asset = std::move(*result);
  } else {
    add(std::move(*result), origin_);
  }
  setBaked(bakeKey(settings));
  return {};
}

// Levels of detail (TuningState::lod): the entity carries an hsdf::HermiteSdfLod whose level 0 is
// the asset baked at K. A renderable holding none of the levels has a new bake (re-bake, refused
// bake put back): its coarser levels are baked then, from the same source, with its band, one
// hsdf::BakeJob per level on a worker thread (finer first), so that the frame never waits for them;
// the module's system picks among the levels ready so far, from the camera of this frame. Off: the
// entity draws level 0 again. A failed level turns levels off; a cancelled one keeps the levels
// baked so far (off and on again bakes the rest).
bool SdfBakes::updateLevels(bool wait) {
  hsdf::HermiteSdfRenderable* drawn = renderable();
  if (!drawn) return false;
  hsdf::HermiteSdfLod* lod = registry_.tryGet<hsdf::HermiteSdfLod>(*entity_);
  const bool holdsLevel = lod && std::find(lod->levels.begin(), lod->levels.end(), drawn->asset) != lod->levels.end();
  if (!tuning_.lod || !source_) {
    levelJob_.reset();
    // A level goes back to level 0; a new bake in the renderable stays.
    if (holdsLevel) drawn->asset = lod->levels.front();
    if (lod) registry_.remove<hsdf::HermiteSdfLod>(*entity_);
    return false;
  }
  if (!holdsLevel) startLevels(drawn->asset);
  if (Status baked = finishLevels(wait); !baked) {
    error_ = baked.error().message;
    log::warn("{} (levels of detail turned off)", error_);
    tuning_.lod = false;
    return false;
  }
  registry_.get<hsdf::HermiteSdfLod>(*entity_).pixelsPerCell = tuning_.lodPixelsPerCell;
  return true;
}

// New levels with `finest` (baked as baked_) as level 0, the coarser ones to come.
void SdfBakes::startLevels(std::shared_ptr<const hsdf::SdfAsset> finest) {
  levelJob_.reset();  // a level of the old level 0 is outdated
  hsdf::BakeSettings settings;
  setBakeKey(baked_, settings);
  settings.band = finest->field.samples.empty() ? hsdf::BakeBand::Sparse : hsdf::BakeBand::Dense;
  settings.budget = budget_;
  hsdf::HermiteSdfLod lod;
  lod.levels = {std::move(finest)};
  registry_.emplaceOrReplace<hsdf::HermiteSdfLod>(*entity_, std::move(lod));
  startNextLevel(settings);
}

void SdfBakes::startNextLevel(const hsdf::BakeSettings& previous) {
  if (const std::optional<hsdf::BakeSettings> next = hsdf::coarserLodLevel(previous))
    levelJob_ = std::make_unique<hsdf::BakeJob>(*source_, *next);
  else
    log::info("levels of detail: {} levels from K = {}", registry_.get<hsdf::HermiteSdfLod>(*entity_).levels.size(),
              baked_.resolution);
}

// Adds the levels whose bakes are done (all of them when `wait`), starting the next one each time.
Status SdfBakes::finishLevels(bool wait) {
  while (levelJob_ && (wait || levelJob_->finishable())) {
    hsdf::BakeJob::Result result = levelJob_->wait();
    const hsdf::BakeSettings settings = levelJob_->settings();
    const bool cancelled = levelJob_->cancelled();
    levelJob_.reset();
    if (!result && cancelled) {
      log::info("levels of detail: level K = {} cancelled; {} levels from K = {} kept", settings.resolution,
                registry_.get<hsdf::HermiteSdfLod>(*entity_).levels.size(), baked_.resolution);
      return {};
    }
    if (!result) return result.error().withContext(fmt::format("levels of detail: level K = {}", settings.resolution));
    registry_.get<hsdf::HermiteSdfLod>(*entity_).levels.push_back(std::move(*result));
    startNextLevel(settings);
  }
  return {};
}

// A re-baked field the GPU could not take (a feature refused its upload: out of GPU memory) is
// swapped back for the field it replaced, which the features still hold (and drew already in the
// frame that found out, in place of the refused one): the component and the tuning name the K on
// screen again. Checked on the first frame after the swap; the replaced field is released then.
std::optional<std::string> SdfBakes::restoreRefused(render::Renderer& renderer) {
  const ReplacedField replaced = std::exchange(replaced_, {});
  hsdf::HermiteSdfRenderable* sdf = renderable();
  if (!replaced.asset || !sdf || !sdf->asset) return std::nullopt;
  const std::uint64_t id = sdf->asset->id;
  if (!renderer.feature<hsdf::HermiteCellFeature>()->refused(id) && !renderer.feature<hsdf::SphereTraceFeature>()->refused(id))
    return std::nullopt;
  error_ = fmt::format("re-baking at resolution {}: the new field does not fit in GPU memory; resolution {} stays "
                       "drawn",
                       baked_.resolution, replaced.key.resolution);
  log::warn("{}", error_);
  sdf->asset = replaced.asset;
  baked_ = replaced.key;
  setBakeKey(baked_, tuning_);
  return error_;
}

}  // namespace samples
