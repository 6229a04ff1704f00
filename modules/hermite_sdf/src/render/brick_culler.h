#pragma once
// GPU-driven culling of cell bricks: brick_cull.comp tests every brick of every drawn
// object against the frustum and, where the object allows it, its normal cone (normal_cone.h), and
// writes the kept bricks and the instance counts of the objects' indirect draws.
//
// How the cell feature uses it, per frame (buffers by device address, host-visible where the CPU
// writes them, one set per frame in flight):
//  - bricks (CellBrickGpu[]) and cones (CellBrickCone[], brickGradientCones) per asset, uploaded once;
//  - objects: one BrickCullObject per drawn object (cullObject below);
//  - commands: one VkDrawIndirectCommand per object written by the CPU with instanceCount 0 and
//    firstInstance = the object's outputFirst (buffer usage INDIRECT | STORAGE | device address);
//  - keptBricks: room for every object's bricks (usage VERTEX | STORAGE | device address): the
//    instance-rate stream the brick draws read;
//  - totals: a BrickCullTotals the CPU zeroes, read back after the frame's fence for stats.
// record() in prepare(): its barriers make the kept bricks and counts visible to the indirect draws
// and the vertex input of every later pass of the same queue.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>
#include <vulkan/vulkan.h>

#include "engine/core/expected.h"
#include "engine/gpu/pipeline.h"
#include "engine/render/camera_view.h"
#include "hermite/hermite_host_device.h"
#include "hermite_sdf/core/field.h"

namespace hsdf {

// Both culling passes, before and after their dispatches: the previous frame's indirect and vertex
// reads before the writes; the writes before this frame's indirect, vertex-attribute, shader and
// host reads.
void barrierBeforeCulling(VkCommandBuffer cmd);
void barrierAfterCulling(VkCommandBuffer cmd);

class BrickCuller {
 public:
  struct Buffers {
    VkDeviceAddress objects = 0;     // BrickCullObject[objectCount]
    VkDeviceAddress bricks = 0;      // CellBrickGpu[]
    VkDeviceAddress cones = 0;       // CellBrickCone[], parallel to bricks
    VkDeviceAddress keptBricks = 0;  // CellBrickGpu[], output
    VkDeviceAddress commands = 0;    // VkDrawIndirectCommand[]
    VkDeviceAddress totals = 0;      // BrickCullTotals
  };

  static engine::Expected<BrickCuller> create(const engine::gpu::Context& context);

  // Records the dispatch (64 bricks a workgroup, one workgroup row per object; maxBricks: the most
  // bricks of any object) between barrierBeforeCulling and barrierAfterCulling. Nothing is
  // recorded for no objects or no bricks.
  void record(VkCommandBuffer cmd, const Buffers& buffers, std::uint32_t objectCount, std::uint32_t maxBricks) const;

  // One object's cull parameters: model and camera give the object-to-clip matrix and the eye in
  // object space; the cone test is allowed when boundaryPositive (SdfAsset) and the camera's near
  // plane stays out of the grid box (brickConeCullAllowed).
  struct ObjectBricks {
    std::uint32_t firstBrick = 0;
    std::uint32_t brickCount = 0;
    std::uint32_t outputFirst = 0;
    std::uint32_t drawCommand = 0;
  };
  static shader::BrickCullObject cullObject(const engine::render::CameraView& camera, const glm::mat4& model,
                                            const GridSpec& grid, bool boundaryPositive, const ObjectBricks& bricks);

 private:
  engine::gpu::Pipeline pipeline_;
};

// GPU-driven culling of the cells of RenderMethod::Cells objects: cell_cull.comp tests
// every cell of every front-face range (a row of a culled object) as the brick pass tests a brick,
// with the cells' own normal cones (cellGradientCone, one per record), and writes the kept records
// (copies: the draws read them as vertex attributes), their record indices and each range's
// command's instance count. Ranges and objects by address as for the bricks: the objects are
// BrickCullObjects (BrickCuller::cullObject), of which the pass reads the object fields only.
class CellCuller {
 public:
  static engine::Expected<CellCuller> create(const engine::gpu::Context& context);

  // What cell_cull.comp reads at CellCullPushConstants::ranges: the ranges, then each pack's first
  // range and ranges.size() (a pack, one workgroup: consecutive ranges of at most
  // CELL_CULL_PACK_CELLS cells together; a longer or an empty one alone), and the pack count. A range
  // of more than CELL_CULL_MAX_RANGE_CELLS cells is a programming error (std::invalid_argument).
  struct RangeUpload {
    std::vector<std::uint32_t> words;
    std::uint32_t packCount = 0;
  };
  static RangeUpload rangeUpload(std::span<const shader::CellCullRange> ranges);

  // Records one dispatch per call (one record precision: its buffers in `push`), one workgroup a
  // pack of ranges (push.packCount), without barriers: the caller puts the passes between barrierBeforeCulling and
  // barrierAfterCulling. Nothing is recorded for no ranges.
  void record(VkCommandBuffer cmd, const shader::CellCullPushConstants& push) const;

 private:
  engine::gpu::Pipeline pipeline_;
};

}  // namespace hsdf
