#include "engine/gpu/lazy_pipeline.h"

#include <utility>

#include "engine/core/log.h"

namespace engine::gpu {

Expected<SharedShaderModule> loadSharedShaderModule(const Context& context, const std::string& name) {
  ENGINE_TRY_ASSIGN(ShaderModule module, ShaderModule::load(context, name));
  return std::make_shared<const ShaderModule>(std::move(module));
}

LazyPipeline::LazyPipeline(GraphicsPipelineDesc desc, std::vector<SharedShaderModule> modules)
    : desc_(std::move(desc)), modules_(std::move(modules)) {}

Expected<const Pipeline*> LazyPipeline::get(const Context& context) {
  if (pipeline_) return &*pipeline_;
  if (failure_) return *failure_;
  if (!described()) return makeError("pipeline '" + desc_.name + "' was never described");
  Expected<Pipeline> made = Pipeline::createGraphics(context, desc_);
  if (!made) {
    failure_ = made.error();
    return made.error();
  }
  pipeline_ = std::move(*made);
  modules_.clear();  // a compiled pipeline no longer needs its modules; other pipelines may
  return &*pipeline_;
}

const Pipeline* LazyPipeline::getOrLog(const Context& context) {
  const bool failedBefore = failure_.has_value();
  Expected<const Pipeline*> pipeline = get(context);
  if (pipeline) return *pipeline;
  if (!failedBefore) log::error("{}; its draws are skipped", pipeline.error().message);
  return nullptr;
}

PipelineCounts countPipelines(std::span<LazyPipeline* const> set) {
  PipelineCounts counts;
  for (const LazyPipeline* pipeline : set) {
    counts.described += pipeline->described() ? 1u : 0u;
    counts.compiled += pipeline->made() ? 1u : 0u;
  }
  return counts;
}

Status createAll(const Context& context, std::span<LazyPipeline* const> set) {
  for (LazyPipeline* pipeline : set)
    if (pipeline->described()) ENGINE_TRY(pipeline->get(context));
  return {};
}

Status createWhereMade(const Context& context, std::span<LazyPipeline* const> fresh,
                       std::span<LazyPipeline* const> old) {
  if (fresh.size() != old.size()) return makeError("a reloaded pipeline set differs in size from the old one");
  for (std::size_t i = 0; i < fresh.size(); ++i)
    if (old[i]->made()) ENGINE_TRY(fresh[i]->get(context));
  return {};
}

}  // namespace engine::gpu
