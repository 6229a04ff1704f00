#pragma once
// Named GPU timings per pass. One GpuTimer per frame in flight: begin(cmd, "depth prepass") ...
// end(cmd) record timestamp pairs; after that frame's fence has signalled, results() returns the
// milliseconds per name. Names, not query slot numbers, are the interface.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/gpu/query_pool.h"

namespace engine::gpu {

class Context;

struct GpuTiming {
  std::string name;
  double milliseconds = 0.0;
};

class GpuTimer {
 public:
  GpuTimer() = default;
  GpuTimer(const Context& context, std::uint32_t maxScopes, const std::string& name);

  // Starts a new frame of measurements (records a pool reset).
  void reset(VkCommandBuffer cmd);
  // The scope's first timestamp is written when the work recorded before it has passed `after` (one
  // stage): the bottom of the pipe (the default) once that work has ended, so that a scope times
  // its own work and not the end of what ran before it; the top of the pipe at once, which on GPUs
  // may be before earlier work ends.
  void begin(VkCommandBuffer cmd, const std::string& scope,
             VkPipelineStageFlags2 after = VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT);
  void end(VkCommandBuffer cmd);
  // Appended to the names of the scopes begun from now on (the renderer's " [view 2]" while it
  // records a second view region): a split screen drawing one feature on both sides gets a timing
  // per side, where one name twice merged both sides' histories in the panel.
  void setScopeSuffix(std::string suffix) { suffix_ = std::move(suffix); }
  // Reads the results of the last recorded frame; call only after its submission completed.
  std::vector<GpuTiming> results() const;
  bool enabled() const { return bool(pool_); }

 private:
  void stamp(VkCommandBuffer cmd, VkPipelineStageFlags2 after, std::uint32_t slot);
  // The slots whose timestamps begin and end scope `index`; on software rasterizers the slot after
  // each only flushes it.
  std::uint32_t beginSlot(std::uint32_t index) const { return index * slotsPerScope_; }
  std::uint32_t endSlot(std::uint32_t index) const { return index * slotsPerScope_ + slotsPerScope_ / 2; }

  QueryPool pool_;                  // slotsPerScope_ timestamps per scope: begin, then end
  std::uint32_t maxScopes_ = 0;
  // Software rasterizers: 4, each timestamp followed by one that only flushes it. Lavapipe (Mesa
  // 22.3) queues a timestamp into every screen bin of the scene being recorded and keeps, per
  // rasterizer thread, the time its last bin reached it; a scene is rasterized once flushed (a
  // barrier, a timestamp not at the top of the pipe). A timestamp that shares a scene with draws
  // thus reads about when the last bin reached it: a scope begun after the ground plane's draw in
  // the same render pass read 0.04 ms for a 27 ms sphere-tracing prepass. Alone in its scene (the
  // flush before it: `after` at the bottom of the pipe; after it: a second timestamp) it reads when
  // the scenes before it had ended.
  std::uint32_t slotsPerScope_ = 2;
  double periodMs_ = 0.0;
  std::vector<std::string> names_;  // one per begun scope, in query order
  std::string suffix_;
  std::vector<std::uint32_t> open_; // stack of open scope indices
};

// The timing named `name`, or null: a scope not recorded that frame, or a device without
// timestamps (no timings at all). Callers that need the scope tell the two apart.
const GpuTiming* findTiming(const std::vector<GpuTiming>& timings, std::string_view name);

// begin() on construction and end() on destruction, where `timer` is not null: a scope for work
// recorded by a function with several early returns (RenderFeature::prepare's sub-steps).
class GpuTimerScope {
 public:
  GpuTimerScope(GpuTimer* timer, VkCommandBuffer cmd, const std::string& scope,
                VkPipelineStageFlags2 after = VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT)
      : timer_(timer), cmd_(cmd) {
    if (timer_) timer_->begin(cmd_, scope, after);
  }
  ~GpuTimerScope() {
    if (timer_) timer_->end(cmd_);
  }
  GpuTimerScope(const GpuTimerScope&) = delete;
  GpuTimerScope& operator=(const GpuTimerScope&) = delete;

 private:
  GpuTimer* timer_;
  VkCommandBuffer cmd_;
};

}  // namespace engine::gpu
