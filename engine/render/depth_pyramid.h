#pragma once
// DepthPyramid: the prepass depth reduced to a mip chain of the FARTHEST depth per texel
// (reverse-Z: the minimum), for occlusion culling in compute (RenderFeature::usesOcclusionCulling):
// a box whose nearest depth is farther than the pyramid over its screen rectangle is hidden by
// what is already drawn. Level 0 is a copy of the depth attachment; level k + 1 has ceil(size / 2)
// texels per axis, each the minimum of the up to 2x2 texels of level k it covers (odd edges: the
// texels that exist), so a texel of level k covers exactly the pixels [x 2^k, (x + 1) 2^k) clipped
// to the frame. The levels live in one storage buffer (row-major, concatenated, level 0 first),
// read by device address: compute passes take it as push constants, no descriptor sets.
#include <cstdint>

#include <vulkan/vulkan.h>

#include "engine/core/expected.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/pipeline.h"

namespace engine::gpu {
class Context;
class Image;
}  // namespace engine::gpu

namespace engine::render {

// What a culling pass needs to read the pyramid (DepthPyramid::levelExtent gives the sizes).
struct DepthPyramidView {
  VkDeviceAddress address = 0;  // float[]: the levels, concatenated
  VkExtent2D extent{};          // level 0: the frame
  std::uint32_t levels = 0;
};

class DepthPyramid {
 public:
  static Expected<DepthPyramid> create(const gpu::Context& context);

  // Level sizes and where each starts in the buffer (in floats), for a frame of `extent`.
  static std::uint32_t levelCount(VkExtent2D extent);
  static VkExtent2D levelExtent(VkExtent2D extent, std::uint32_t level);
  static std::uint32_t levelOffset(VkExtent2D extent, std::uint32_t level);

  // Sizes the buffer for frames of `extent` (with the GPU idle: the renderer's resize).
  void resize(const gpu::Context& context, VkExtent2D extent);
  // Records the build from `depth` (of the resized extent), which arrives in
  // DEPTH_ATTACHMENT_OPTIMAL with its attachment writes done and leaves in it, ready for further
  // depth tests and writes. Its writes are visible to compute shaders afterwards.
  void record(VkCommandBuffer cmd, const gpu::Image& depth) const;
  DepthPyramidView view() const { return view_; }
  const gpu::Buffer& buffer() const { return buffer_; }

 private:
  void copyDepth(VkCommandBuffer cmd, const gpu::Image& depth) const;
  void reduceLevels(VkCommandBuffer cmd) const;

  gpu::Pipeline pipeline_;
  gpu::Buffer buffer_;
  DepthPyramidView view_;
};

}  // namespace engine::render
