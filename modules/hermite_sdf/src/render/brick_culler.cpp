#include "render/brick_culler.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/render/gpu_scene.h"
#include "engine/gpu/buffer.h"
#include "hermite_sdf/core/normal_cone.h"
#include "render/model_scales.h"

namespace hsdf {
namespace {

constexpr std::uint32_t kWorkgroupSize = 64;  // brick_cull.comp local_size_x

}  // namespace

engine::Expected<BrickCuller> BrickCuller::create(const engine::gpu::Context& context) {
  ENGINE_TRY_ASSIGN(auto module, engine::gpu::ShaderModule::load(context, "brick_cull.comp"));
  BrickCuller culler;
  ENGINE_TRY_ASSIGN(culler.pipeline_, engine::gpu::Pipeline::createCompute(context, "brick cull", module.handle(),
                                                                           sizeof(shader::BrickCullPushConstants)));
  return culler;
}

void barrierBeforeCulling(VkCommandBuffer cmd) {
  // Write after read: the previous frame's draws may still read the output streams and commands.
  engine::gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT |
                                      VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT,
                             0, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, 0);
}

void barrierAfterCulling(VkCommandBuffer cmd) {
  engine::gpu::memoryBarrier(
      cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
      VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT |
          VK_PIPELINE_STAGE_2_ALL_GRAPHICS_BIT | VK_PIPELINE_STAGE_2_COPY_BIT | VK_PIPELINE_STAGE_2_HOST_BIT,
      VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT |
          VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_HOST_READ_BIT);
}

void BrickCuller::record(VkCommandBuffer cmd, const Buffers& buffers, std::uint32_t objectCount,
                         std::uint32_t maxBricks) const {
  if (objectCount == 0 || maxBricks == 0) return;
  barrierBeforeCulling(cmd);
  const shader::BrickCullPushConstants push{buffers.objects, buffers.bricks,   buffers.cones, buffers.keptBricks,
                                            buffers.commands, buffers.totals, objectCount,  0};
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.handle());
  vkCmdPushConstants(cmd, pipeline_.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
  vkCmdDispatch(cmd, (maxBricks + kWorkgroupSize - 1) / kWorkgroupSize, objectCount, 1);
  barrierAfterCulling(cmd);
}

shader::BrickCullObject BrickCuller::cullObject(const engine::render::CameraView& camera, const glm::mat4& model,
                                                const GridSpec& grid, bool boundaryPositive,
                                                const ObjectBricks& bricks) {
  const glm::mat4 invModel = glm::inverse(model);
  // Both in double, from matrices far from the world origin (engine::render::eyeInObject).
  const glm::dvec3 eyeExact = engine::render::eyeInObject(model, camera.position);
  const glm::vec3 eye(eyeExact);
  // The cone test asks whether rays from an eye point meet a brick's surface from behind; an
  // orthographic camera's rays share no point (normal_cone.glsl takes one): no cone test.
  const bool coneTest = !camera.orthographic() &&
      brickConeCullAllowed(boundaryPositive, eyeExact, double(camera.nearPlaneReachInObject(invModel)), grid);
  shader::BrickCullObject object{};
  object.objectToClip = glm::mat4(glm::dmat4(camera.proj) * camera.viewFrom(glm::dvec3(0.0)) * glm::dmat4(model));
  object.gridOriginSpacing = glm::vec4(glm::vec3(grid.origin), float(grid.spacing));
  object.eyeConeTest = glm::vec4(eye, coneTest ? 1.0f : 0.0f);
  object.firstBrick = bricks.firstBrick;
  object.brickCount = bricks.brickCount;
  object.outputFirst = bricks.outputFirst;
  object.drawCommand = bricks.drawCommand;
  object.minScale = float(modelScales(model).smallest);
  return object;
}

engine::Expected<CellCuller> CellCuller::create(const engine::gpu::Context& context) {
  ENGINE_TRY_ASSIGN(auto module, engine::gpu::ShaderModule::load(context, "cell_cull.comp"));
  CellCuller culler;
  ENGINE_TRY_ASSIGN(culler.pipeline_, engine::gpu::Pipeline::createCompute(context, "cell cull", module.handle(),
                                                                           sizeof(shader::CellCullPushConstants)));
  return culler;
}

CellCuller::RangeUpload CellCuller::rangeUpload(std::span<const shader::CellCullRange> ranges) {
  RangeUpload upload;
  upload.words.resize(ranges.size_bytes() / sizeof(std::uint32_t));
  if (!ranges.empty()) std::memcpy(upload.words.data(), ranges.data(), ranges.size_bytes());
  std::uint32_t cells = 0;
  bool open = false;  // a pack that may take more ranges
  for (std::uint32_t r = 0; r < ranges.size(); ++r) {
    const std::uint32_t n = ranges[r].cellCount;
    if (n > CELL_CULL_MAX_RANGE_CELLS)  // the pass walks a range's cells as 32 chunks of 64 bits
      throw std::invalid_argument(fmt::format("cell cull range {} has {} cells, more than CELL_CULL_MAX_RANGE_CELLS",
                                              r, n));
    const bool alone = n == 0 || n > CELL_CULL_PACK_CELLS;  // an empty range's count: the single-range path
    if (alone || !open || cells + n > CELL_CULL_PACK_CELLS) {
      upload.words.push_back(r);
      ++upload.packCount;
      cells = 0;
    }
    cells += n;
    open = !alone;
  }
  upload.words.push_back(static_cast<std::uint32_t>(ranges.size()));
  return upload;
}

void CellCuller::record(VkCommandBuffer cmd, const shader::CellCullPushConstants& push) const {
  if (push.packCount == 0) return;
  constexpr std::uint32_t kMaxGroupsX = 65535;  // the least maxComputeWorkGroupCount[0] Vulkan allows
  const std::uint32_t groupsX = std::min(push.packCount, kMaxGroupsX);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.handle());
  vkCmdPushConstants(cmd, pipeline_.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
  vkCmdDispatch(cmd, groupsX, (push.packCount + groupsX - 1) / groupsX, 1);
}

}  // namespace hsdf
