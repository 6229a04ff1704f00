#pragma once
// What each entity drew in each view region's last frame (e.g. which asset), kept by a render feature
// that draws it again in place of what it cannot draw yet (a new asset refused for GPU memory, or
// still being uploaded in parts). One record per view region: the regions of a split screen may
// draw one entity in other forms (the sides of a comparison swap other assets in), and a record per
// entity alone made a region that was waiting for its new form draw the other region's form.
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "engine/ecs/entity.h"
#include "engine/render/render_feature.h"

namespace engine::render {

template <class Value>
class DrawnPerRegion {
 public:
  using Drawn = std::unordered_map<ecs::Entity, Value>;

  // At the start of each prepare(): the region `frame` draws now. The entities of another registry
  // are other objects: every record is forgotten.
  void beginRegion(const FrameContext& frame) {
    if (registry_ != &frame.registry) regions_.clear();
    registry_ = &frame.registry;
    region_ = frame.viewRegionIndex;
    frame_ = frame.frameNumber;
    if (regions_.size() <= region_) regions_.resize(region_ + 1);
  }

  // What `entity` drew in this region's last frame; a region that has not drawn it (a region just
  // added) takes what another region drew of it in this frame or the previous one. Null: none.
  const Value* previous(ecs::Entity entity) const {
    if (const Value* own = find(regions_[region_], entity)) return own;
    for (std::uint32_t r = 0; r < regions_.size(); ++r)
      if (const Value* other = r != region_ && recent(regions_[r]) ? find(regions_[r], entity) : nullptr) return other;
    return nullptr;
  }

  // This region's draws of this frame (replacing its last frame's).
  void setDrawn(Drawn drawn) { regions_[region_] = {frame_, std::move(drawn)}; }

  // Calls `f(value)` for what each entity drew in the other regions drawn this frame or the
  // previous one (a region no longer drawn, e.g. the split turned off, no longer counts).
  template <class F>
  void forOtherRegions(F&& f) const {
    for (std::uint32_t r = 0; r < regions_.size(); ++r)
      if (r != region_ && recent(regions_[r]))
        for (const auto& entry : regions_[r].drawn) f(entry.second);
  }

 private:
  struct Region {
    std::uint64_t frame = 0;
    Drawn drawn;
  };
  static const Value* find(const Region& region, ecs::Entity entity) {
    const auto found = region.drawn.find(entity);
    return found == region.drawn.end() ? nullptr : &found->second;
  }
  bool recent(const Region& region) const { return !region.drawn.empty() && region.frame + 1 >= frame_; }

  std::vector<Region> regions_;
  std::uint32_t region_ = 0;
  std::uint64_t frame_ = 0;
  const ecs::Registry* registry_ = nullptr;
};

}  // namespace engine::render
