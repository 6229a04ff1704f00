#pragma once
// A render feature's statistics per view region of the last frame. A frame of several regions (a
// split screen) prepares each region in turn (render_feature.h), and a feature whose prepare()
// starts its stats afresh kept only the last region's: the tuning panel of a split screen with
// one method left and another right showed the left one's feature "objects 0, draws 0".
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace engine::render {

template <class Stats>
class RegionStats {
 public:
  // At the start of each prepare(), before the feature starts `current` afresh for this region:
  // `current` holds the previous region's stats, kept when it was this frame's.
  void startRegion(std::uint64_t frameNumber, const Stats& current) {
    if (frameNumber == frame_) {
      earlier_.push_back(current);
      return;
    }
    earlier_.clear();
    frame_ = frameNumber;
  }
  // Each region's stats of the last frame prepared, in drawing order: the earlier regions', then
  // `current` (the last region's).
  std::vector<Stats> all(const Stats& current) const {
    std::vector<Stats> regions = earlier_;
    regions.push_back(current);
    return regions;
  }

 private:
  std::vector<Stats> earlier_;
  std::uint64_t frame_ = std::numeric_limits<std::uint64_t>::max();
};

// What a panel writes before a region's stats line: "view N: " where the frame had several regions.
inline std::string regionPrefix(std::size_t region, std::size_t regions) {
  return regions > 1 ? "view " + std::to_string(region + 1) + ": " : std::string();
}

}  // namespace engine::render
