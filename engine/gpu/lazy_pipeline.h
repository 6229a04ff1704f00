#pragma once
// LazyPipeline: a graphics pipeline described when its owner is created and compiled the first
// time a frame binds it. A render feature with many variants (per record precision, per counting
// or debug variant, per proxy form) then pays at creation only for loading its shader modules,
// and a process compiles only the pipelines it draws with: on lavapipe, compiling all of one
// feature's variants up front took 2.6 s of a 3-second test program, most of them never bound.
// createAll() compiles a set ahead of any frame (a load screen, a statistics run); a reload
// compiles again only what frames had bound (createWhereNeeded); a PipelineWarmer compiles a set on
// a worker thread while frames go on, so a frame that later needs one of them does not compile it,
// and a PipelineWarming decides when an owner's frames start one and starts it again after a reload.
//
// Threads: get() and warm() may be called from several threads at once (a frame, a warmer). Each
// pipeline has its own mutex, held while it compiles: a second caller waits for that one compile
// and then finds it made, so nothing is compiled twice, and a frame never waits on another
// pipeline's compile. vkCreateGraphicsPipelines is free-threaded and the context's pipeline cache is
// internally synchronized. Moving, describing anew and destroying are the owner's alone, with no
// warmer running over the pipeline.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>
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
  // Moves are the owner's, with no other thread using either pipeline.
  LazyPipeline(LazyPipeline&& other) noexcept;
  LazyPipeline& operator=(LazyPipeline&& other) noexcept;
  LazyPipeline(const LazyPipeline&) = delete;
  LazyPipeline& operator=(const LazyPipeline&) = delete;

  // The pipeline, compiled on the first call, for a frame to bind (or createAll), which makes it
  // needed(). A failure is kept and returned again, not retried every frame: the description and
  // its SPIR-V do not change until the owner reloads them.
  Expected<const Pipeline*> get(const Context& context);
  // The pipeline, or null where it cannot be compiled: the failure is logged the first time, and
  // the caller skips the draws that need it (the frame goes on without them). Needed, as get().
  const Pipeline* getOrLog(const Context& context);
  // Compiles it ahead of a frame that may bind it (a PipelineWarmer's worker), without making it
  // needed: a reload compiles up front only what frames bound, and warms the rest again. A failure
  // is kept for the frame that needs it to log.
  void warm(const Context& context);
  // Whether a frame has bound it (get or getOrLog was called), compiled or not.
  bool needed() const { return needed_.load(std::memory_order_relaxed); }
  // Whether get() has compiled it (a failed or never-needed pipeline is not made). Never waits for
  // a compile under way on another thread (it reads false until that one is done).
  bool made() const { return made_.load(std::memory_order_acquire); }
  bool described() const { return desc_.vertex != VK_NULL_HANDLE; }
  const std::string& name() const { return desc_.name; }
  // How many times this pipeline was compiled (attempts, failed ones included): 0 or 1 until the
  // owner describes it anew.
  std::uint32_t compiles() const { return compiles_.load(std::memory_order_relaxed); }

 private:
  Expected<const Pipeline*> compileLocked(const Context& context);
  GraphicsPipelineDesc desc_;
  std::vector<SharedShaderModule> modules_;
  std::optional<Pipeline> pipeline_;
  std::optional<Error> failure_;
  bool failureLogged_ = false;
  std::atomic<bool> made_{false};  // pipeline_ is set; read without the lock (the frame's fast path)
  std::atomic<std::uint32_t> compiles_{0};
  std::atomic<bool> needed_{false};
  mutable std::mutex mutex_;  // held while compiling: pipeline_, failure_, modules_, failureLogged_
};

// Compiles a set of described pipelines, one after another, on a worker thread at low priority,
// so that a frame switching to one of them binds it instead of compiling it (a compile takes tens
// to hundreds of milliseconds). A frame that needs a pipeline the worker is compiling waits for that
// one (LazyPipeline's lock); one the worker has not reached it compiles itself, and the worker
// then skips it. The destructor (or stop()) stops the worker before its next pipeline and joins it:
// at most the compile under way finishes. The pipelines and the context must outlive the warmer,
// and the owner stops it before it moves, replaces or destroys any of them (a shader reload).
class PipelineWarmer {
 public:
  PipelineWarmer() = default;
  PipelineWarmer(const Context& context, std::vector<LazyPipeline*> set);
  ~PipelineWarmer() { stop(); }
  PipelineWarmer(const PipelineWarmer&) = delete;
  PipelineWarmer& operator=(const PipelineWarmer&) = delete;

  // Stops the worker before its next pipeline and waits for it; idempotent.
  void stop();
  // Waits until the worker has been through its whole set (tests, a load screen).
  void wait();
  bool running() const { return worker_.joinable() && !finished_.load(std::memory_order_acquire); }

 private:
  void run(std::stop_token stop, const Context& context, std::vector<LazyPipeline*> set);
  std::atomic<bool> finished_{false};
  std::jthread worker_;  // last: joined before the members above go
};

// How many pipelines of a set were described, and how many of those are compiled so far.
struct PipelineCounts {
  std::uint32_t described = 0;
  std::uint32_t compiled = 0;
};
PipelineCounts countPipelines(std::span<LazyPipeline* const> set);

// Compiles every described pipeline of `set` (the first failure names its pipeline).
Status createAll(const Context& context, std::span<LazyPipeline* const> set);
// Compiles each pipeline of `fresh` whose counterpart in `old` (the same position) was needed: a
// reload from new SPIR-V has what frames drew with ready, and fails before anything is replaced.
// Those only warmed are not compiled here, on the thread that reloads (a frame's): the owner's
// PipelineWarming warms them again.
Status createWhereNeeded(const Context& context, std::span<LazyPipeline* const> fresh,
                         std::span<LazyPipeline* const> old);
// createWhereNeeded, then waits for the device to be idle: frames in flight may still use `old`,
// which the caller replaces next.
Status readyToReplace(const Context& context, std::span<LazyPipeline* const> fresh, std::span<LazyPipeline* const> old);

// When an owner of lazy pipelines (a render feature) warms them, and which: its frames call
// frame() each; the second of them that has something to warm for starts a PipelineWarmer over the
// set `next` returns then (the first compiles what it draws itself, and a worker compiling beside
// it would only slow it down). Once per set of pipelines: reloading() stops the worker before the
// owner replaces them, and the next frame warms the fresh set at once (the reload compiled what
// frames bind, so that frame compiles nothing a worker would slow down). Owned by the render
// thread; declared after the pipelines, so that its worker is joined before they are destroyed, and
// stopped first by an owner whose destructor destroys what the descriptions name (stop()).
class PipelineWarming {
 public:
  using NextSet = std::function<std::vector<LazyPipeline*>()>;
  // `wanted`: the owner's setting is on and this frame has objects it may draw next.
  void frame(const Context& context, bool wanted, const NextSet& next);
  // Before the owner replaces the pipelines it warms: at most the compile under way finishes.
  void reloading();
  // Stops the worker and waits for it (at most the compile under way finishes); later frames start
  // none until reloading(). Before the owner destroys anything the pipelines' descriptions name (a descriptor set
  // layout): a worker compiling a pipeline uses it, and the members' destruction joins it too late.
  void stop();
  // Waits until the set being warmed is compiled (tests, a load screen); none: returns.
  void wait();
  bool started() const { return warmer_ != nullptr; }

 private:
  std::unique_ptr<PipelineWarmer> warmer_;
  std::uint32_t framesWanting_ = 0;
};

// A shader reload of an owner's set of pipelines (`Set`: a struct whose all() lists its
// LazyPipelines, always in the same order): `describe` makes a fresh set from the SPIR-V on disk,
// swapped in only when every pipeline a frame has drawn with compiled from it; a failure keeps
// the old set. Those only warmed are warmed again from the next frame (`warming`).
template <class Set, class Describe>
Status reloadPipelineSet(const Context& context, PipelineWarming& warming, Set& current, const Describe& describe) {
  warming.reloading();  // its worker compiles the pipelines about to be replaced
  ENGINE_TRY_ASSIGN(Set fresh, describe());
  ENGINE_TRY(readyToReplace(context, fresh.all(), current.all()));
  current = std::move(fresh);
  return {};
}

}  // namespace engine::gpu
