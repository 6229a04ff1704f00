#include "engine/render/depth_pyramid.h"

#include <algorithm>

#include "engine/gpu/context.h"
#include "engine/gpu/image.h"
#include "shared/host_device.h"

namespace engine::render {

namespace {
constexpr std::uint32_t kGroupSize = 8;  // depth_pyramid.comp's local size per axis
}

Expected<DepthPyramid> DepthPyramid::create(const gpu::Context& context) {
  ENGINE_TRY_ASSIGN(auto module, gpu::ShaderModule::load(context, "depth_pyramid.comp"));
  DepthPyramid pyramid;
  ENGINE_TRY_ASSIGN(pyramid.pipeline_, gpu::Pipeline::createCompute(context, "depth pyramid", module.handle(),
                                                                     sizeof(shader::DepthPyramidPushConstants)));
  return pyramid;
}

std::uint32_t DepthPyramid::levelCount(VkExtent2D extent) {
  std::uint32_t levels = 1;
  for (VkExtent2D e = extent; e.width > 1 || e.height > 1; ++levels) e = levelExtent(e, 1);
  return levels;
}

VkExtent2D DepthPyramid::levelExtent(VkExtent2D extent, std::uint32_t level) {
  for (std::uint32_t i = 0; i < level; ++i) extent = {(extent.width + 1) / 2, (extent.height + 1) / 2};
  return extent;
}

std::uint32_t DepthPyramid::levelOffset(VkExtent2D extent, std::uint32_t level) {
  std::uint32_t offset = 0;
  for (std::uint32_t i = 0; i < level; ++i) {
    const VkExtent2D e = levelExtent(extent, i);
    offset += e.width * e.height;
  }
  return offset;
}

void DepthPyramid::resize(const gpu::Context& context, VkExtent2D extent) {
  view_ = {0, extent, levelCount(extent)};
  const VkDeviceSize bytes = VkDeviceSize(levelOffset(extent, view_.levels)) * sizeof(float);
  buffer_ = gpu::Buffer(context, bytes,
                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT |
                            VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                        gpu::MemoryUsage::GpuOnly, "depth pyramid");
  view_.address = buffer_.address();
}

void DepthPyramid::record(VkCommandBuffer cmd, const gpu::Image& depth) const {
  // An earlier view region's or frame's build wrote the pyramid and its culling passes read it.
  gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_COPY_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT |
                         VK_ACCESS_2_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_COPY_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                     VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  copyDepth(cmd, depth);
  reduceLevels(cmd);
}

// Level 0: the depth attachment copied as it is (a copy, so that no descriptor set is needed).
void DepthPyramid::copyDepth(VkCommandBuffer cmd, const gpu::Image& depth) const {
  constexpr VkPipelineStageFlags2 tests =
      VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
  gpu::imageBarrier(cmd, depth.handle(), VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, tests, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 0, 1};
  region.imageExtent = {view_.extent.width, view_.extent.height, 1};
  vkCmdCopyImageToBuffer(cmd, depth.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer_.handle(), 1, &region);
  gpu::imageBarrier(cmd, depth.handle(), VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                    VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_NONE, tests,
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
  gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

// Levels 1.. one dispatch each, each reading the level the previous dispatch wrote.
void DepthPyramid::reduceLevels(VkCommandBuffer cmd) const {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.handle());
  for (std::uint32_t level = 1; level < view_.levels; ++level) {
    const VkExtent2D src = levelExtent(view_.extent, level - 1);
    const VkExtent2D dst = levelExtent(view_.extent, level);
    const shader::DepthPyramidPushConstants push{view_.address, levelOffset(view_.extent, level - 1),
                                                 levelOffset(view_.extent, level), src.width, src.height,
                                                 dst.width, dst.height};
    vkCmdPushConstants(cmd, pipeline_.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, (dst.width + kGroupSize - 1) / kGroupSize, (dst.height + kGroupSize - 1) / kGroupSize, 1);
    gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_COPY_BIT,
                       VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT);
  }
}

}  // namespace engine::render
