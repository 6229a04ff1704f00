#pragma once
// LazyPipeline: a graphics pipeline described when its owner is created and compiled the first
// time a frame binds it. A render feature with many variants (per record precision, per counting
// or debug variant, per proxy form) then pays at creation only for loading its shader modules,
// and a process compiles only the pipelines it draws with: on lavapipe, compiling all of one
// feature's variants up front took 2.6 s of a 3-second test program, most of them never bound.
// createAll() compiles a set ahead of any frame (a load screen, a statistics run); a reload
// compiles again only what frames had used (createWhereMade).
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "engine/core/expected.h"
#include "engine/gpu/pipeline.h"

namespace engine::gpu {

class Context;

// A shader module several described pipelines share (a vertex shader of many fragment variants).
using SharedShaderModule = std::shared_ptr<const ShaderModule>;
Expected<SharedShaderModule> loadSharedShaderModule(const Context& context, const std::string& name);

class LazyPipeline {
 public:
  LazyPipeline() = default;
  // `modules` keep the shader modules `desc` names alive until the pipeline is compiled.
  LazyPipeline(GraphicsPipelineDesc desc, std::vector<SharedShaderModule> modules);

  // The pipeline, compiled on the first call. A failure is kept and returned again, not retried
  // every frame: the description and its SPIR-V do not change until the owner reloads them.
  Expected<const Pipeline*> get(const Context& context);
  // The pipeline, or null where it cannot be compiled: the failure is logged the first time, and
  // the caller skips the draws that need it (the frame goes on without them).
  const Pipeline* getOrLog(const Context& context);
  // Whether get() has compiled it (a failed or never-needed pipeline is not made).
  bool made() const { return pipeline_.has_value(); }
  bool described() const { return desc_.vertex != VK_NULL_HANDLE; }
  const std::string& name() const { return desc_.name; }

 private:
  GraphicsPipelineDesc desc_;
  std::vector<SharedShaderModule> modules_;
  std::optional<Pipeline> pipeline_;
  std::optional<Error> failure_;
};

// How many pipelines of a set were described, and how many of those are compiled so far.
struct PipelineCounts {
  std::uint32_t described = 0;
  std::uint32_t compiled = 0;
};
PipelineCounts countPipelines(std::span<LazyPipeline* const> set);

// Compiles every described pipeline of `set` (the first failure names its pipeline).
Status createAll(const Context& context, std::span<LazyPipeline* const> set);
// Compiles each pipeline of `fresh` whose counterpart in `old` (the same position) was compiled:
// a reload from new SPIR-V has what frames drew with ready, and fails before anything is replaced.
Status createWhereMade(const Context& context, std::span<LazyPipeline* const> fresh,
                       std::span<LazyPipeline* const> old);

}  // namespace engine::gpu
