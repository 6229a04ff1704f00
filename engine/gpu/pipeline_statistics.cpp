#include "engine/gpu/pipeline_statistics.h"

#include <utility>

#include "engine/core/log.h"
#include "engine/gpu/context.h"
#include "engine/gpu/vk_check.h"

namespace engine::gpu {
namespace {

// Vulkan writes the counters in the order of their flag bits; PipelineStatistics lists them so.
constexpr VkQueryPipelineStatisticFlags kStatistics =
    VK_QUERY_PIPELINE_STATISTIC_INPUT_ASSEMBLY_VERTICES_BIT | VK_QUERY_PIPELINE_STATISTIC_INPUT_ASSEMBLY_PRIMITIVES_BIT |
    VK_QUERY_PIPELINE_STATISTIC_VERTEX_SHADER_INVOCATIONS_BIT | VK_QUERY_PIPELINE_STATISTIC_CLIPPING_INVOCATIONS_BIT |
    VK_QUERY_PIPELINE_STATISTIC_CLIPPING_PRIMITIVES_BIT | VK_QUERY_PIPELINE_STATISTIC_FRAGMENT_SHADER_INVOCATIONS_BIT;
constexpr std::uint32_t kCounters = 6;

}  // namespace

PipelineStatisticsQueries::PipelineStatisticsQueries(const Context& context, std::uint32_t maxScopes,
                                                     const std::string& name)
    : context_(&context), maxScopes_(maxScopes) {
  if (!context.capabilities().pipelineStatistics) return;
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_PIPELINE_STATISTICS;
  info.queryCount = maxScopes;
  info.pipelineStatistics = kStatistics;
  VK_CHECK(vkCreateQueryPool(context.device(), &info, nullptr, &pool_));
  context.setName(pool_, VK_OBJECT_TYPE_QUERY_POOL, name);
}

PipelineStatisticsQueries::~PipelineStatisticsQueries() { release(); }

PipelineStatisticsQueries::PipelineStatisticsQueries(PipelineStatisticsQueries&& other) noexcept {
  *this = std::move(other);
}

PipelineStatisticsQueries& PipelineStatisticsQueries::operator=(PipelineStatisticsQueries&& other) noexcept {
  if (this != &other) {
    release();
    context_ = std::exchange(other.context_, nullptr);
    pool_ = std::exchange(other.pool_, VK_NULL_HANDLE);
    maxScopes_ = other.maxScopes_;
    names_ = std::move(other.names_);
    open_ = other.open_;
    skipped_ = other.skipped_;
  }
  return *this;
}

void PipelineStatisticsQueries::release() {
  if (pool_) vkDestroyQueryPool(context_->device(), pool_, nullptr);
  pool_ = VK_NULL_HANDLE;
}

void PipelineStatisticsQueries::reset(VkCommandBuffer cmd) {
  names_.clear();
  open_ = false;
  skipped_ = false;
  if (pool_) vkCmdResetQueryPool(cmd, pool_, 0, maxScopes_);
}

void PipelineStatisticsQueries::begin(VkCommandBuffer cmd, const std::string& scope) {
  if (!pool_) return;
  if (open_ || names_.size() >= maxScopes_) {
    log::warn("pipeline statistics: '{}' not measured ({})", scope,
              open_ ? "another scope is open; these queries cannot nest" : "too many scopes in one frame");
    return;
  }
  open_ = true;
  names_.push_back(scope);
  vkCmdBeginQuery(cmd, pool_, static_cast<std::uint32_t>(names_.size() - 1), 0);
}

void PipelineStatisticsQueries::end(VkCommandBuffer cmd) {
  if (!pool_ || !open_) return;
  open_ = false;
  vkCmdEndQuery(cmd, pool_, static_cast<std::uint32_t>(names_.size() - 1));
}

std::vector<PipelineStatistics> PipelineStatisticsQueries::results() const {
  std::vector<PipelineStatistics> stats;
  if (!pool_ || names_.empty()) return stats;
  const auto count = static_cast<std::uint32_t>(names_.size());
  constexpr std::uint32_t stride = kCounters + 1;  // counters + availability
  std::vector<std::uint64_t> values(std::size_t(count) * stride);
  const VkResult result =
      vkGetQueryPoolResults(context_->device(), pool_, 0, count, values.size() * sizeof(std::uint64_t), values.data(),
                            stride * sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WITH_AVAILABILITY_BIT);
  if (result != VK_SUCCESS && result != VK_NOT_READY) VK_CHECK(result);
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::uint64_t* v = &values[std::size_t(i) * stride];
    if (v[kCounters] == 0) continue;  // not available
    stats.push_back({names_[i], v[0], v[1], v[2], v[3], v[4], v[5]});
  }
  return stats;
}

const PipelineStatistics* findStatistics(const std::vector<PipelineStatistics>& stats, const std::string& name) {
  for (const PipelineStatistics& s : stats)
    if (s.name == name) return &s;
  return nullptr;
}

}  // namespace engine::gpu
