#include "field/parallel.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace hsdf::detail {
namespace {

struct SharedState {
  std::atomic<std::size_t> next{0};
  std::atomic<std::size_t> done{0};
  std::atomic<bool> stop{false};
  std::mutex mutex;
  std::condition_variable wake;
  std::optional<engine::Error> firstError;
  unsigned runningWorkers = 0;

  void fail(engine::Error error) {
    std::lock_guard lock(mutex);
    if (!firstError) firstError = std::move(error);
    stop.store(true);
  }
};

void workerLoop(SharedState& state, std::size_t count, const std::function<engine::Status(std::size_t)>& work) {
  while (!state.stop.load(std::memory_order_relaxed)) {
    const std::size_t item = state.next.fetch_add(1);
    if (item >= count) break;
    if (engine::Status status = work(item); !status.ok()) {
      state.fail(status.error());
      break;
    }
    state.done.fetch_add(1);
  }
  std::lock_guard lock(state.mutex);
  --state.runningWorkers;
  state.wake.notify_all();
}

unsigned workerCount(const BakeOptions& options, std::size_t count) {
  unsigned threads = options.threads != 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  return unsigned(std::min<std::size_t>(threads, std::max<std::size_t>(count, 1)));
}

bool cancelRequested(const BakeOptions& options, float fraction) {
  if (options.cancel != nullptr && options.cancel->isCancelled()) return true;
  return options.progress && !options.progress(fraction);
}

}  // namespace

engine::Status runParallel(std::size_t count, const BakeOptions& options,
                           const std::function<engine::Status(std::size_t)>& work) {
  // The start is reported (fraction 0) before any work: a callback that refuses at once stops the
  // run even where every item finishes before the first poll below (a small bake on a fast machine
  // finished unasked: SparseBake.CancelsByTokenAndByProgressCallback failed in CI).
  if (cancelRequested(options, 0.0f)) return engine::makeError("cancelled");
  SharedState state;
  const unsigned threads = workerCount(options, count);
  state.runningWorkers = threads;
  std::vector<std::thread> workers;
  workers.reserve(threads);
  for (unsigned t = 0; t < threads; ++t) workers.emplace_back(workerLoop, std::ref(state), count, std::cref(work));

  bool cancelled = false;
  {
    std::unique_lock lock(state.mutex);
    while (state.runningWorkers > 0) {
      state.wake.wait_for(lock, std::chrono::milliseconds(20));
      if (cancelled || state.runningWorkers == 0) continue;
      const float fraction = count > 0 ? float(double(state.done.load()) / double(count)) : 1.0f;
      lock.unlock();  // never hold the lock while calling user code
      cancelled = cancelRequested(options, fraction);
      if (cancelled) state.stop.store(true);
      lock.lock();
    }
  }
  for (std::thread& worker : workers) worker.join();

  if (state.firstError) return *state.firstError;
  if (cancelled || (options.cancel != nullptr && options.cancel->isCancelled())) return engine::makeError("cancelled");
  if (options.progress) options.progress(1.0f);  // finished: a late cancel request has nothing left to stop
  return {};
}

}  // namespace hsdf::detail
