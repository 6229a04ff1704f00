#include "engine/gpu/pipeline_statistics.h"

#include "engine/core/log.h"
#include "engine/gpu/context.h"

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
    : maxScopes_(maxScopes) {
  if (!context.capabilities().pipelineStatistics) return;
  pool_ = QueryPool(context, VK_QUERY_TYPE_PIPELINE_STATISTICS, maxScopes, name, kStatistics);
}

void PipelineStatisticsQueries::reset(VkCommandBuffer cmd) {
  names_.clear();
  open_ = false;
  skipped_ = false;
  pool_.reset(cmd);
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
  vkCmdBeginQuery(cmd, pool_.handle(), static_cast<std::uint32_t>(names_.size() - 1), 0);
}

void PipelineStatisticsQueries::end(VkCommandBuffer cmd) {
  if (!pool_ || !open_) return;
  open_ = false;
  vkCmdEndQuery(cmd, pool_.handle(), static_cast<std::uint32_t>(names_.size() - 1));
}

std::vector<PipelineStatistics> PipelineStatisticsQueries::results() const {
  std::vector<PipelineStatistics> stats;
  if (!pool_ || names_.empty()) return stats;
  const auto count = static_cast<std::uint32_t>(names_.size());
  constexpr std::uint32_t stride = kCounters + 1;  // counters + availability
  const std::vector<std::uint64_t> values = pool_.read(count, kCounters);
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
