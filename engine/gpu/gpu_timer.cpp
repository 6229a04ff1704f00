#include "engine/gpu/gpu_timer.h"

#include "engine/core/log.h"
#include "engine/gpu/context.h"

namespace engine::gpu {

GpuTimer::GpuTimer(const Context& context, std::uint32_t maxScopes, const std::string& name) : maxScopes_(maxScopes) {
  if (!context.capabilities().timestamps) return;  // timings silently empty on such devices
  periodMs_ = double(context.capabilities().timestampPeriodNs) * 1e-6;
  pool_ = QueryPool(context, VK_QUERY_TYPE_TIMESTAMP, maxScopes * 2, name);
}

void GpuTimer::reset(VkCommandBuffer cmd) {
  names_.clear();
  open_.clear();
  pool_.reset(cmd);
}

void GpuTimer::begin(VkCommandBuffer cmd, const std::string& scope, VkPipelineStageFlags2 after) {
  if (!pool_) return;
  if (names_.size() >= maxScopes_) {
    log::warn("GpuTimer: more than {} scopes in one frame; '{}' not timed", maxScopes_, scope);
    open_.push_back(~0u);
    return;
  }
  const auto index = static_cast<std::uint32_t>(names_.size());
  names_.push_back(scope);
  open_.push_back(index);
  vkCmdWriteTimestamp2(cmd, after, pool_.handle(), index * 2);
}

void GpuTimer::end(VkCommandBuffer cmd) {
  if (!pool_ || open_.empty()) return;
  const std::uint32_t index = open_.back();
  open_.pop_back();
  if (index != ~0u) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, pool_.handle(), index * 2 + 1);
}

std::vector<GpuTiming> GpuTimer::results() const {
  std::vector<GpuTiming> timings;
  if (!pool_ || names_.empty()) return timings;
  // Per scope: begin tick, its availability, end tick, its availability.
  const std::vector<std::uint64_t> ticks = pool_.read(static_cast<std::uint32_t>(names_.size() * 2), 1);
  for (std::size_t i = 0; i < names_.size(); ++i) {
    const std::uint64_t begin = ticks[4 * i], beginReady = ticks[4 * i + 1];
    const std::uint64_t end = ticks[4 * i + 2], endReady = ticks[4 * i + 3];
    if (!beginReady || !endReady) continue;
    timings.push_back({names_[i], double(end - begin) * periodMs_});
  }
  return timings;
}

}  // namespace engine::gpu
