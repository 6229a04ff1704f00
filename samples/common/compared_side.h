#pragma once
// The compared side of the Viewer's split screen and difference view (TuningState::split,
// difference): its own bake at effectiveCompareResolution on a worker thread (until it is ready,
// and for a compared method of cells, the main asset stands in), the two view regions of a split
// frame, and both sides' normals compared into a heat map drawn over the frame.
#include <algorithm>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/core/expected.h"
#include "engine/ecs/registry.h"
#include "engine/render/renderer.h"
#include "difference_view.h"
#include "hermite_sdf/core/bake_job.h"
#include "tuning.h"

namespace samples {

class ComparedSide {
 public:
  // Puts the scene in the state `tuning` draws, the SDF entity showing `asset` (a view region's
  // override; Viewer::showState).
  using ShowState = std::function<void(const TuningState& tuning, const std::shared_ptr<const hsdf::SdfAsset>& asset)>;
  // The main side's field, shared when the compared side wants the same K, padding and shell.
  struct MainField {
    std::shared_ptr<const hsdf::SdfAsset> asset;  // with the dense field, or not shared
    BakeKey key;
  };

  explicit ComparedSide(ShowState showState) : showState_(std::move(showState)) {}
  // The heat map's overlay (before the first difference frame).
  void createOverlay(const engine::gpu::Context& context, std::uint32_t framesInFlight);
  // Before the device goes: the bake stops, the overlay's buffers are released.
  void release();

  // Starts the bake when the compared side should draw another K (or padding, shell) than it has.
  void updateBake(const TuningState& tuning, const hsdf::BakeSource* source, const MainField& main,
                  const hsdf::BakeBudget& budget);
  // Puts the finished bake's field in place (waiting for it); a failed one is not retried for the
  // same key (the reason is in bakeError()).
  void finishBake();
  hsdf::BakeJob* bakeJob() { return job_.get(); }
  void cancelBake();
  const std::string& bakeError() const { return bakeError_; }
  // The K the compared side is drawn with (`mainResolution` when it draws the main asset).
  int resolutionDrawn(const TuningState& tuning, int mainResolution) const;

  // Two regions split at the divider: `tuning` left (top) drawing `main` (with levels of detail,
  // the level the view picked), the compared one right (bottom) drawing its own bake or `baked`,
  // the field baked at K (level 0: a compared side of cells at K is K, not the level).
  std::vector<engine::render::ViewRegion> splitRegions(const TuningState& tuning, VkExtent2D extent,
                                                       const std::shared_ptr<const hsdf::SdfAsset>& main,
                                                       const std::shared_ptr<const hsdf::SdfAsset>& baked) const;
  // The two sides' normals frames (the SDF alone) compared on the CPU; the heat map goes to the
  // overlay of the frame drawn next (overlay()). `main` and `baked` as for splitRegions.
  engine::Status renderDifference(const TuningState& tuning, const std::shared_ptr<const hsdf::SdfAsset>& main,
                                  const std::shared_ptr<const hsdf::SdfAsset>& baked,
                                  engine::ecs::Registry& registry, engine::render::Renderer& renderer,
                                  const engine::render::CameraView& camera);
  // The heat map over `next` (the UI, or null).
  engine::render::OverlayPass* overlay(engine::render::OverlayPass* next);
  // The numbers of the last difference-view frame (empty when the view is off).
  const std::optional<NormalDifference>& difference() const { return difference_; }
  void clearDifference() { difference_.reset(); }
  // Degrees shown red in the heat map.
  float range() const { return range_; }
  void setRange(float degrees) { range_ = std::max(degrees, 0.1f); }

 private:
  std::shared_ptr<const hsdf::SdfAsset> asset(const TuningState& tuning,
                                              const std::shared_ptr<const hsdf::SdfAsset>& main) const;
  NormalsFrame renderNormals(const TuningState& tuning, const std::shared_ptr<const hsdf::SdfAsset>& asset,
                             engine::ecs::Registry& registry, engine::render::Renderer& renderer,
                             const engine::render::CameraView& camera);

  ShowState showState_;
  std::shared_ptr<const hsdf::SdfAsset> asset_;
  BakeKey key_;  // what asset_ was baked with
  std::unique_ptr<hsdf::BakeJob> job_;
  std::string bakeError_;
  std::optional<BakeKey> failed_;  // the last failed bake's
  std::optional<NormalDifference> difference_;
  float range_ = 10.0f;
  std::unique_ptr<ImageOverlay> overlay_;
};

}  // namespace samples
