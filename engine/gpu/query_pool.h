#pragma once
// An owned VkQueryPool: the one piece GpuTimer (timestamps) and PipelineStatisticsQueries
// (pipeline statistics) share. It creates, names, resets and reads the pool and destroys it once;
// what the queries mean and how scopes map to query slots stays with the two users.
#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/gpu/device_handle.h"

namespace engine::gpu {

class Context;

class QueryPool {
 public:
  QueryPool() = default;
  // `statistics` is the VkQueryPipelineStatisticFlags of a VK_QUERY_TYPE_PIPELINE_STATISTICS pool,
  // 0 for other types.
  QueryPool(const Context& context, VkQueryType type, std::uint32_t count, const std::string& name,
            VkQueryPipelineStatisticFlags statistics = 0);

  VkQueryPool handle() const { return pool_.get(); }
  explicit operator bool() const { return bool(pool_); }
  std::uint32_t count() const { return count_; }

  // Records a reset of every query of the pool (outside a render pass).
  void reset(VkCommandBuffer cmd) const;
  // The first `queries` results as 64-bit values: `valuesPerQuery` values each, followed by the
  // query's availability (0: not available). Results not yet written read as unavailable.
  std::vector<std::uint64_t> read(std::uint32_t queries, std::uint32_t valuesPerQuery) const;

 private:
  const Context* context_ = nullptr;
  QueryPoolHandle pool_;  // owned from its creation: a failed naming gives it back
  std::uint32_t count_ = 0;
};

}  // namespace engine::gpu
