#include "engine/gpu/deferred_release.h"

namespace engine::gpu {

void DeferredRelease::collect(std::uint64_t frameNumber, std::uint32_t framesInFlight) {
  std::erase_if(pending_, [&](const Entry& entry) { return completed(entry.lastUse, frameNumber, framesInFlight); });
}

}  // namespace engine::gpu
