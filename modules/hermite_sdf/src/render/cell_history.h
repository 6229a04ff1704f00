#pragma once
// The visibility history of occlusion culling (cell_cull.comp, HermiteCellFeature): one
// uint per cell of each culled object and view region, 1 when the cell was visible the last time
// phase 2 tested it. An object's cells keep their place from frame to frame (a base per entity,
// plus the cell's index within its asset), so the history survives the per-frame re-sort of the
// rows. Only the GPU reads and writes it. Nothing depends on it being right: a fresh (zeroed) or
// stale history only makes phase 2 draw what phase 1 did not.
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/ecs/entity.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/deferred_release.h"

namespace engine::gpu {
class Context;
}

namespace hsdf {

class CellHistory {
 public:
  // One culled object of this frame: its entity, the asset it draws and that asset's cell count.
  struct Object {
    engine::ecs::Entity entity;
    std::uint64_t asset = 0;
    std::uint32_t cells = 0;
  };

  // The base of each object (same order) in view region `region` of `regions`. Objects keep their
  // bases from the region's earlier frames; new ones are appended. Each region places its objects
  // on its own: the sides of a split screen may draw other assets for the same entity (the
  // compared side at another K), which would otherwise take each other's places every frame and
  // leave both with a fresh history. When they do not fit, the buffer is replaced by a larger
  // zeroed one (fill recorded in `cmd`; the old one is retired until frame `frameNumber`
  // completes) and every object of every region is placed anew: the history restarts.
  std::vector<std::uint32_t> place(const engine::gpu::Context& context, VkCommandBuffer cmd,
                                   const std::vector<Object>& objects, std::uint32_t region, std::uint32_t regions,
                                   std::uint64_t frameNumber, engine::gpu::DeferredRelease& retired);
  VkDeviceAddress address() const { return buffer_.address(); }
  // Forgets every place and retires the buffer until frame `frameNumber` completes (occlusion
  // culling unused for a while: HermiteCellFeature::Settings::releaseAfterFrames); the next place()
  // starts a fresh history.
  void release(std::uint64_t frameNumber, engine::gpu::DeferredRelease& retired);
  std::uint64_t bytes() const { return buffer_ ? buffer_.size() : 0; }

 private:
  struct Slot {
    std::uint64_t asset = 0;
    std::uint32_t base = 0;
    std::uint32_t cells = 0;
  };
  // One view region's places: its objects' slots, and the cells placed in its part of the buffer.
  struct Region {
    std::unordered_map<engine::ecs::Entity, Slot> slots;
    std::uint32_t used = 0;
  };
  bool placeAll(Region& region, const std::vector<Object>& objects, std::vector<std::uint32_t>& bases);
  void grow(const engine::gpu::Context& context, VkCommandBuffer cmd, const std::vector<Object>& objects,
            std::uint32_t regions, std::uint64_t frameNumber, engine::gpu::DeferredRelease& retired);

  std::vector<Region> regions_;
  std::uint32_t capacity_ = 0;  // cells per region
  engine::gpu::Buffer buffer_;  // regions_ x capacity_ uints
};

}  // namespace hsdf
