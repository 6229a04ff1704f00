#include "hermite_sdf/render/cell_feature.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <unordered_set>

#include <imgui.h>

#include "engine/core/log.h"
#include "engine/ecs/registry.h"
#include "engine/gpu/context.h"
#include "engine/gpu/vk_check.h"
#include "engine/render/gpu_scene.h"
#include "engine/scene/transform.h"
#include "hermite/hermite_host_device.h"
#include "cells/cell_bricks.h"
#include "render/brick_culler.h"
#include "render/cell_history.h"
#include "render/cell_rows.h"
#include "hermite_sdf/render/lod.h"
#include "hermite_sdf/core/normal_cone.h"

namespace hsdf {

using engine::gpu::Buffer;
using engine::gpu::Pipeline;

// The GPU copy of every drawn asset's cell records: one fp32 and one fp16 buffer, each the
// concatenation of the assets' streams, so one vertex-buffer binding serves all objects.
struct CellBuffers {
  struct Entry {
    std::shared_ptr<const SdfAsset> asset;
    std::uint32_t firstRecord = 0;  // same index in both buffers
    CellRows rows;
    std::vector<shader::CellRunGpu> runs;  // firstRecord relative to the asset's stream
    std::uint32_t firstRun = 0;            // index of runs[0] in the run buffer
    CellBricks bricks;                     // RenderMethod::CellBricks, indices relative to the asset's stream
    std::vector<shader::CellBrickCone> cones;  // one per brick (normal_cone.h), for the brick culling pass
    // Whether bricks and cones were built: only for assets drawn as bricks, since the cones cost a
    // few microseconds per cell (seconds at K >= 1024) that cells and runs would pay for nothing.
    bool bricksBuilt = false;
    std::uint32_t firstBrick = 0;          // index of bricks.bricks[0] in the brick buffer
    // One normal cone per record (cellGradientCone), for the cell culling pass: built, as the
    // bricks' cones, only for assets some entity draws as culled cells.
    std::vector<shader::CellBrickCone> cellCones;
    bool cellConesBuilt = false;
    std::uint64_t lastFrame = 0;           // the last frame that drew the asset
  };
  std::unordered_map<std::uint64_t, Entry> entries;  // by asset id
  Buffer records[2];
  Buffer runs;  // every asset's runs, firstRecord global (RenderMethod::CellRuns)
  Buffer bricks;      // every asset's CellBrickGpu, firstIndex global (RenderMethod::CellBricks)
  Buffer brickCells;  // the bricks' kept cells: global record indices, brick by brick
  Buffer brickCones;  // CellBrickCone per entry of `bricks`
  Buffer cellCones;   // CellBrickCone per record (same index as `records`); never-cull cones for
                      // assets without cell cones
  std::uint32_t runLength = 0;  // the maximum run length the runs were built with
  std::uint64_t bytes = 0;
};

// This frame's indirect commands for one record precision: the front-face list, then the
// near-cell list, as ranges of the shared command and draw-data arrays.
struct HermiteCellFeature::Batch {
  std::uint32_t frontFirst = 0, frontCount = 0;
  std::uint32_t nearFirst = 0, nearCount = 0;
  std::uint32_t wireFirst = 0;  // DEBUG_VIEW_WIREFRAME: the front list again with kWireVertices
  std::uint32_t lateFirst = 0;  // occlusion culling: the front list again, drawn in phase 2
};

// One description of a cell record: the GPU structs of hermite_host_device.h. The CPU records
// (cells.h), uploaded byte for byte, must match them field by field, and the vertex layout below is
// derived from them. The coordinate halves pack as x | y << 16 and z | class << 16 (little endian).
template <class Cpu, class Gpu>
constexpr bool sameRecordLayout() {
  return sizeof(Cpu) == sizeof(Gpu) && offsetof(Cpu, corners) == offsetof(Gpu, corners) &&
         sizeof(Cpu::corners) == sizeof(Gpu::corners) && offsetof(Cpu, x) == offsetof(Gpu, xy) &&
         offsetof(Cpu, y) == offsetof(Gpu, xy) + 2 && offsetof(Cpu, z) == offsetof(Gpu, zc) &&
         offsetof(Cpu, cellClass) == offsetof(Gpu, zc) + 2 && offsetof(Gpu, zc) == offsetof(Gpu, xy) + 4;
}
static_assert(sameRecordLayout<CellRecord, shader::CellRecordGpu>(), "CellRecord and CellRecordGpu must match");
static_assert(sameRecordLayout<CellRecordHalf, shader::CellRecordHalfGpu>(), "CellRecordHalf and CellRecordHalfGpu must match");

namespace {

constexpr std::uint32_t kRecordStride[2] = {sizeof(CellRecord), sizeof(CellRecordHalf)};
// Vertices per instance of every box (cells, thin cells, runs, bricks; box.glsl): the front faces as
// one triangle fan, all six faces (near-plane boxes, drawn by back faces) as one triangle strip: 8
// and 14 vertex-shader invocations per box (issue 20, step 2); the wireframe: the 12 edges.
constexpr std::uint32_t kFanVertices = 8;
constexpr std::uint32_t kStripVertices = 14;
constexpr std::uint32_t kWireVertices = 24;

// One record per instance: locations 0-7 the corners (f, fx, fy, fz), 8 the coordinate and class
// as four 16-bit integers (cells.vert, cells_thin.vert).
template <class Gpu>
engine::gpu::VertexLayout recordVertexLayout(VkFormat cornerFormat) {
  engine::gpu::VertexLayout layout;
  layout.bindings.push_back({0, sizeof(Gpu), VK_VERTEX_INPUT_RATE_INSTANCE});
  constexpr std::uint32_t cornerBytes = sizeof(Gpu::corners) / 8;
  for (std::uint32_t i = 0; i < 8; ++i)
    layout.attributes.push_back({i, 0, cornerFormat, std::uint32_t(offsetof(Gpu, corners)) + i * cornerBytes});
  layout.attributes.push_back({8, 0, VK_FORMAT_R16G16B16A16_UINT, std::uint32_t(offsetof(Gpu, xy))});
  return layout;
}

engine::gpu::VertexLayout cellVertexLayout(int precision) {
  return precision == 0 ? recordVertexLayout<shader::CellRecordGpu>(VK_FORMAT_R32G32B32A32_SFLOAT)
                        : recordVertexLayout<shader::CellRecordHalfGpu>(VK_FORMAT_R16G16B16A16_SFLOAT);
}

engine::gpu::VertexLayout runVertexLayout() {
  engine::gpu::VertexLayout layout;
  layout.bindings.push_back({0, sizeof(shader::CellRunGpu), VK_VERTEX_INPUT_RATE_INSTANCE});
  layout.attributes.push_back({0, 0, VK_FORMAT_R32G32_UINT, offsetof(shader::CellRunGpu, xy)});
  layout.attributes.push_back({1, 0, VK_FORMAT_R32_UINT, offsetof(shader::CellRunGpu, firstRecord)});
  return layout;
}

// One CellBrickGpu per instance, read whole (bricks.vert).
engine::gpu::VertexLayout brickVertexLayout() {
  engine::gpu::VertexLayout layout;
  layout.bindings.push_back({0, sizeof(shader::CellBrickGpu), VK_VERTEX_INPUT_RATE_INSTANCE});
  layout.attributes.push_back({0, 0, VK_FORMAT_R32G32B32A32_UINT, 0});
  return layout;
}

constexpr VkAccessFlags2 kStorageReadWrite = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;

bool drawnAsCells(RenderMethod method) {
  return method == RenderMethod::Cells || method == RenderMethod::CellRuns || method == RenderMethod::CellBricks;
}

// The renderer's work counters when the frame counts (the capture reads them back), else the
// feature's own heat-map counters when the evals view is on, else none.
VkDeviceAddress counterAddress(const engine::render::FrameContext& frame, bool active,
                               const engine::gpu::PixelBuffer& own) {
  return frame.workCounters ? frame.workCounters : active ? own.address() : 0;
}

// The NDC rectangle (x0, y0, x1, y1) that holds the object's grid box on screen, grown by two
// pixels for the proxies' dilation and rasterization; the whole screen when a corner lies at or
// behind the eye plane, where the projection of the box is unbounded.
glm::vec4 screenBounds(const glm::mat4& viewProj, const glm::mat4& model, const Aabb& box, VkExtent2D extent) {
  const glm::vec4 whole(-1.0f, -1.0f, 1.0f, 1.0f);
  glm::vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 p((corner & 1) ? box.max.x : box.min.x, (corner & 2) ? box.max.y : box.min.y,
                       (corner & 4) ? box.max.z : box.min.z);
    const glm::vec4 clip = viewProj * (model * glm::vec4(glm::vec3(p), 1.0f));
    if (!(clip.w > 1e-6f)) return whole;
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    lo = glm::min(lo, ndc);
    hi = glm::max(hi, ndc);
  }
  const glm::vec2 margin(4.0f / float(std::max(extent.width, 1u)), 4.0f / float(std::max(extent.height, 1u)));
  return glm::clamp(glm::vec4(lo - margin, hi + margin), -1.0f, 1.0f);
}

// The asset's bricks: those built for it before (they depend on the asset only), else built now. A
// grid too large for brick coordinates is reported and gets no bricks (its CellBricks objects
// draw nothing).
CellBricks bricksOf(const SdfAsset& asset, const std::unordered_map<std::uint64_t, CellBuffers::Entry>& built) {
  if (auto old = built.find(asset.id); old != built.end() && old->second.bricksBuilt) return old->second.bricks;
  auto bricks = buildCellBricks(asset.cells);
  if (bricks) return std::move(*bricks);
  engine::log::warn("hermite cells: '{}' cannot be drawn as cell bricks: {}", asset.name, bricks.error().message);
  return {};
}

// The normal cones of the asset's bricks (brick culling), cached like the bricks. Cones that cannot
// be built (they only fail for bricks inconsistent with the stream) are replaced by cones that
// never cull, so the culling pass keeps every brick and the object still draws.
std::vector<shader::CellBrickCone> conesOf(const SdfAsset& asset, const CellBricks& bricks,
                                           const std::unordered_map<std::uint64_t, CellBuffers::Entry>& built) {
  if (auto old = built.find(asset.id); old != built.end() && old->second.bricksBuilt) return old->second.cones;
  auto cones = brickGradientCones(asset.cells, bricks.bricks, bricks.cellRecords);
  if (cones) return std::move(*cones);
  engine::log::warn("hermite cells: '{}': no brick normal cones: {}", asset.name, cones.error().message);
  return std::vector<shader::CellBrickCone>(bricks.bricks.size(), neverCullCone());
}

// The normal cone of each of the asset's cells (cell culling), cached like the bricks' cones.
std::vector<shader::CellBrickCone> cellConesOf(const SdfAsset& asset,
                                               const std::unordered_map<std::uint64_t, CellBuffers::Entry>& built) {
  if (auto old = built.find(asset.id); old != built.end() && old->second.cellConesBuilt) return old->second.cellCones;
  return cellGradientCones(asset.cells);
}

// A culling pass's output buffer of at least `bytes` (device address, storage, plus `usage`): the
// frame slot's old one while it is large enough.
Buffer& ensureOutput(const engine::gpu::Context& context, Buffer& buffer, VkDeviceSize bytes, VkBufferUsageFlags usage,
                     const char* name) {
  bytes = std::max<VkDeviceSize>(bytes, 4);  // a zero-sized buffer is invalid
  if (!buffer || buffer.size() < bytes)
    buffer = Buffer(context, bytes, usage | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                    engine::gpu::MemoryUsage::GpuOnly, name);
  return buffer;
}

constexpr std::uint32_t kNotCulled = ~0u;

glm::vec4 unite(const glm::vec4& a, const glm::vec4& b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::max(a.z, b.z), std::max(a.w, b.w)};
}

}  // namespace

HermiteCellFeature::HermiteCellFeature() : buffers_(std::make_unique<CellBuffers>()) {
  for (auto& batch : batches_) batch = std::make_unique<Batch>();
}

HermiteCellFeature::~HermiteCellFeature() = default;

engine::Status HermiteCellFeature::initialize(const engine::gpu::Context& context,
                                              const engine::render::RendererFormats& formats,
                                              std::uint32_t framesInFlight) {
  context_ = &context;
  multiDraw_ = context.capabilities().multiDrawIndirect;
  drawData_ = engine::render::PerFrameBuffer(context, framesInFlight, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                             "hermite cell draws");
  // Storage too: the brick culling pass writes the instance counts of the bricks' commands.
  indirect_ = engine::render::PerFrameBuffer(context, framesInFlight,
                                             VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                             "hermite cell indirect");
  cullObjects_ = engine::render::PerFrameBuffer(context, framesInFlight, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                                "hermite brick cull objects");
  cullTotals_ = engine::render::PerFrameBuffer(context, framesInFlight, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                               "hermite brick cull totals");
  keptBricks_.resize(framesInFlight);
  ENGINE_TRY_ASSIGN(auto culler, BrickCuller::create(context));
  culler_ = std::make_unique<BrickCuller>(std::move(culler));
  cellCullObjectBuffer_ = engine::render::PerFrameBuffer(context, framesInFlight, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                                         "hermite cell cull objects");
  cellCullRangeBuffer_ = engine::render::PerFrameBuffer(context, framesInFlight, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                                        "hermite cell cull ranges");
  keptCellRecords_.resize(framesInFlight);
  keptCellIndices_.resize(framesInFlight);
  history_ = std::make_unique<CellHistory>();
  frameSlots_ = framesInFlight;
  ENGINE_TRY_ASSIGN(auto cellCuller, CellCuller::create(context));
  cellCuller_ = std::make_unique<CellCuller>(std::move(cellCuller));
  objects_ = engine::render::PerFrameBuffer(context, framesInFlight, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                            "hermite cell objects");
  formats_ = formats;
  ENGINE_TRY_ASSIGN(pipelines_, createPipelines());
  return {};
}

// Built aside and swapped in only when every one was created: a failure keeps the old ones.
engine::Status HermiteCellFeature::reloadShaders() {
  ENGINE_TRY_ASSIGN(Pipelines fresh, createPipelines());
  context_->waitIdle();  // frames in flight may still use the old pipelines
  pipelines_ = std::move(fresh);
  return {};
}

engine::Expected<HermiteCellFeature::Pipelines> HermiteCellFeature::createPipelines() const {
  const engine::gpu::Context& context = *context_;
  const engine::render::RendererFormats& formats = formats_;
  Pipelines p;
  // Fragment shaders per prepass variant (Variant; shaders/hermite/hit_depth.glsl): front faces, near cells.
  static constexpr const char* kCellsFront[kVariants] = {"cells_depth.frag", "cells_depth_counted.frag",
                                                         "cells_depth_early.frag"};
  static constexpr const char* kCellsNear[kVariants] = {"cells_depth_near.frag", "cells_depth_near_counted.frag",
                                                        "cells_depth_near_early.frag"};
  static constexpr const char* kRunsFront[kVariants] = {"runs_depth.frag", "runs_depth_counted.frag",
                                                        "runs_depth_early.frag"};
  static constexpr const char* kRunsNear[kVariants] = {"runs_depth_near.frag", "runs_depth_near_counted.frag",
                                                       "runs_depth_near_early.frag"};
  static constexpr const char* kVariantNames[kVariants] = {"", " counted", " early"};
  ENGINE_TRY_ASSIGN(auto vert, engine::gpu::ShaderModule::load(context, "cells.vert"));
  ENGINE_TRY_ASSIGN(auto fixupFrag, engine::gpu::ShaderModule::load(context, "cells_depth_early_fixup.frag"));
  ENGINE_TRY_ASSIGN(auto resolveVert, engine::gpu::ShaderModule::load(context, "cells_resolve.vert"));
  ENGINE_TRY_ASSIGN(auto wireVert, engine::gpu::ShaderModule::load(context, "cells_wire.vert"));
  ENGINE_TRY_ASSIGN(auto wireFrag, engine::gpu::ShaderModule::load(context, "cells_wire.frag"));
  ENGINE_TRY_ASSIGN(auto resolveFrag, engine::gpu::ShaderModule::load(context, "cells_resolve.frag"));
  ENGINE_TRY_ASSIGN(auto runsVert, engine::gpu::ShaderModule::load(context, "runs.vert"));

  for (int variant = 0; variant < kVariants; ++variant) {
    ENGINE_TRY_ASSIGN(auto frontFrag, engine::gpu::ShaderModule::load(context, kCellsFront[variant]));
    ENGINE_TRY_ASSIGN(auto nearFrag, engine::gpu::ShaderModule::load(context, kCellsNear[variant]));
    for (int precision = 0; precision < 2; ++precision) {
      const std::string suffix = std::string(kVariantNames[variant]) + (precision == 0 ? " fp32" : " fp16");
      engine::gpu::GraphicsPipelineDesc desc;
      desc.vertex = vert.handle();
      desc.vertexLayout = cellVertexLayout(precision);
      desc.pushConstantBytes = sizeof(shader::HermitePushConstants);
      desc.depthFormat = formats.depth;
      desc.colorFormats = {formats.visibility};
      desc.depthCompare = VK_COMPARE_OP_GREATER;  // a miss writes depth 0, which this rejects (hit_depth.glsl)
      desc.name = "hermite cells depth" + suffix;
      desc.fragment = frontFrag.handle();
      desc.cullMode = VK_CULL_MODE_BACK_BIT;
      desc.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_FAN;
      ENGINE_TRY_ASSIGN(p.depthFront[variant][precision], Pipeline::createGraphics(context, desc));
      desc.name = "hermite cells depth near" + suffix;
      desc.fragment = nearFrag.handle();
      desc.cullMode = VK_CULL_MODE_FRONT_BIT;
      desc.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP;
      ENGINE_TRY_ASSIGN(p.depthNear[variant][precision], Pipeline::createGraphics(context, desc));
    }
    // Cell runs: records by address, one pipeline pair for both precisions (HERMITE_FLAG_HALF_RECORDS).
    ENGINE_TRY_ASSIGN(auto runsFrontFrag, engine::gpu::ShaderModule::load(context, kRunsFront[variant]));
    ENGINE_TRY_ASSIGN(auto runsNearFrag, engine::gpu::ShaderModule::load(context, kRunsNear[variant]));
    engine::gpu::GraphicsPipelineDesc desc;
    desc.vertex = runsVert.handle();
    desc.vertexLayout = runVertexLayout();
    desc.pushConstantBytes = sizeof(shader::HermitePushConstants);
    desc.depthFormat = formats.depth;
    desc.colorFormats = {formats.visibility};
    desc.depthCompare = VK_COMPARE_OP_GREATER;
    desc.name = std::string("hermite cell runs depth") + kVariantNames[variant];
    desc.fragment = runsFrontFrag.handle();
    desc.cullMode = VK_CULL_MODE_BACK_BIT;
    desc.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_FAN;
    ENGINE_TRY_ASSIGN(p.runsFront[variant], Pipeline::createGraphics(context, desc));
    desc.name = std::string("hermite cell runs depth near") + kVariantNames[variant];
    desc.fragment = runsNearFrag.handle();
    desc.cullMode = VK_CULL_MODE_FRONT_BIT;
    desc.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP;
    ENGINE_TRY_ASSIGN(p.runsNear[variant], Pipeline::createGraphics(context, desc));
  }
  ENGINE_TRY(createBrickPipelines(p));
  ENGINE_TRY(createThinCellPipelines(p));

  // Wireframe: edges over the shaded frame, hidden where the surface is in front of them.
  for (int precision = 0; precision < 2; ++precision) {
    engine::gpu::GraphicsPipelineDesc wire;
    wire.name = std::string("hermite cells wireframe") + (precision == 0 ? " fp32" : " fp16");
    wire.vertex = wireVert.handle();
    wire.fragment = wireFrag.handle();
    wire.vertexLayout = cellVertexLayout(precision);
    std::erase_if(wire.vertexLayout.attributes, [](const auto& a) { return a.location != 8; });  // coordinates only
    wire.pushConstantBytes = sizeof(shader::HermitePushConstants);
    wire.topology = VK_PRIMITIVE_TOPOLOGY_LINE_LIST;
    wire.cullMode = VK_CULL_MODE_NONE;
    wire.depthFormat = formats.depth;
    wire.colorFormats = {formats.color};
    wire.depthWrite = false;
    wire.depthCompare = VK_COMPARE_OP_GREATER_OR_EQUAL;
    ENGINE_TRY_ASSIGN(p.wire[precision], Pipeline::createGraphics(context, wire));
  }
  // Shading: a rectangle over the cell objects' screen bounds; which of its pixels are ours comes
  // from the visibility buffer.
  engine::gpu::GraphicsPipelineDesc resolve;
  resolve.name = "hermite cells resolve";
  resolve.vertex = resolveVert.handle();
  resolve.fragment = resolveFrag.handle();
  resolve.cullMode = VK_CULL_MODE_NONE;
  // The rectangle lies on the far plane (reverse-Z: depth 0), so LESS passes only where the prepass
  // drew something. Background pixels fail this test before the shader runs: on lavapipe a 4x4
  // block whose pixels all fail an early test skips the shader, while a discard inside it does
  // not (docs/perf/cells-breakdown-lavapipe.md); GPUs reject such quads early too.
  resolve.depthTest = true;
  resolve.depthCompare = VK_COMPARE_OP_LESS;
  resolve.depthWrite = false;
  resolve.depthFormat = formats.depth;
  resolve.colorFormats = {formats.color};
  resolve.pushConstantBytes = sizeof(shader::HermitePushConstants);
  resolve.setLayouts = {formats.sceneSetLayout};
  ENGINE_TRY_ASSIGN(p.resolve, Pipeline::createGraphics(context, resolve));
  // Early depth fix-up: the same rectangle, in the prepass, writing only depth (always: the faces it
  // replaces lie in front of the hits, and nothing else has been drawn yet).
  engine::gpu::GraphicsPipelineDesc fixup;
  fixup.name = "hermite cells depth fix-up";
  fixup.vertex = resolveVert.handle();
  fixup.fragment = fixupFrag.handle();
  fixup.cullMode = VK_CULL_MODE_NONE;
  fixup.depthCompare = VK_COMPARE_OP_ALWAYS;
  fixup.depthFormat = formats.depth;
  fixup.colorFormats = {formats.visibility};
  fixup.colorWrite = false;
  fixup.pushConstantBytes = sizeof(shader::HermitePushConstants);
  ENGINE_TRY_ASSIGN(p.depthFixup, Pipeline::createGraphics(context, fixup));
  return p;
}


// Cell bricks: production and counted variants, no early depth one (a frame that draws bricks
// keeps the early depth stage off: buildDraws). Both precisions share one pipeline pair.
engine::Status HermiteCellFeature::createBrickPipelines(Pipelines& p) const {
  static constexpr const char* kFront[kBrickVariants] = {"bricks_depth.frag", "bricks_depth_counted.frag"};
  static constexpr const char* kNear[kBrickVariants] = {"bricks_depth_near.frag", "bricks_depth_near_counted.frag"};
  static constexpr const char* kNames[kBrickVariants] = {"", " counted"};
  ENGINE_TRY_ASSIGN(auto vert, engine::gpu::ShaderModule::load(*context_, "bricks.vert"));
  for (int variant = 0; variant < kBrickVariants; ++variant) {
    ENGINE_TRY_ASSIGN(auto front, engine::gpu::ShaderModule::load(*context_, kFront[variant]));
    ENGINE_TRY_ASSIGN(auto near, engine::gpu::ShaderModule::load(*context_, kNear[variant]));
    engine::gpu::GraphicsPipelineDesc desc;
    desc.vertex = vert.handle();
    desc.vertexLayout = brickVertexLayout();
    desc.pushConstantBytes = sizeof(shader::HermitePushConstants);
    desc.depthFormat = formats_.depth;
    desc.colorFormats = {formats_.visibility};
    desc.depthCompare = VK_COMPARE_OP_GREATER;
    desc.name = std::string("hermite cell bricks depth") + kNames[variant];
    desc.fragment = front.handle();
    desc.cullMode = VK_CULL_MODE_BACK_BIT;
    desc.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_FAN;
    ENGINE_TRY_ASSIGN(p.bricksFront[variant], Pipeline::createGraphics(*context_, desc));
    desc.name = std::string("hermite cell bricks depth near") + kNames[variant];
    desc.fragment = near.handle();
    desc.cullMode = VK_CULL_MODE_FRONT_BIT;
    desc.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP;
    ENGINE_TRY_ASSIGN(p.bricksNear[variant], Pipeline::createGraphics(*context_, desc));
  }
  return {};
}

// Thin cell boxes: production and counted variants (no early depth one: buildDraws keeps the stage
// off), per precision for the cell attribute's offset in the record; the corners are read by address.
engine::Status HermiteCellFeature::createThinCellPipelines(Pipelines& p) const {
  static constexpr const char* kFront[kBrickVariants] = {"cells_thin_depth.frag", "cells_thin_depth_counted.frag"};
  static constexpr const char* kNear[kBrickVariants] = {"cells_thin_depth_near.frag",
                                                        "cells_thin_depth_near_counted.frag"};
  static constexpr const char* kNames[kBrickVariants] = {"", " counted"};
  ENGINE_TRY_ASSIGN(auto vert, engine::gpu::ShaderModule::load(*context_, "cells_thin.vert"));
  for (int variant = 0; variant < kBrickVariants; ++variant) {
    ENGINE_TRY_ASSIGN(auto front, engine::gpu::ShaderModule::load(*context_, kFront[variant]));
    ENGINE_TRY_ASSIGN(auto near, engine::gpu::ShaderModule::load(*context_, kNear[variant]));
    for (int precision = 0; precision < 2; ++precision) {
      const std::string suffix = std::string(kNames[variant]) + (precision == 0 ? " fp32" : " fp16");
      engine::gpu::GraphicsPipelineDesc desc;
      desc.vertex = vert.handle();
      desc.vertexLayout = cellVertexLayout(precision);
      std::erase_if(desc.vertexLayout.attributes, [](const auto& a) { return a.location != 8; });  // the cell only
      desc.pushConstantBytes = sizeof(shader::HermitePushConstants);
      desc.depthFormat = formats_.depth;
      desc.colorFormats = {formats_.visibility};
      desc.depthCompare = VK_COMPARE_OP_GREATER;
      desc.name = "hermite thin cells depth" + suffix;
      desc.fragment = front.handle();
      desc.cullMode = VK_CULL_MODE_BACK_BIT;
      desc.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_FAN;
      ENGINE_TRY_ASSIGN(p.thinFront[variant][precision], Pipeline::createGraphics(*context_, desc));
      desc.name = "hermite thin cells depth near" + suffix;
      desc.fragment = near.handle();
      desc.cullMode = VK_CULL_MODE_FRONT_BIT;
      desc.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP;
      ENGINE_TRY_ASSIGN(p.thinNear[variant][precision], Pipeline::createGraphics(*context_, desc));
    }
  }
  return {};
}

void HermiteCellFeature::syncAssets(const engine::render::FrameContext& frame) {
  std::vector<std::shared_ptr<const SdfAsset>> wanted;
  std::unordered_set<std::uint64_t> seen;
  std::unordered_set<std::uint64_t> asBricks;  // assets some entity draws as cell bricks
  std::unordered_set<std::uint64_t> asCulledCells;  // ... as culled cells (RenderMethod::Cells, Settings::cullCells)
  bool missing = false;
  frame.registry.view<HermiteSdfRenderable>().each([&](engine::ecs::Entity entity, const HermiteSdfRenderable& r) {
    if (!drawnAsCells(r.method) || !r.asset || r.asset->cells.records.empty()) return;
    const bool bricks = r.method == RenderMethod::CellBricks;
    const bool culledCells = r.method == RenderMethod::Cells && settings_.cullCells;
    if (refused_.contains(r.asset->id)) {
      // The entity still draws the asset the refused one replaced (buildDraws): keep it uploaded.
      if (auto previous = drawnAssets_.find(entity); previous != drawnAssets_.end())
        if (auto kept = buffers_->entries.find(previous->second); kept != buffers_->entries.end()) {
          if (bricks) asBricks.insert(kept->first);
          if (culledCells) asCulledCells.insert(kept->first);
          if (seen.insert(kept->first).second) {
            wanted.push_back(kept->second.asset);
            kept->second.lastFrame = frame.frameNumber;
          }
        }
      return;
    }
    if (bricks) asBricks.insert(r.asset->id);
    if (culledCells) asCulledCells.insert(r.asset->id);
    if (!seen.insert(r.asset->id).second) return;
    wanted.push_back(r.asset);
    auto entry = buffers_->entries.find(r.asset->id);
    if (entry == buffers_->entries.end())
      missing = true;
    else
      entry->second.lastFrame = frame.frameNumber;
  });
  for (std::uint64_t id : asBricks)  // an uploaded asset now drawn as bricks: build its bricks
    if (auto entry = buffers_->entries.find(id); entry != buffers_->entries.end() && !entry->second.bricksBuilt)
      missing = true;
  for (std::uint64_t id : asCulledCells)  // ... now drawn as culled cells: build its cell cones
    if (auto entry = buffers_->entries.find(id); entry != buffers_->entries.end() && !entry->second.cellConesBuilt)
      missing = true;
  const bool runsStale = !wanted.empty() && buffers_->runLength != settings_.maxRunLength &&
                         settings_.maxRunLength != refusedRunLength_;  // the setting changed
  if (!missing && !runsStale) return;

  // View regions call prepare() once per region: an asset an earlier region of this frame drew
  // stays (its draws are recorded already and the next frame draws it again).
  for (const auto& [id, entry] : buffers_->entries)
    if (entry.lastFrame == frame.frameNumber && seen.insert(id).second) wanted.push_back(entry.asset);

  // Rebuild the concatenated buffers with the assets drawn now (assets no longer drawn are dropped).
  // The old buffers may be referenced by commands recorded earlier in this frame and by frames in
  // flight: they are retired below, and freed once this frame has completed (prepare()).
  CellBuffers rebuilt;
  std::vector<CellRecord> full;
  std::vector<CellRecordHalf> half;
  std::vector<shader::CellRunGpu> runs;
  std::vector<shader::CellBrickGpu> bricks;
  std::vector<std::uint32_t> brickCells;
  std::vector<shader::CellBrickCone> cones;
  std::vector<shader::CellBrickCone> cellCones;
  for (const auto& asset : wanted) {
    CellBuffers::Entry entry;
    entry.asset = asset;
    entry.firstRecord = static_cast<std::uint32_t>(full.size());
    if (!buffers_->entries.contains(asset->id)) entry.rows = buildCellRows(asset->cells);  // else moved below
    entry.runs = buildCellRuns(asset->cells, settings_.maxRunLength);
    entry.firstRun = static_cast<std::uint32_t>(runs.size());
    for (shader::CellRunGpu run : entry.runs) {
      run.firstRecord += entry.firstRecord;
      runs.push_back(run);
    }
    const auto old = buffers_->entries.find(asset->id);
    entry.bricksBuilt = asBricks.contains(asset->id) || (old != buffers_->entries.end() && old->second.bricksBuilt);
    if (entry.bricksBuilt) {
      entry.bricks = bricksOf(*asset, buffers_->entries);
      entry.cones = conesOf(*asset, entry.bricks, buffers_->entries);
    }
    cones.insert(cones.end(), entry.cones.begin(), entry.cones.end());
    entry.cellConesBuilt =
        asCulledCells.contains(asset->id) || (old != buffers_->entries.end() && old->second.cellConesBuilt);
    if (entry.cellConesBuilt) {
      entry.cellCones = cellConesOf(*asset, buffers_->entries);
      cellCones.insert(cellCones.end(), entry.cellCones.begin(), entry.cellCones.end());
    } else {
      cellCones.resize(cellCones.size() + asset->cells.records.size(), neverCullCone());
    }
    entry.firstBrick = static_cast<std::uint32_t>(bricks.size());
    for (shader::CellBrickGpu brick : entry.bricks.bricks) {
      brick.firstIndex += static_cast<std::uint32_t>(brickCells.size());
      bricks.push_back(brick);
    }
    for (std::uint32_t record : entry.bricks.cellRecords) brickCells.push_back(entry.firstRecord + record);
    full.insert(full.end(), asset->cells.records.begin(), asset->cells.records.end());
    half.insert(half.end(), asset->cellsHalf.records.begin(), asset->cellsHalf.records.end());
    rebuilt.entries.emplace(asset->id, std::move(entry));
  }
  // Vertex attributes in the prepass; read by address in the resolve pass.
  constexpr VkBufferUsageFlags usage = VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                       VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
  try {
    rebuilt.records[0] = engine::gpu::createBufferWithData(*context_, full.data(), full.size() * sizeof(CellRecord),
                                                           usage, "hermite cells fp32");
    rebuilt.records[1] = engine::gpu::createBufferWithData(*context_, half.data(),
                                                           half.size() * sizeof(CellRecordHalf), usage,
                                                           "hermite cells fp16");
    rebuilt.runs = engine::gpu::createBufferWithData(*context_, runs.data(), runs.size() * sizeof(shader::CellRunGpu),
                                                     VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, "hermite cell runs");
    // Never empty (a zero-sized buffer is invalid): a padding entry no draw reaches.
    if (bricks.empty()) bricks.push_back({});
    if (brickCells.empty()) brickCells.push_back(0);
    if (cones.empty()) cones.push_back({});
    if (cellCones.empty()) cellCones.push_back({});
    rebuilt.bricks = engine::gpu::createBufferWithData(*context_, bricks.data(), bricks.size() * sizeof(shader::CellBrickGpu),
                                                       usage, "hermite cell bricks");
    rebuilt.brickCells = engine::gpu::createBufferWithData(
        *context_, brickCells.data(), brickCells.size() * sizeof(std::uint32_t),
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT, "hermite cell brick cells");
    rebuilt.brickCones = engine::gpu::createBufferWithData(
        *context_, cones.data(), cones.size() * sizeof(shader::CellBrickCone),
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT, "hermite cell brick cones");
    rebuilt.cellCones = engine::gpu::createBufferWithData(
        *context_, cellCones.data(), cellCones.size() * sizeof(shader::CellBrickCone),
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT, "hermite cell cones");
  } catch (const engine::gpu::VulkanError& e) {
    if (e.result() != VK_ERROR_OUT_OF_DEVICE_MEMORY) throw;
    refuseNewAssets(frame, wanted, e.what());  // the old buffers stay: what was drawn is drawn
    return;
  }
  // Only now: a failed allocation above must leave the old entries whole.
  for (auto& [id, entry] : rebuilt.entries)
    if (auto old = buffers_->entries.find(id); old != buffers_->entries.end()) entry.rows = std::move(old->second.rows);
  rebuilt.runLength = settings_.maxRunLength;
  rebuilt.bytes = full.size() * sizeof(CellRecord) + half.size() * sizeof(CellRecordHalf) +
                  runs.size() * sizeof(shader::CellRunGpu) + bricks.size() * sizeof(shader::CellBrickGpu) +
                  brickCells.size() * sizeof(std::uint32_t) +
                  (cones.size() + cellCones.size()) * sizeof(shader::CellBrickCone);
  for (auto& [id, entry] : rebuilt.entries) entry.lastFrame = frame.frameNumber;
  retired_.retire(std::move(buffers_), frame.frameNumber);
  buffers_ = std::make_unique<CellBuffers>(std::move(rebuilt));
  engine::log::debug("hermite cells: {} assets, {} records uploaded", buffers_->entries.size(), full.size());
}

// The rebuilt buffers did not fit in GPU memory. The assets this rebuild was for (new ones, or a
// new run length) are refused for good, each reported once, so later frames neither retry nor
// report them again; the assets already uploaded keep drawing from the old buffers.
void HermiteCellFeature::refuseNewAssets(const engine::render::FrameContext& frame,
                                         const std::vector<std::shared_ptr<const SdfAsset>>& wanted,
                                         const std::string& why) {
  bool refusedAny = false;
  for (const auto& asset : wanted) {
    if (buffers_->entries.contains(asset->id)) continue;
    refused_.insert(asset->id);
    refusedAny = true;
    frame.reportDropped(fmt::format("hermite cells: '{}' ({} cells) is not drawn: out of GPU memory ({})", asset->name,
                                    asset->cells.records.size(), why));
  }
  if (refusedAny) return;
  refusedRunLength_ = settings_.maxRunLength;
  frame.reportDropped(fmt::format("hermite cells: cell runs of length {} are not built: out of GPU memory ({}); the "
                                  "runs of length {} stay",
                                  settings_.maxRunLength, why, buffers_->runLength));
}

void HermiteCellFeature::buildDraws(engine::render::FrameContext& frame) {
  std::vector<VkDrawIndirectCommand> commands[kBatches][2];  // [fp32 cells, fp16 cells, runs, bricks][front, near]
  std::vector<shader::HermiteDraw> draws[kBatches][2];
  std::vector<shader::HermiteObject> hermiteObjects;
  std::vector<std::uint32_t> objectIndices;
  stats_ = Stats{};
  cullObjectList_.clear();
  cullOutputBricks_ = 0;
  cullMaxBricks_ = 0;
  cellCullObjects_.clear();
  cellCullEntities_.clear();
  cellCullFirstRecord_.clear();
  cellCullCells_.clear();
  std::vector<std::uint32_t> cellCullObject[2];  // per front command of the cell batches: its cull object or kNotCulled
  for (int precision = 0; precision < 2; ++precision) {
    cellCullRanges_[precision].clear();
    cellCullOutput_[precision] = 0;
  }
  stats_.gpuBytes = buffers_->bytes;
  screenRect_ = glm::vec4(1.0f, 1.0f, -1.0f, -1.0f);  // empty until an object is drawn
  std::vector<glm::vec4> objectRects;
  bool objectsOverlap = false;  // two cell objects share screen pixels: no early depth (see the header)
  bool drawsBricks = false;     // bricks have no early depth variant: none this frame
  float largestCellPixels = 0.0f;  // of the RenderMethod::Cells objects (ThinBoxes::Auto)
  std::unordered_map<engine::ecs::Entity, std::uint64_t> drawnThisFrame;
  const glm::mat4 viewProj = frame.camera.proj * frame.camera.view;

  frame.registry.view<HermiteSdfRenderable, engine::scene::WorldTransform>().each(
      [&](engine::ecs::Entity entity, const HermiteSdfRenderable& r, const engine::scene::WorldTransform& world) {
        if (!drawnAsCells(r.method) || !r.asset) return;
        if (!engine::render::drawableTransform(world.matrix)) {  // the rays could not be taken into the grid
          stats_.skippedObjects++;
          return;
        }
        auto found = buffers_->entries.find(r.asset->id);
        // A refused asset (its upload did not fit in GPU memory) that replaced the entity's field:
        // the field it replaced is still uploaded and is drawn instead, from this very frame on.
        if (found == buffers_->entries.end() && refused_.contains(r.asset->id))
          if (auto previous = drawnAssets_.find(entity); previous != drawnAssets_.end())
            found = buffers_->entries.find(previous->second);
        if (found == buffers_->entries.end()) return;
        drawnThisFrame[entity] = found->first;
        const CellBuffers::Entry& entry = found->second;
        const SdfAsset& asset = *entry.asset;
        const GridSpec& grid = asset.cells.grid;  // cells-only assets have no dense field
        const int precision = r.halfPrecision && halfPrecisionFits(grid) ? 1 : 0;  // else fp32, see renderable.h

        shader::ObjectData object = engine::render::GpuScene::makeObject(world.matrix, r.color, r.roughness, 0.0f, kFeatureId);
        const std::uint32_t objectIndex = frame.scene.addObject(object);
        shader::HermiteDraw draw{};
        draw.gridOriginSpacing = glm::vec4(glm::vec3(grid.origin), float(grid.spacing));
        draw.object = objectIndex;
        draw.subdivisions = std::clamp(r.subdivisions, 1u, 64u);
        draw.refineSteps = std::min(r.refineSteps, 16u);
        draw.flags = r.normals == NormalMode::CentralDifferences ? HERMITE_FLAG_NORMALS_CENTRAL : 0u;
        if (r.certified) draw.flags |= HERMITE_FLAG_CERTIFIED;
        draw.resolution = std::uint32_t(grid.resolution);
        draw.firstCell = entry.firstRecord;
        hermiteObjects.push_back({draw.gridOriginSpacing, buffers_->records[precision].address(),
                                  std::uint32_t(precision), draw.flags});
        objectIndices.push_back(objectIndex);

        // The eye in grid units, and how far (in grid units) the near plane reaches around it.
        const glm::vec3 eyeObject = glm::vec3(object.invModel * glm::vec4(frame.camera.position, 1.0f));
        const glm::dvec3 eyeGrid = (glm::dvec3(eyeObject) - grid.origin) / grid.spacing;
        const double reachGrid = double(frame.camera.nearPlaneReachInObject(object.invModel)) / grid.spacing;

        const glm::vec4 rect = screenBounds(viewProj, world.matrix, grid.bounds(), frame.extent);
        for (const glm::vec4& other : objectRects)
          objectsOverlap |= rect.x < other.z && other.x < rect.z && rect.y < other.w && other.y < rect.w;
        objectRects.push_back(rect);
        screenRect_ = unite(screenRect_, rect);
        stats_.objects++;
        // Runs, bricks and thin cells read their records by address: the draw says which buffer and
        // which precision (the paper's cells ignore it: their records are vertex attributes).
        draw.records = buffers_->records[precision].address();
        if (precision == 1) draw.flags |= HERMITE_FLAG_HALF_RECORDS;
        if (r.method == RenderMethod::CellBricks) {
          drawsBricks = true;
          stats_.cells += asset.cells.records.size();
          addBrickDraws(entry.bricks.bricks, entry.firstBrick, draw, eyeGrid, reachGrid, commands[kBrickBatch],
                        draws[kBrickBatch]);
          if (settings_.cullBricks && !entry.bricks.bricks.empty()) {
            // The command just added starts empty and the culling pass counts its kept bricks, which
            // it writes from the object's range of the kept-brick stream on.
            VkDrawIndirectCommand& command = commands[kBrickBatch][0].back();
            BrickCuller::ObjectBricks range{entry.firstBrick, command.instanceCount, cullOutputBricks_,
                                            std::uint32_t(commands[kBrickBatch][0].size() - 1)};
            cullObjectList_.push_back(
                BrickCuller::cullObject(frame.camera, world.matrix, grid, asset.boundaryPositive, range));
            cullOutputBricks_ += command.instanceCount;
            cullMaxBricks_ = std::max(cullMaxBricks_, command.instanceCount);
            command.instanceCount = 0;
            command.firstInstance = range.outputFirst;
          }
          return;
        }
        if (r.method == RenderMethod::CellRuns) {
          const std::vector<CellRows::Range> rowOrder = orderedRows(entry.rows, eyeGrid, settings_.frontToBack);
          for (const CellRows::Range& range : runRanges(entry.runs, rowOrder)) {
            commands[2][0].push_back({kFanVertices, range.count, 0, entry.firstRun + range.first});
            draws[2][0].push_back(draw);
          }
          shader::HermiteDraw nearDraw = draw;
          nearDraw.flags |= HERMITE_FLAG_NEAR_CELL;
          for (std::uint32_t run : runsNearPoint(entry.runs, eyeGrid, reachGrid)) {
            commands[2][1].push_back({kStripVertices, 1, 0, entry.firstRun + run});
            draws[2][1].push_back(nearDraw);
            stats_.nearCells++;
          }
          stats_.cells += asset.cells.records.size();
          stats_.runs += entry.runs.size();
          return;
        }
        largestCellPixels = std::max(largestCellPixels, cellPixelsOnScreen(grid, world.matrix, frame.camera, frame.extent.height));
        // Culled cells: the object's rows become ranges of the culling pass (cullCellRanges), which
        // reads the object's frustum, eye and cone permission from its BrickCullObject.
        std::uint32_t cullObject = kNotCulled;
        if (settings_.cullCells) {
          cullObject = std::uint32_t(cellCullObjects_.size());
          cellCullObjects_.push_back(
              BrickCuller::cullObject(frame.camera, world.matrix, grid, asset.boundaryPositive, {}));
          cellCullEntities_.emplace_back(entity, found->first);
          cellCullFirstRecord_.push_back(entry.firstRecord);
          cellCullCells_.push_back(std::uint32_t(asset.cells.records.size()));
        }
        for (const CellRows::Range& range : orderedRows(entry.rows, eyeGrid, settings_.frontToBack)) {
          commands[precision][0].push_back({kFanVertices, range.count, 0, entry.firstRecord + range.first});
          draws[precision][0].push_back(draw);
          cellCullObject[precision].push_back(cullObject);
          stats_.cells += range.count;
        }
        shader::HermiteDraw nearDraw = draw;
        nearDraw.flags |= HERMITE_FLAG_NEAR_CELL;
        for (std::uint32_t record : cellsNearPoint(entry.rows, asset.cells, eyeGrid, reachGrid)) {
          commands[precision][1].push_back({kStripVertices, 1, 0, entry.firstRecord + record});
          draws[precision][1].push_back(nearDraw);
          stats_.nearCells++;
        }
      });

  // One upload: [fp32 front][fp32 near][fp16 front][fp16 near][runs front][runs near][bricks front][bricks near].
  std::vector<VkDrawIndirectCommand> allCommands;
  std::vector<shader::HermiteDraw> allDraws;
  for (int precision = 0; precision < kBatches; ++precision) {
    Batch& batch = *batches_[precision];
    batch.frontFirst = static_cast<std::uint32_t>(allCommands.size());
    batch.frontCount = static_cast<std::uint32_t>(commands[precision][0].size());
    allCommands.insert(allCommands.end(), commands[precision][0].begin(), commands[precision][0].end());
    allDraws.insert(allDraws.end(), draws[precision][0].begin(), draws[precision][0].end());
    batch.nearFirst = static_cast<std::uint32_t>(allCommands.size());
    batch.nearCount = static_cast<std::uint32_t>(commands[precision][1].size());
    allCommands.insert(allCommands.end(), commands[precision][1].begin(), commands[precision][1].end());
    allDraws.insert(allDraws.end(), draws[precision][1].begin(), draws[precision][1].end());
  }
  stats_.draws = static_cast<std::uint32_t>(allCommands.size());
  for (shader::BrickCullObject& object : cullObjectList_) object.drawCommand += batches_[kBrickBatch]->frontFirst;
  drawnAssets_ = std::move(drawnThisFrame);
  if (frame.debugView == DEBUG_VIEW_WIREFRAME) {
    for (int precision = 0; precision < 2; ++precision) {
      Batch& batch = *batches_[precision];
      batch.wireFirst = static_cast<std::uint32_t>(allCommands.size());
      for (std::uint32_t i = 0; i < batch.frontCount; ++i) {
        VkDrawIndirectCommand wire = allCommands[batch.frontFirst + i];
        wire.vertexCount = kWireVertices;
        allCommands.push_back(wire);
        allDraws.push_back(allDraws[batch.frontFirst + i]);
      }
    }
  }
  occlusion_ = settings_.cullCells && settings_.cullOcclusion && !cellCullObjects_.empty();
  if (occlusion_) placeHistory(frame);
  cullCellRanges(allCommands, cellCullObject);  // after the wireframe's copies, which draw every cell
  if (occlusion_) addLateCommands(allCommands, allDraws);
  thinBoxes_ = thinBoxesWanted(settings_.thinBoxes, context_->capabilities().isSoftwareRasterizer, largestCellPixels);
  stats_.thinBoxes = thinBoxes_;
  stats_.largestCellPixels = largestCellPixels;
  // Occlusion culling keeps the early depth stage off: the stage leaves the boxes' face depths in
  // the depth buffer until its fix-up, so phase 1 would need its fix-up before the pyramid and
  // phase 2 an early stage and a fix-up of its own over pixels that phase 1 already made final.
  // Culling removes the hidden boxes the stage only made cheaper (on lavapipe; on GPUs the stage
  // gains nothing, issue 20).
  earlyDepth_ = earlyDepthWanted(settings_.earlyDepth, context_->capabilities().isSoftwareRasterizer) &&
                stats_.draws > 0 && !objectsOverlap && !drawsBricks && !thinBoxes_ && !occlusion_;
  if (!allCommands.empty()) {
    indirect_.upload(frame.frameSlot, allCommands);
    drawData_.upload(frame.frameSlot, allDraws);
  }
  if (!hermiteObjects.empty()) {
    objects_.upload(frame.frameSlot, hermiteObjects);
    const VkDeviceAddress base = objects_.address(frame.frameSlot);
    for (std::size_t i = 0; i < objectIndices.size(); ++i)
      frame.scene.object(objectIndices[i]).payload = base + i * sizeof(shader::HermiteObject);
  }
}

// The front-face commands of culled cells (cullObjects: per command of the two cell batches) become
// the culling pass's ranges: each command then draws its range of the kept-cell stream, from an
// instance count of 0 that the pass overwrites. The ranges take the commands' order, so the rows
// stay front to back.
void HermiteCellFeature::cullCellRanges(std::vector<VkDrawIndirectCommand>& commands,
                                        const std::vector<std::uint32_t> cullObjects[2]) {
  for (int precision = 0; precision < 2; ++precision) {
    const Batch& batch = *batches_[precision];
    for (std::uint32_t i = 0; i < batch.frontCount; ++i) {
      if (cullObjects[precision][i] == kNotCulled) continue;
      VkDrawIndirectCommand& command = commands[batch.frontFirst + i];
      const std::uint32_t object = cullObjects[precision][i];
      // The range's first cell in the history: its object's base plus the cell's index in its asset.
      const std::uint32_t historyFirst =
          occlusion_ ? historyBase_[object] + (command.firstInstance - cellCullFirstRecord_[object]) : 0;
      const shader::CellCullRange range{command.firstInstance, command.instanceCount, cellCullOutput_[precision],
                                        batch.frontFirst + i, object, historyFirst, 0, 0};
      cellCullRanges_[precision].push_back(range);
      cellCullOutput_[precision] += command.instanceCount;
      command.instanceCount = 0;
      command.firstInstance = range.outputFirst;
    }
  }
}

// This view region's places in the visibility history for this frame's culled objects.
void HermiteCellFeature::placeHistory(engine::render::FrameContext& frame) {
  std::vector<CellHistory::Object> objects;
  for (std::size_t i = 0; i < cellCullEntities_.size(); ++i)
    objects.push_back({cellCullEntities_[i].first, cellCullEntities_[i].second, cellCullCells_[i]});
  const std::uint32_t regions = std::max(1u, frameSlots_ / std::max(1u, frame.framesInFlight));
  historyBase_ = history_->place(*context_, frame.cmd, objects, frame.frameSlot % regions, regions,
                                 frame.frameNumber, retired_);
}

// Phase 2's commands: the culled front lists again (every front command of the two cell batches is
// culled when occlusion culling is on), each drawing its range of the second half of the kept
// stream, from an instance count of 0 that the late culling pass overwrites.
void HermiteCellFeature::addLateCommands(std::vector<VkDrawIndirectCommand>& commands,
                                         std::vector<shader::HermiteDraw>& draws) {
  for (int precision = 0; precision < 2; ++precision) {
    Batch& batch = *batches_[precision];
    batch.lateFirst = static_cast<std::uint32_t>(commands.size());
    for (std::uint32_t i = 0; i < batch.frontCount; ++i) {
      VkDrawIndirectCommand late = commands[batch.frontFirst + i];
      late.firstInstance += cellCullOutput_[precision];
      commands.push_back(late);
      draws.push_back(draws[batch.frontFirst + i]);
    }
  }
}

// The size on screen, in pixels, of one cell of `grid` placed by `world`, seen from the camera at
// the distance of the grid box's centre (ThinBoxes::Auto: a typical cell of the object, not its
// nearest one as the levels of detail take).
float HermiteCellFeature::cellPixelsOnScreen(const GridSpec& grid, const glm::mat4& world,
                                             const engine::render::CameraView& camera, std::uint32_t viewportHeight) {
  const float scale = largestAxisScale(world);
  const glm::vec3 centre = glm::vec3(world * glm::vec4(glm::vec3(grid.bounds().center()), 1.0f));
  return projectedPixels(scale * float(grid.spacing), glm::length(camera.position - centre), camera.fovY, viewportHeight);
}

// A CellBricks object: one command for all its bricks (firstInstance = its first brick; the brick
// culling pass will write instanceCount), and the bricks the near plane may cut by back faces.
void HermiteCellFeature::addBrickDraws(const std::vector<shader::CellBrickGpu>& bricks, std::uint32_t firstBrick,
                                       const shader::HermiteDraw& draw, const glm::dvec3& eyeGrid, double reachGrid,
                                       std::vector<VkDrawIndirectCommand> commands[2],
                                       std::vector<shader::HermiteDraw> draws[2]) {
  const auto count = static_cast<std::uint32_t>(bricks.size());
  if (count == 0) return;  // reported when the bricks could not be built
  commands[0].push_back({kFanVertices, count, 0, firstBrick});
  draws[0].push_back(draw);
  shader::HermiteDraw nearDraw = draw;
  nearDraw.flags |= HERMITE_FLAG_NEAR_CELL;
  for (std::uint32_t brick : bricksNearPoint(bricks, eyeGrid, reachGrid)) {
    commands[1].push_back({kStripVertices, 1, 0, firstBrick + brick});
    draws[1].push_back(nearDraw);
    stats_.nearCells++;
  }
  stats_.bricks += count;
}

void HermiteCellFeature::ensureCounters(engine::render::FrameContext& frame) {
  countersActive_ = settings_.heatMapCounters && frame.debugView == DEBUG_VIEW_EVALS && stats_.draws > 0;
  if (!countersActive_) return;
  counters_.ensure(*context_, frame.extent);
  // Earlier frames read the counters in their shading pass; this frame rewrites them.
  engine::gpu::memoryBarrier(frame.cmd, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                             VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  vkCmdFillBuffer(frame.cmd, counters_.handle(), 0, VK_WHOLE_SIZE, 0);
  engine::gpu::memoryBarrier(frame.cmd, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                             VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, kStorageReadWrite);
}

void HermiteCellFeature::prepare(engine::render::FrameContext& frame) {
  retired_.collect(frame.frameNumber, frame.framesInFlight);
  syncAssets(frame);
  buildDraws(frame);
  recordCulling(frame);
  ensureCounters(frame);
  ensureHitDepths(frame);
  stats_.earlyDepth = earlyDepth_;
  stats_.countedVariant = stats_.draws > 0 && prepassVariant(frame) == kCounted;
}

// The culling passes of this frame slot, bricks and cells, which add up their counts in the slot's
// totals. The totals of the slot's previous passes are complete now (its submission was waited
// for): they become the stats.
void HermiteCellFeature::recordCulling(engine::render::FrameContext& frame) {
  lastCullSlot_ = frame.frameSlot;
  if (cullObjectList_.empty() && cellCullObjects_.empty()) return;
  cullTotals_.upload(frame.frameSlot, std::vector<shader::BrickCullTotals>(1));
  recordBrickCulling(frame);
  recordCellCulling(frame);
}

// The brick culling pass of this frame slot (brick_culler.h): every culled object's bricks tested
// against the frustum and its normal cones, the kept ones written to the slot's kept-brick stream,
// which the bricks' front-face draws then read instead of the asset buffer.
void HermiteCellFeature::recordBrickCulling(engine::render::FrameContext& frame) {
  if (cullObjectList_.empty()) return;
  cullObjects_.upload(frame.frameSlot, cullObjectList_);
  Buffer& kept = ensureOutput(*context_, keptBricks_[frame.frameSlot],
                              VkDeviceSize(cullOutputBricks_) * sizeof(shader::CellBrickGpu),
                              VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, "hermite kept bricks");
  culler_->record(frame.cmd,
                 {cullObjects_.address(frame.frameSlot), buffers_->bricks.address(), buffers_->brickCones.address(),
                  kept.address(), indirect_.address(frame.frameSlot), cullTotals_.address(frame.frameSlot)},
                 std::uint32_t(cullObjectList_.size()), cullMaxBricks_);
}

// The cell culling pass (cell_cull.comp) of this frame slot: one dispatch per record precision
// over its ranges, writing the slot's kept records (the front faces' vertex stream instead of the
// record buffer), their record indices and the commands' instance counts.
void HermiteCellFeature::recordCellCulling(engine::render::FrameContext& frame) {
  std::vector<shader::CellCullRange> ranges = cellCullRanges_[0];
  ranges.insert(ranges.end(), cellCullRanges_[1].begin(), cellCullRanges_[1].end());
  if (ranges.empty()) return;
  const std::uint32_t slot = frame.frameSlot;
  cellCullObjectBuffer_.upload(slot, cellCullObjects_);
  cellCullRangeBuffer_.upload(slot, ranges);
  barrierBeforeCulling(frame.cmd);
  shader::CellCullPushConstants push{};
  if (occlusion_) {
    // The previous frame's phase 2 wrote the history this phase 1 reads.
    engine::gpu::memoryBarrier(frame.cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                               VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, kStorageReadWrite);
    push.history = history_->address();
    push.phase = CELL_CULL_PHASE_EARLY;
  }
  recordCellCullPasses(frame.cmd, slot, push);
  barrierAfterCulling(frame.cmd);
}

// The relative depth margin of the occlusion test (CellCullPushConstants::depthMargin). A hit lies
// at most the search margin beyond its cell: 0.02 pixel of dilation (taken as 0.1 pixel: a depth
// along the ray, any direction), or kMinDilation = 1/4096 cell. At a distance d, p pixels are
// p * 2 d / (proj[1][1] H) world units, a relative depth change of p * 2 / (proj[1][1] H) under
// reverse-Z (depth ~ 1 / d); 1/4096 of a cell is at most ~1e-3 of its distance for any cell not
// larger on screen than the view (taken as 2e-3).
float HermiteCellFeature::occlusionDepthMargin(const engine::render::CameraView& camera, VkExtent2D extent) {
  const float pixelAngle = 2.0f / (std::abs(camera.proj[1][1]) * float(std::max(extent.height, 1u)));
  return 0.1f * pixelAngle + 2.0e-3f;
}

// Occlusion culling's phase 2 (after the renderer built the pyramid of phase 1's depth): every
// culled cell tested against it, the history updated, the visible cells phase 1 did not draw
// written to the second half of the kept streams and counted in the late commands.
void HermiteCellFeature::recordLateCulling(engine::render::PassContext& pass,
                                           const engine::render::DepthPyramidView& pyramid) {
  if (!occlusion_) return;
  pass.timer.begin(pass.cmd, "cells late culling");
  barrierBeforeCulling(pass.cmd);
  // Phase 1 read the history and wrote the first halves of the streams and the commands.
  engine::gpu::memoryBarrier(pass.cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, kStorageReadWrite,
                             VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, kStorageReadWrite);
  shader::CellCullPushConstants push{};
  push.history = history_->address();
  push.pyramid = pyramid.address;
  push.pyramidWidth = pyramid.extent.width;
  push.pyramidHeight = pyramid.extent.height;
  push.pyramidLevels = pyramid.levels;
  push.phase = CELL_CULL_PHASE_LATE;
  push.depthMargin = occlusionDepthMargin(pass.frame.camera, pyramid.extent);
  recordCellCullPasses(pass.cmd, pass.frame.frameSlot, push);
  barrierAfterCulling(pass.cmd);
  pass.timer.end(pass.cmd);
}

// One cell_cull.comp dispatch per record precision over its ranges, with the slot's buffers; the
// phase and occlusion fields of `push` as the caller set them. Phase 2 writes its commands and
// kept cells after phase 1's.
void HermiteCellFeature::recordCellCullPasses(VkCommandBuffer cmd, std::uint32_t slot,
                                              shader::CellCullPushConstants push) {
  VkDeviceAddress rangeAddress = cellCullRangeBuffer_.address(slot);
  const bool late = push.phase == CELL_CULL_PHASE_LATE;
  for (int precision = 0; precision < 2; ++precision) {
    const auto rangeCount = static_cast<std::uint32_t>(cellCullRanges_[precision].size());
    if (rangeCount == 0) continue;
    const VkDeviceSize kept = VkDeviceSize(cellCullOutput_[precision]) * (occlusion_ ? 2 : 1);
    const Buffer& records = ensureOutput(*context_, keptCellRecords_[slot][precision], kept * kRecordStride[precision],
                                         VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, "hermite kept cells");
    const Buffer& indices = ensureOutput(*context_, keptCellIndices_[slot][precision], kept * sizeof(std::uint32_t), 0,
                                         "hermite kept cell indices");
    push.objects = cellCullObjectBuffer_.address(slot);
    push.ranges = rangeAddress;
    push.records = buffers_->records[precision].address();
    push.cones = buffers_->cellCones.address();
    push.keptRecords = records.address();
    push.keptIndices = indices.address();
    push.commands = indirect_.address(slot);
    push.totals = cullTotals_.address(slot);
    push.rangeCount = rangeCount;
    push.recordWords = kRecordStride[precision] / 4;
    const Batch& batch = *batches_[precision];
    push.commandOffset = late ? batch.lateFirst - batch.frontFirst : 0;
    push.outputOffset = late ? cellCullOutput_[precision] : 0;
    cellCuller_->record(cmd, push);
    rangeAddress += VkDeviceAddress(rangeCount) * sizeof(shader::CellCullRange);
  }
}

shader::BrickCullTotals HermiteCellFeature::cullTotals() const {
  shader::BrickCullTotals totals{};
  const Buffer& buffer = cullTotals_.buffer(lastCullSlot_);
  const bool culled = !cullObjectList_.empty() || !cellCullObjects_.empty();
  if (culled && buffer && buffer.mapped()) std::memcpy(&totals, buffer.mapped(), sizeof(totals));
  return totals;
}

// The per-pixel hit depths of the early depth stage, zero between frames (the fix-up clears what
// it read). A buffer that cannot be allocated turns early depth off, the frame still draws.
void HermiteCellFeature::ensureHitDepths(engine::render::FrameContext& frame) {
  if (!earlyDepth_) return;
  VkCommandBuffer cmd = frame.cmd;
  bool made = false;
  try {
    made = hitDepths_.ensure(*context_, frame.extent);
  } catch (const engine::gpu::VulkanError& e) {
    if (e.result() != VK_ERROR_OUT_OF_DEVICE_MEMORY) throw;
    engine::log::warn("hermite cells: no early depth this frame: {}", e.what());
    earlyDepth_ = false;
    return;
  }
  if (made) {
    vkCmdFillBuffer(cmd, hitDepths_.handle(), 0, VK_WHOLE_SIZE, 0);
    engine::gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                               VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, kStorageReadWrite);
    return;
  }
  // The previous frame's (or view region's) fix-up cleared the pixels it read; this frame's early
  // fragments write them again.
  engine::gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                             VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, kStorageReadWrite);
}

// The production pipelines unless the frame counts work or draws the early depth stage (whose
// variants count when pc.counters is set: they hold buffer writes anyway). The counted variants
// then draw the same image as the production ones, and count what they counted before.
HermiteCellFeature::Variant HermiteCellFeature::prepassVariant(const engine::render::FrameContext& frame) const {
  if (earlyDepth_) return kEarly;
  return counterAddress(frame, countersActive_, counters_) != 0 ? kCounted : kProduction;
}

void HermiteCellFeature::recordBatch(engine::render::PassContext& pass, int precision, bool near, bool late) {
  const Batch& batch = *batches_[precision];
  const std::uint32_t first = late ? batch.lateFirst : near ? batch.nearFirst : batch.frontFirst;
  const std::uint32_t count = near ? batch.nearCount : batch.frontCount;
  if (count == 0) return;
  VkCommandBuffer cmd = pass.cmd;
  const bool runs = precision == kRunBatch;
  const bool bricks = precision == kBrickBatch;
  const Variant variant = prepassVariant(pass.frame);
  const int noEarly = withoutEarlyStage(variant);
  const Pipeline& pipeline = bricks ? (near ? pipelines_.bricksNear[noEarly] : pipelines_.bricksFront[noEarly])
                             : runs ? (near ? pipelines_.runsNear[variant] : pipelines_.runsFront[variant])
                             : thinBoxes_ ? (near ? pipelines_.thinNear[noEarly][precision]
                                                  : pipelines_.thinFront[noEarly][precision])
                                    : (near ? pipelines_.depthNear[variant][precision]
                                            : pipelines_.depthFront[variant][precision]);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.handle());
  const VkBuffer vertexBuffer = bricks ? buffers_->bricks.handle()
                                : runs ? buffers_->runs.handle()
                                       : buffers_->records[precision].handle();
  const VkDeviceSize offset = 0;
  vkCmdBindVertexBuffers(cmd, 0, 1, &vertexBuffer, &offset);

  shader::HermitePushConstants push{};
  push.draw.frameGlobals = pass.frameGlobals;
  push.draw.objects = pass.objects;
  push.draw.debugView = pass.frame.debugView;
  push.draws = drawData_.address(pass.frame.frameSlot);
  push.counters = counterAddress(pass.frame, countersActive_, counters_);
  push.hitDepths = earlyDepth_ ? hitDepths_.address() : 0;
  if (bricks && !near && !cullObjectList_.empty()) {
    // The front faces draw the culling pass's kept bricks (the near list: every near brick).
    const Buffer& kept = keptBricks_[pass.frame.frameSlot];
    const VkBuffer keptBuffer = kept.handle();
    vkCmdBindVertexBuffers(cmd, 0, 1, &keptBuffer, &offset);
    push.bricks = kept.address();
    push.brickCells = buffers_->brickCells.address();
  } else if (bricks) {
    push.bricks = buffers_->bricks.address();
    push.brickCells = buffers_->brickCells.address();
  } else if (!runs && !near && !cellCullRanges_[precision].empty()) {
    // The front faces draw the cell culling pass's kept records (the near list: every near cell).
    const VkBuffer keptBuffer = keptCellRecords_[pass.frame.frameSlot][precision].handle();
    vkCmdBindVertexBuffers(cmd, 0, 1, &keptBuffer, &offset);
    push.cellRecords = keptCellIndices_[pass.frame.frameSlot][precision].address();
  }
  recordIndirect(cmd, pipeline, push, pass.frame.frameSlot, first, count);
}

HermiteCellFeature::Variant HermiteCellFeature::withoutEarlyStage(Variant variant) {
  return variant == kCounted ? kCounted : kProduction;
}

void HermiteCellFeature::recordIndirect(VkCommandBuffer cmd, const Pipeline& pipeline, shader::HermitePushConstants push,
                                        std::uint32_t frameSlot, std::uint32_t first, std::uint32_t count) {
  const VkBuffer indirect = indirect_.buffer(frameSlot).handle();
  constexpr auto stride = static_cast<std::uint32_t>(sizeof(VkDrawIndirectCommand));
  const VkShaderStageFlags stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
  if (multiDraw_) {
    push.drawBase = first;
    vkCmdPushConstants(cmd, pipeline.layout(), stages, 0, sizeof(push), &push);
    vkCmdDrawIndirect(cmd, indirect, VkDeviceSize(first) * stride, count, stride);
    return;
  }
  for (std::uint32_t i = 0; i < count; ++i) {  // gl_DrawID is 0 in each single draw
    push.drawBase = first + i;
    vkCmdPushConstants(cmd, pipeline.layout(), stages, 0, sizeof(push), &push);
    vkCmdDrawIndirect(cmd, indirect, VkDeviceSize(first + i) * stride, 1, stride);
  }
}

void HermiteCellFeature::recordWireframe(engine::render::PassContext& pass, int precision) {
  const Batch& batch = *batches_[precision];
  if (batch.frontCount == 0) return;
  VkCommandBuffer cmd = pass.cmd;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelines_.wire[precision].handle());
  const VkBuffer vertexBuffer = buffers_->records[precision].handle();
  const VkDeviceSize offset = 0;
  vkCmdBindVertexBuffers(cmd, 0, 1, &vertexBuffer, &offset);
  shader::HermitePushConstants push{};
  push.draw.frameGlobals = pass.frameGlobals;
  push.draw.objects = pass.objects;
  push.draws = drawData_.address(pass.frame.frameSlot);
  recordIndirect(cmd, pipelines_.wire[precision], push, pass.frame.frameSlot, batch.wireFirst, batch.frontCount);
}

void HermiteCellFeature::recordResolve(engine::render::PassContext& pass) {
  recordRectangle(pass, pipelines_.resolve);
}

// The rectangle over the cell objects' screen bounds (cells_resolve.vert) with `pipeline`: the
// shading resolve (which reads the scene set) or the early depth fix-up.
void HermiteCellFeature::recordRectangle(engine::render::PassContext& pass, const Pipeline& pipeline) {
  if (!(screenRect_.x < screenRect_.z && screenRect_.y < screenRect_.w)) return;  // no object on screen
  VkCommandBuffer cmd = pass.cmd;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.handle());
  if (pass.pass == engine::render::Pass::Opaque)
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.layout(), 0, 1, &pass.sceneSet, 0, nullptr);
  shader::HermitePushConstants push{};
  push.draw.frameGlobals = pass.frameGlobals;
  push.draw.objects = pass.objects;
  push.draw.debugView = pass.frame.debugView;
  push.counters = counterAddress(pass.frame, countersActive_, counters_);
  push.hitDepths = earlyDepth_ ? hitDepths_.address() : 0;
  push.screenRect = screenRect_;
  vkCmdPushConstants(cmd, pipeline.layout(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                     sizeof(push), &push);
  vkCmdDraw(cmd, 6, 1, 0, 0);
}

void HermiteCellFeature::recordPass(engine::render::PassContext& pass) {
  if (stats_.draws == 0) return;
  if (pass.pass == engine::render::Pass::Opaque) {
    pass.timer.begin(pass.cmd, "cells shading");
    recordResolve(pass);
    if (pass.frame.debugView == DEBUG_VIEW_WIREFRAME)
      for (int precision = 0; precision < 2; ++precision) recordWireframe(pass, precision);
    pass.timer.end(pass.cmd);
    return;
  }
  if (pass.occlusionLate) {  // phase 2 of occlusion culling: the culled cells' late commands only
    pass.timer.begin(pass.cmd, "cells prepass late");
    for (int precision = 0; precision < 2; ++precision) recordBatch(pass, precision, false, true);
    pass.timer.end(pass.cmd);
    return;
  }
  if (!earlyDepth_) recordPrepassDraws(pass);  // else drawn in the early depth stage
}

void HermiteCellFeature::recordEarlyDepth(engine::render::PassContext& pass) {
  if (stats_.draws > 0) recordPrepassDraws(pass);
}

void HermiteCellFeature::recordEarlyDepthResolve(engine::render::PassContext& pass) {
  if (stats_.draws == 0) return;
  pass.timer.begin(pass.cmd, "cells depth fix-up");
  recordRectangle(pass, pipelines_.depthFixup);
  pass.timer.end(pass.cmd);
}

void HermiteCellFeature::recordPrepassDraws(engine::render::PassContext& pass) {
  pass.timer.begin(pass.cmd, "cells prepass");
  for (int precision = 0; precision < kBatches; ++precision) {
    recordBatch(pass, precision, false);
    recordBatch(pass, precision, true);
  }
  pass.timer.end(pass.cmd);
}

void HermiteCellFeature::drawUi() {
  if (!ImGui::CollapsingHeader("Hermite cells", ImGuiTreeNodeFlags_DefaultOpen)) return;
  // Read-only: the application owns the setting (the scene runner's tuning panel writes it).
  const bool wanted = earlyDepthWanted(settings_.earlyDepth, context_->capabilities().isSoftwareRasterizer);
  const char* mode = settings_.earlyDepth == EarlyDepth::Auto ? " (auto)" : "";
  ImGui::Text("front-to-back rows: %s, early depth: %s%s", settings_.frontToBack ? "on" : "off",
              stats_.earlyDepth ? "on" : wanted ? "off (objects overlap on screen)" : "off", mode);
  ImGui::Text("objects %u, cells %llu, draws %u, near cells %u, skipped %u", stats_.objects,
              static_cast<unsigned long long>(stats_.cells), stats_.draws, stats_.nearCells, stats_.skippedObjects);
  ImGui::Text("cell buffers: %.2f MiB", double(stats_.gpuBytes) / (1024.0 * 1024.0));
}

}  // namespace hsdf
