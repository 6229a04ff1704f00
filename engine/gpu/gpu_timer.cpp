#include "engine/gpu/gpu_timer.h"

#include <utility>

#include "engine/core/log.h"
#include "engine/gpu/context.h"
#include "engine/gpu/vk_check.h"

namespace engine::gpu {

GpuTimer::GpuTimer(const Context& context, std::uint32_t maxScopes, const std::string& name)
    : context_(&context), maxScopes_(maxScopes) {
  if (!context.capabilities().timestamps) return;  // timings silently empty on such devices
  periodMs_ = double(context.capabilities().timestampPeriodNs) * 1e-6;
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = maxScopes * 2;
  VK_CHECK(vkCreateQueryPool(context.device(), &info, nullptr, &pool_));
  context.setName(pool_, VK_OBJECT_TYPE_QUERY_POOL, name);
}

GpuTimer::~GpuTimer() { release(); }

GpuTimer::GpuTimer(GpuTimer&& other) noexcept { *this = std::move(other); }

GpuTimer& GpuTimer::operator=(GpuTimer&& other) noexcept {
  if (this != &other) {
    release();
    context_ = std::exchange(other.context_, nullptr);
    pool_ = std::exchange(other.pool_, VK_NULL_HANDLE);
    maxScopes_ = other.maxScopes_;
    periodMs_ = other.periodMs_;
    names_ = std::move(other.names_);
    open_ = std::move(other.open_);
  }
  return *this;
}

void GpuTimer::release() {
  if (pool_) vkDestroyQueryPool(context_->device(), pool_, nullptr);
  pool_ = VK_NULL_HANDLE;
}

void GpuTimer::reset(VkCommandBuffer cmd) {
  names_.clear();
  open_.clear();
  if (pool_) vkCmdResetQueryPool(cmd, pool_, 0, maxScopes_ * 2);
}

void GpuTimer::begin(VkCommandBuffer cmd, const std::string& scope) {
  if (!pool_) return;
  if (names_.size() >= maxScopes_) {
    log::warn("GpuTimer: more than {} scopes in one frame; '{}' not timed", maxScopes_, scope);
    open_.push_back(~0u);
    return;
  }
  const auto index = static_cast<std::uint32_t>(names_.size());
  names_.push_back(scope);
  open_.push_back(index);
  vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, pool_, index * 2);
}

void GpuTimer::end(VkCommandBuffer cmd) {
  if (!pool_ || open_.empty()) return;
  const std::uint32_t index = open_.back();
  open_.pop_back();
  if (index != ~0u) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, pool_, index * 2 + 1);
}

std::vector<GpuTiming> GpuTimer::results() const {
  std::vector<GpuTiming> timings;
  if (!pool_ || names_.empty()) return timings;
  const auto queryCount = static_cast<std::uint32_t>(names_.size() * 2);
  std::vector<std::uint64_t> ticks(queryCount * 2);  // value + availability per query
  const VkResult result = vkGetQueryPoolResults(
      context_->device(), pool_, 0, queryCount, ticks.size() * sizeof(std::uint64_t), ticks.data(),
      2 * sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WITH_AVAILABILITY_BIT);
  if (result != VK_SUCCESS && result != VK_NOT_READY) VK_CHECK(result);
  for (std::size_t i = 0; i < names_.size(); ++i) {
    const std::uint64_t begin = ticks[4 * i], beginReady = ticks[4 * i + 1];
    const std::uint64_t end = ticks[4 * i + 2], endReady = ticks[4 * i + 3];
    if (!beginReady || !endReady) continue;
    timings.push_back({names_[i], double(end - begin) * periodMs_});
  }
  return timings;
}

}  // namespace engine::gpu
