#include "engine/gpu/gpu_timer.h"

#include "engine/core/log.h"
#include "engine/gpu/context.h"

namespace engine::gpu {

GpuTimer::GpuTimer(const Context& context, std::uint32_t maxScopes, const std::string& name) : maxScopes_(maxScopes) {
  if (!context.capabilities().timestamps) return;  // timings silently empty on such devices
  periodMs_ = double(context.capabilities().timestampPeriodNs) * 1e-6;
  slotsPerScope_ = context.capabilities().isSoftwareRasterizer ? 4 : 2;
  pool_ = QueryPool(context, VK_QUERY_TYPE_TIMESTAMP, maxScopes * slotsPerScope_, name);
}

void GpuTimer::reset(VkCommandBuffer cmd) {
  names_.clear();
  open_.clear();
  suffix_.clear();
  pool_.reset(cmd);
}

void GpuTimer::begin(VkCommandBuffer cmd, const std::string& scope, VkPipelineStageFlags2 after) {
  if (!pool_) return;
  if (names_.size() >= maxScopes_) {
    log::warn("GpuTimer: more than {} scopes in one frame; '{}{}' not timed", maxScopes_, scope, suffix_);
    open_.push_back(~0u);
    return;
  }
  const auto index = static_cast<std::uint32_t>(names_.size());
  names_.push_back(scope + suffix_);
  open_.push_back(index);
  stamp(cmd, after, beginSlot(index));
}

void GpuTimer::end(VkCommandBuffer cmd) {
  if (!pool_ || open_.empty()) return;
  const std::uint32_t index = open_.back();
  open_.pop_back();
  if (index != ~0u) stamp(cmd, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, endSlot(index));
}

void GpuTimer::stamp(VkCommandBuffer cmd, VkPipelineStageFlags2 after, std::uint32_t slot) {
  vkCmdWriteTimestamp2(cmd, after, pool_.handle(), slot);
  if (slotsPerScope_ == 4) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, pool_.handle(), slot + 1);
}

std::vector<GpuTiming> GpuTimer::results() const {
  std::vector<GpuTiming> timings;
  if (!pool_ || names_.empty()) return timings;
  // read(..., 1) returns two values per slot, its tick and then its availability.
  const std::vector<std::uint64_t> values = pool_.read(static_cast<std::uint32_t>(names_.size() * slotsPerScope_), 1);
  const auto tick = [&](std::uint32_t slot) { return values[2 * std::size_t(slot)]; };
  const auto ready = [&](std::uint32_t slot) { return values[2 * std::size_t(slot) + 1] != 0; };
  for (std::uint32_t i = 0; i < names_.size(); ++i) {
    if (!ready(beginSlot(i)) || !ready(endSlot(i))) continue;
    timings.push_back({names_[i], double(tick(endSlot(i)) - tick(beginSlot(i))) * periodMs_});
  }
  return timings;
}

const GpuTiming* findTiming(const std::vector<GpuTiming>& timings, std::string_view name) {
  for (const GpuTiming& timing : timings)
    if (timing.name == name) return &timing;
  return nullptr;
}

}  // namespace engine::gpu
