#include "engine/gpu/query_pool.h"

#include "engine/gpu/context.h"
#include "engine/gpu/vk_check.h"

namespace engine::gpu {

QueryPool::QueryPool(const Context& context, VkQueryType type, std::uint32_t count, const std::string& name,
                     VkQueryPipelineStatisticFlags statistics)
    : context_(&context), count_(count) {
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = type;
  info.queryCount = count;
  info.pipelineStatistics = statistics;
  VK_CHECK(vkCreateQueryPool(context.device(), &info, nullptr, pool_.receive(context.device())));
  context.setName(pool_.get(), VK_OBJECT_TYPE_QUERY_POOL, name);
}

void QueryPool::reset(VkCommandBuffer cmd) const {
  if (pool_) vkCmdResetQueryPool(cmd, pool_.get(), 0, count_);
}

std::vector<std::uint64_t> QueryPool::read(std::uint32_t queries, std::uint32_t valuesPerQuery) const {
  const std::uint32_t stride = valuesPerQuery + 1;  // + availability
  std::vector<std::uint64_t> values(std::size_t(queries) * stride, 0);
  if (!pool_ || queries == 0) return values;
  // VK_NOT_READY is expected for queries that were never written this frame (their availability
  // stays 0); anything else is an error.
  const VkResult result = vkGetQueryPoolResults(
      context_->device(), pool_.get(), 0, queries, values.size() * sizeof(std::uint64_t), values.data(),
      stride * sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WITH_AVAILABILITY_BIT);
  if (result != VK_SUCCESS && result != VK_NOT_READY) VK_CHECK(result);
  return values;
}

}  // namespace engine::gpu
