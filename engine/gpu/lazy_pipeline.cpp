#include "engine/gpu/lazy_pipeline.h"

#include <exception>
#include <utility>

#ifdef __linux__
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

#include "engine/core/log.h"
#include "engine/gpu/context.h"

namespace engine::gpu {

Expected<SharedShaderModule> loadSharedShaderModule(const Context& context, const std::string& name) {
  ENGINE_TRY_ASSIGN(ShaderModule module, ShaderModule::load(context, name));
  return std::make_shared<const ShaderModule>(std::move(module));
}

LazyPipeline::LazyPipeline(GraphicsPipelineDesc desc, std::vector<SharedShaderModule> modules)
    : desc_(std::move(desc)), modules_(std::move(modules)) {}

LazyPipeline::LazyPipeline(LazyPipeline&& other) noexcept { *this = std::move(other); }

LazyPipeline& LazyPipeline::operator=(LazyPipeline&& other) noexcept {
  if (this != &other) {
    desc_ = std::move(other.desc_);
    modules_ = std::move(other.modules_);
    pipeline_ = std::move(other.pipeline_);
    other.pipeline_.reset();
    failure_ = std::exchange(other.failure_, std::nullopt);
    failureLogged_ = std::exchange(other.failureLogged_, false);
    made_.store(other.made_.exchange(false));
    compiles_.store(other.compiles_.exchange(0));
    needed_.store(other.needed_.exchange(false));
  }
  return *this;
}

Expected<const Pipeline*> LazyPipeline::get(const Context& context) {
  needed_.store(true, std::memory_order_relaxed);
  if (made()) return &*pipeline_;  // set once before made_, never changed while shared
  const std::lock_guard lock(mutex_);
  return compileLocked(context);
}

// With mutex_ held: another thread that compiled it while this one waited leaves it made.
Expected<const Pipeline*> LazyPipeline::compileLocked(const Context& context) {
  if (pipeline_) return &*pipeline_;
  if (failure_) return *failure_;
  if (!described()) return makeError("pipeline '" + desc_.name + "' was never described");
  compiles_.fetch_add(1, std::memory_order_relaxed);
  log::debug("compiling pipeline '{}'", desc_.name);
  Expected<Pipeline> made = Pipeline::createGraphics(context, desc_);
  if (!made) {
    failure_ = made.error();
    return made.error();
  }
  pipeline_ = std::move(*made);
  modules_.clear();  // a compiled pipeline no longer needs its modules; other pipelines may
  made_.store(true, std::memory_order_release);
  return &*pipeline_;
}

void LazyPipeline::warm(const Context& context) {
  if (made()) return;
  const std::lock_guard lock(mutex_);
  (void)compileLocked(context);
}

const Pipeline* LazyPipeline::getOrLog(const Context& context) {
  needed_.store(true, std::memory_order_relaxed);
  if (made()) return &*pipeline_;
  const std::lock_guard lock(mutex_);
  Expected<const Pipeline*> pipeline = compileLocked(context);
  if (pipeline) return *pipeline;
  // Logged by the first frame that needs it, whichever thread's compile failed.
  if (!std::exchange(failureLogged_, true)) log::error("{}; its draws are skipped", pipeline.error().message);
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

Status createWhereNeeded(const Context& context, std::span<LazyPipeline* const> fresh,
                         std::span<LazyPipeline* const> old) {
  if (fresh.size() != old.size()) return makeError("a reloaded pipeline set differs in size from the old one");
  for (std::size_t i = 0; i < fresh.size(); ++i)
    if (old[i]->needed()) ENGINE_TRY(fresh[i]->get(context));
  return {};
}

Status readyToReplace(const Context& context, std::span<LazyPipeline* const> fresh, std::span<LazyPipeline* const> old) {
  ENGINE_TRY(createWhereNeeded(context, fresh, old));
  context.waitIdle();
  return {};
}

namespace {

// The warmer's compiles yield to the frames' threads on a machine with few cores (lavapipe renders
// on the CPU): the lowest priority for this thread alone (Linux keeps a nice value per thread).
void lowerThisThreadsPriority() {
#ifdef __linux__
  (void)setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 19);
#endif
}

}  // namespace

PipelineWarmer::PipelineWarmer(const Context& context, std::vector<LazyPipeline*> set)
    : worker_([this, &context, set = std::move(set)](std::stop_token stop) mutable {
        run(stop, context, std::move(set));
      }) {}

void PipelineWarmer::run(std::stop_token stop, const Context& context, std::vector<LazyPipeline*> set) {
  lowerThisThreadsPriority();
  try {
    for (LazyPipeline* pipeline : set) {
      if (stop.stop_requested()) break;
      if (pipeline->described()) pipeline->warm(context);
    }
  } catch (const std::exception& error) {  // a frame compiling the rest itself is no worse than without a warmer
    log::warn("pipeline warmer stopped: {}", error.what());
  }
  finished_.store(true, std::memory_order_release);
}

void PipelineWarmer::stop() {
  worker_.request_stop();
  if (worker_.joinable()) worker_.join();
}

void PipelineWarmer::wait() {
  if (worker_.joinable()) worker_.join();
}

void PipelineWarming::frame(const Context& context, bool wanted, const NextSet& next) {
  if (!wanted || warmer_) return;
  if (++framesWanting_ < 2) return;
  warmer_ = std::make_unique<PipelineWarmer>(context, next());
}

// A set warmed before (started: the owner's frames wanted it) is warmed again by the next frame.
void PipelineWarming::reloading() {
  framesWanting_ = warmer_ ? 1u : 0u;
  warmer_.reset();
}

void PipelineWarming::stop() {
  if (warmer_) warmer_->stop();
}

void PipelineWarming::wait() {
  if (warmer_) warmer_->wait();
}

}  // namespace engine::gpu
