#pragma once
// Progress reporting and cancellation for long CPU jobs (field baking, re-bakes from the UI).
#include <atomic>
#include <functional>
#include <string_view>

namespace engine {

// Called with a fraction in [0,1]; may be called from worker threads (calls are serialized by
// the caller). Returning false requests cancellation.
using ProgressCallback = std::function<bool(float fraction)>;

// A cancellation flag that can be shared with a worker (e.g. set from a UI button).
struct CancelToken {
  std::atomic<bool> cancelled{false};
  void cancel() { cancelled.store(true, std::memory_order_relaxed); }
  bool isCancelled() const { return cancelled.load(std::memory_order_relaxed); }
};

}  // namespace engine
