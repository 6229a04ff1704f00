#pragma once
// Named pipeline-statistics queries: how much work a scope of a frame gave the vertex and fragment
// stages (vertex / fragment shader invocations, primitives assembled and clipped). These counts do
// not depend on how fast the device is, so they carry over from lavapipe to a GPU where timings do
// not. One PipelineStatisticsQueries per frame in flight, used like GpuTimer: begin(cmd, "name")
// ... end(cmd) outside or inside a render pass (never nested: Vulkan allows one active query of
// this type per command buffer), results() after that frame's fence has signalled.
// Empty (enabled() false) on devices without the pipelineStatisticsQuery feature.
#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/gpu/query_pool.h"

namespace engine::gpu {

class Context;

struct PipelineStatistics {
  std::string name;
  std::uint64_t inputAssemblyVertices = 0;
  std::uint64_t inputAssemblyPrimitives = 0;
  std::uint64_t vertexShaderInvocations = 0;
  std::uint64_t clippingInvocations = 0;    // primitives that reached the clipping stage
  std::uint64_t clippingPrimitives = 0;     // primitives that came out of it
  std::uint64_t fragmentShaderInvocations = 0;
};

class PipelineStatisticsQueries {
 public:
  PipelineStatisticsQueries() = default;
  PipelineStatisticsQueries(const Context& context, std::uint32_t maxScopes, const std::string& name);

  // Starts a new frame of measurements (records a pool reset; outside a render pass).
  void reset(VkCommandBuffer cmd);
  // A scope begun while another is open is not measured (logged once per frame).
  void begin(VkCommandBuffer cmd, const std::string& scope);
  void end(VkCommandBuffer cmd);
  // The counts of the last recorded frame; call only after its submission completed. Scopes whose
  // results are not available are left out.
  std::vector<PipelineStatistics> results() const;
  bool enabled() const { return bool(pool_); }

 private:
  QueryPool pool_;  // one query per scope
  std::uint32_t maxScopes_ = 0;
  std::vector<std::string> names_;
  bool open_ = false;
  bool skipped_ = false;  // the open scope is not measured
};

// The counts of `name` in `stats`, or nullptr.
const PipelineStatistics* findStatistics(const std::vector<PipelineStatistics>& stats, const std::string& name);

}  // namespace engine::gpu
