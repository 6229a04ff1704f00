// The cell feature's pipelines: cells, thin cells, runs, bricks and their vertex layouts.
#include "hermite_sdf/render/cell_feature.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <span>
#include <utility>
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
#include "render/cell_feature_internal.h"
#include "render/cell_tiler.h"
#include "render/cell_history.h"
#include "cells/cell_rows.h"
#include "render/wireframe.h"
#include "hermite_sdf/render/lod.h"
#include "hermite_sdf/core/normal_cone.h"

namespace hsdf {

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

}  // namespace

std::vector<HermiteCellFeature::Pipelines::Lazy*> HermiteCellFeature::Pipelines::all() {
  std::vector<Lazy*> set;
  const auto addEach = [&](std::span<Lazy> pipelines) {
    for (Lazy& pipeline : pipelines) set.push_back(&pipeline);
  };
  for (auto& row : depthFront) addEach(row);
  for (auto& row : depthNear) addEach(row);
  for (auto& row : thinFront) addEach(row);
  for (auto& row : thinNear) addEach(row);
  for (std::span<Lazy> row : {std::span<Lazy>(wire), std::span<Lazy>(runsFront), std::span<Lazy>(runsNear),
                              std::span<Lazy>(bricksFront), std::span<Lazy>(bricksNear), std::span<Lazy>(tiles)})
    addEach(row);
  set.push_back(&resolve);
  set.push_back(&depthFixup);
  return set;
}

namespace {

// The shaders of a box proxy's prepass: its vertex stage, and the fragment stages of its front
// faces and of its near boxes.
struct BoxShaders {
  engine::gpu::SharedShaderModule vertex;
  engine::gpu::SharedShaderModule front;
  engine::gpu::SharedShaderModule near;
};

// A box proxy's prepass pipeline pair (cells, thin cells, runs, bricks).
struct BoxPrepass {
  engine::gpu::LazyPipeline front;
  engine::gpu::LazyPipeline near;
};

// Depth tested and written with the visibility buffer as colour (a miss writes depth 0, which
// GREATER rejects: hit_depth.glsl). The front pipeline draws the boxes' front faces (a fan a face,
// back faces culled), "<name> near<suffix>" the boxes the eye is near or inside, by their back faces
// (strips, front faces culled).
BoxPrepass describeBoxPrepass(const engine::render::RendererFormats& formats, const BoxShaders& shaders,
                              engine::gpu::VertexLayout layout, const std::string& name, const std::string& suffix) {
  engine::gpu::GraphicsPipelineDesc desc;
  desc.vertex = shaders.vertex->handle();
  desc.vertexLayout = std::move(layout);
  desc.pushConstantBytes = sizeof(shader::HermitePushConstants);
  desc.depthFormat = formats.depth;
  desc.colorFormats = formats.prepassColorFormats();
  desc.depthCompare = VK_COMPARE_OP_GREATER;
  BoxPrepass pair;
  desc.name = name + suffix;
  desc.fragment = shaders.front->handle();
  desc.cullMode = VK_CULL_MODE_BACK_BIT;
  desc.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_FAN;
  pair.front = engine::gpu::LazyPipeline(desc, {shaders.vertex, shaders.front});
  desc.name = name + " near" + suffix;
  desc.fragment = shaders.near->handle();
  desc.cullMode = VK_CULL_MODE_FRONT_BIT;
  desc.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP;
  pair.near = engine::gpu::LazyPipeline(desc, {shaders.vertex, shaders.near});
  return pair;
}

}  // namespace

// Every pipeline of the feature, described with its shader modules loaded (a missing or bad SPIR-V
// file fails here), compiled when a frame first draws with it. The shared shaders are loaded
// first, then each family is described.
engine::Expected<HermiteCellFeature::Pipelines> HermiteCellFeature::describePipelines() const {
  const engine::gpu::Context& context = *context_;
  Pipelines p;
  ENGINE_TRY_ASSIGN(auto vert, engine::gpu::loadSharedShaderModule(context, "cells.vert"));
  ENGINE_TRY_ASSIGN(auto fixupFrag, engine::gpu::loadSharedShaderModule(context, "cells_depth_early_fixup.frag"));
  ENGINE_TRY_ASSIGN(auto resolveVert, engine::gpu::loadSharedShaderModule(context, "cells_resolve.vert"));
  ENGINE_TRY_ASSIGN(auto wireFrag, engine::gpu::loadSharedShaderModule(context, "cells_wire.frag"));
  ENGINE_TRY_ASSIGN(auto resolveFrag, engine::gpu::loadSharedShaderModule(context, "cells_resolve.frag"));
  ENGINE_TRY_ASSIGN(auto runsVert, engine::gpu::loadSharedShaderModule(context, "runs.vert"));

  ENGINE_TRY(describeCellPipelines(p, vert, runsVert));
  ENGINE_TRY(describeBrickPipelines(p));
  ENGINE_TRY(describeThinCellPipelines(p));
  ENGINE_TRY(describeTilePipelines(p));
  ENGINE_TRY(describeWirePipelines(p, wireFrag));
  describeResolvePipelines(p, resolveVert, resolveFrag, fixupFrag);
  return p;
}

// The prepass pipelines of cells (per variant and precision) and of cell runs (per variant).
engine::Status HermiteCellFeature::describeCellPipelines(Pipelines& p, const engine::gpu::SharedShaderModule& vert,
                                                         const engine::gpu::SharedShaderModule& runsVert) const {
  const engine::gpu::Context& context = *context_;
  const engine::render::RendererFormats& formats = formats_;
  // Fragment shaders per prepass variant (Variant; shaders/hermite/hit_depth.glsl): front faces, near cells.
  static constexpr const char* kCellsFront[kVariants] = {"cells_depth.frag", "cells_depth_counted.frag",
                                                         "cells_depth_early.frag"};
  static constexpr const char* kCellsNear[kVariants] = {"cells_depth_near.frag", "cells_depth_near_counted.frag",
                                                        "cells_depth_near_early.frag"};
  static constexpr const char* kVariantNames[kVariants] = {"", " counted", " early"};
  for (int variant = 0; variant < kVariants; ++variant) {
    ENGINE_TRY_ASSIGN(auto frontFrag, engine::gpu::loadSharedShaderModule(context, kCellsFront[variant]));
    ENGINE_TRY_ASSIGN(auto nearFrag, engine::gpu::loadSharedShaderModule(context, kCellsNear[variant]));
    for (int precision = 0; precision < 2; ++precision) {
      const std::string suffix = std::string(kVariantNames[variant]) + (precision == 0 ? " fp32" : " fp16");
      BoxPrepass pair = describeBoxPrepass(formats, {vert, frontFrag, nearFrag}, cellVertexLayout(precision),
                                           "hermite cells depth", suffix);
      p.depthFront[variant][precision] = std::move(pair.front);
      p.depthNear[variant][precision] = std::move(pair.near);
    }
    ENGINE_TRY(describeRunPipelines(p, runsVert, variant, kVariantNames[variant]));
  }
  return {};
}

// One variant's prepass pipelines of cell runs (front faces, near cells).
engine::Status HermiteCellFeature::describeRunPipelines(Pipelines& p, const engine::gpu::SharedShaderModule& runsVert,
                                                        int variant, const char* variantName) const {
  const engine::gpu::Context& context = *context_;
  const engine::render::RendererFormats& formats = formats_;
  static constexpr const char* kRunsFront[kVariants] = {"runs_depth.frag", "runs_depth_counted.frag",
                                                        "runs_depth_early.frag"};
  static constexpr const char* kRunsNear[kVariants] = {"runs_depth_near.frag", "runs_depth_near_counted.frag",
                                                       "runs_depth_near_early.frag"};
  // Cell runs: records by address, one pipeline pair for both precisions (HERMITE_FLAG_HALF_RECORDS).
  ENGINE_TRY_ASSIGN(auto runsFrontFrag, engine::gpu::loadSharedShaderModule(context, kRunsFront[variant]));
  ENGINE_TRY_ASSIGN(auto runsNearFrag, engine::gpu::loadSharedShaderModule(context, kRunsNear[variant]));
  BoxPrepass pair = describeBoxPrepass(formats, {runsVert, runsFrontFrag, runsNearFrag}, runVertexLayout(),
                                       "hermite cell runs depth", variantName);
  p.runsFront[variant] = std::move(pair.front);
  p.runsNear[variant] = std::move(pair.near);
  return {};
}

// The wireframe pipelines, one per batch (DEBUG_VIEW_WIREFRAME): the cells' boxes per record
// precision, the runs' and the bricks' boxes, each from its batch's vertex stream.
engine::Status HermiteCellFeature::describeWirePipelines(Pipelines& p,
                                                         const engine::gpu::SharedShaderModule& wireFrag) const {
  const engine::gpu::Context& context = *context_;
  const engine::render::RendererFormats& formats = formats_;
  ENGINE_TRY_ASSIGN(auto cellsWire, engine::gpu::loadSharedShaderModule(context, "cells_wire.vert"));
  ENGINE_TRY_ASSIGN(auto runsWire, engine::gpu::loadSharedShaderModule(context, "runs_wire.vert"));
  ENGINE_TRY_ASSIGN(auto bricksWire, engine::gpu::loadSharedShaderModule(context, "bricks_wire.vert"));
  static constexpr const char* kNames[kBatches] = {"cells fp32", "cells fp16", "runs", "bricks"};
  // Edges over the shaded frame, hidden where the surface is in front of them.
  for (int batch = 0; batch < kBatches; ++batch) {
    engine::gpu::GraphicsPipelineDesc wire = wireframePipelineDesc(formats);
    wire.name = std::string("hermite wireframe ") + kNames[batch];
    const engine::gpu::SharedShaderModule& vertex = batch == kRunBatch     ? runsWire
                                                    : batch == kBrickBatch ? bricksWire
                                                                           : cellsWire;
    wire.vertex = vertex->handle();
    wire.fragment = wireFrag->handle();
    if (batch == kRunBatch) {
      wire.vertexLayout = runVertexLayout();
    } else if (batch == kBrickBatch) {
      wire.vertexLayout = brickVertexLayout();
    } else {
      wire.vertexLayout = cellVertexLayout(batch);
      std::erase_if(wire.vertexLayout.attributes, [](const auto& a) { return a.location != 8; });  // coordinates only
    }
    wire.pushConstantBytes = sizeof(shader::HermitePushConstants);
    p.wire[batch] = Pipelines::Lazy(wire, {vertex, wireFrag});
  }
  return {};
}

// The full-screen-rectangle pipelines: the shading (resolve) pass and the early depth fix-up.
void HermiteCellFeature::describeResolvePipelines(Pipelines& p, const engine::gpu::SharedShaderModule& resolveVert,
                                                  const engine::gpu::SharedShaderModule& resolveFrag,
                                                  const engine::gpu::SharedShaderModule& fixupFrag) const {
  const engine::render::RendererFormats& formats = formats_;
  // Shading: a rectangle over the cell objects' screen bounds; which of its pixels are ours comes
  // from the visibility buffer.
  engine::gpu::GraphicsPipelineDesc resolve;
  resolve.name = "hermite cells resolve";
  resolve.vertex = resolveVert->handle();
  resolve.fragment = resolveFrag->handle();
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
  p.resolve = Pipelines::Lazy(resolve, {resolveVert, resolveFrag});
  // Early depth fix-up: the same rectangle, in the prepass, writing only depth (always: the faces it
  // replaces lie in front of the hits, and nothing else has been drawn yet).
  engine::gpu::GraphicsPipelineDesc fixup;
  fixup.name = "hermite cells depth fix-up";
  fixup.vertex = resolveVert->handle();
  fixup.fragment = fixupFrag->handle();
  fixup.cullMode = VK_CULL_MODE_NONE;
  fixup.depthCompare = VK_COMPARE_OP_ALWAYS;
  fixup.depthFormat = formats.depth;
  fixup.colorFormats = formats.prepassColorFormats();
  fixup.colorWrite = false;
  fixup.pushConstantBytes = sizeof(shader::HermitePushConstants);
  p.depthFixup = Pipelines::Lazy(fixup, {resolveVert, fixupFrag});
}


// Cell bricks: production and counted variants, no early depth one (a frame that draws bricks
// keeps the early depth stage off: buildDraws). Both precisions share one pipeline pair.
engine::Status HermiteCellFeature::describeBrickPipelines(Pipelines& p) const {
  static constexpr const char* kFront[kBrickVariants] = {"bricks_depth.frag", "bricks_depth_counted.frag"};
  static constexpr const char* kNear[kBrickVariants] = {"bricks_depth_near.frag", "bricks_depth_near_counted.frag"};
  static constexpr const char* kNames[kBrickVariants] = {"", " counted"};
  ENGINE_TRY_ASSIGN(auto vert, engine::gpu::loadSharedShaderModule(*context_, "bricks.vert"));
  for (int variant = 0; variant < kBrickVariants; ++variant) {
    ENGINE_TRY_ASSIGN(auto front, engine::gpu::loadSharedShaderModule(*context_, kFront[variant]));
    ENGINE_TRY_ASSIGN(auto near, engine::gpu::loadSharedShaderModule(*context_, kNear[variant]));
    BoxPrepass pair =
        describeBoxPrepass(formats_, {vert, front, near}, brickVertexLayout(), "hermite cell bricks depth", kNames[variant]);
    p.bricksFront[variant] = std::move(pair.front);
    p.bricksNear[variant] = std::move(pair.near);
  }
  return {};
}

// Thin cell boxes: production and counted variants (no early depth one: buildDraws keeps the stage
// off), per precision for the cell attribute's offset in the record; the corners are read by address.
engine::Status HermiteCellFeature::describeThinCellPipelines(Pipelines& p) const {
  static constexpr const char* kFront[kBrickVariants] = {"cells_thin_depth.frag", "cells_thin_depth_counted.frag"};
  static constexpr const char* kNear[kBrickVariants] = {"cells_thin_depth_near.frag",
                                                        "cells_thin_depth_near_counted.frag"};
  static constexpr const char* kNames[kBrickVariants] = {"", " counted"};
  ENGINE_TRY_ASSIGN(auto vert, engine::gpu::loadSharedShaderModule(*context_, "cells_thin.vert"));
  for (int variant = 0; variant < kBrickVariants; ++variant) {
    ENGINE_TRY_ASSIGN(auto front, engine::gpu::loadSharedShaderModule(*context_, kFront[variant]));
    ENGINE_TRY_ASSIGN(auto near, engine::gpu::loadSharedShaderModule(*context_, kNear[variant]));
    for (int precision = 0; precision < 2; ++precision) {
      const std::string suffix = std::string(kNames[variant]) + (precision == 0 ? " fp32" : " fp16");
      engine::gpu::VertexLayout layout = cellVertexLayout(precision);
      std::erase_if(layout.attributes, [](const auto& a) { return a.location != 8; });  // the cell only
      BoxPrepass pair = describeBoxPrepass(formats_, {vert, front, near}, std::move(layout), "hermite thin cells depth", suffix);
      p.thinFront[variant][precision] = std::move(pair.front);
      p.thinNear[variant][precision] = std::move(pair.near);
    }
  }
  return {};
}

// Tiled cells: production and counted variants (no early depth: a frame that draws tiles keeps the
// stage off), both precisions in one pipeline (the fragment shader reads records by address).
engine::Status HermiteCellFeature::describeTilePipelines(Pipelines& p) const {
  static constexpr const char* kFragments[kBrickVariants] = {"cell_tiles_depth.frag", "cell_tiles_depth_counted.frag"};
  static constexpr const char* kNames[kBrickVariants] = {"", " counted"};
  const bool points = tilesAsPoints(*context_);
  ENGINE_TRY_ASSIGN(auto vert, engine::gpu::loadSharedShaderModule(*context_, points ? "cell_tiles.vert" : "cell_tiles_quads.vert"));
  for (int variant = 0; variant < kBrickVariants; ++variant) {
    ENGINE_TRY_ASSIGN(auto frag, engine::gpu::loadSharedShaderModule(*context_, kFragments[variant]));
    engine::gpu::GraphicsPipelineDesc desc;
    desc.vertex = vert->handle();
    desc.fragment = frag->handle();
    desc.pushConstantBytes = sizeof(shader::HermitePushConstants);
    desc.depthFormat = formats_.depth;
    desc.colorFormats = formats_.prepassColorFormats();
    desc.depthCompare = VK_COMPARE_OP_GREATER;  // a miss writes depth 0, which this rejects (hit_depth.glsl)
    desc.cullMode = VK_CULL_MODE_NONE;
    desc.topology = points ? VK_PRIMITIVE_TOPOLOGY_POINT_LIST : VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    desc.name = std::string("hermite cell tiles depth") + kNames[variant];
    p.tiles[variant] = Pipelines::Lazy(desc, {vert, frag});
  }
  return {};
}


// What the next change of the tuning panel's most used options would bind: the other methods'
// prepass pipelines (cells at either record precision, in the proxy form the frame draws them;
// runs; bricks; front faces and near cells) and, where the early depth stage is wanted, the early
// variants and their fix-up that cells and runs then draw with (a frame of tiles or bricks keeps
// the stage off, the next frame of runs turns it on), and their variants without the stage. Not
// every variant, the wireframe or the other proxy form: those are 4 to 5 times as many compiles
// (on lavapipe ~0.1-0.3 s of CPU each, competing with the frames on a machine of two cores) for
// switches that are rarer. Those made already are skipped by the worker at the cost of a lock.
std::vector<engine::gpu::LazyPipeline*> HermiteCellFeature::likelyNextPipelines(Variant base) {
  Pipelines& p = pipelines_;
  const bool early = earlyDepthWanted(settings_.earlyDepth, context_->capabilities().isSoftwareRasterizer) && !occlusion_;
  const Variant boxes = early ? kEarly : base;  // cells as boxes and runs
  // A frame that drew no cells measured no cell on screen (ThinBoxes::Auto on a GPU then says thin
  // for a largest cell of 0 pixels): the first frame of cells may pick either form, so both are warmed.
  const bool thinUnmeasured = settings_.thinBoxes == ThinBoxes::Auto && stats_.largestCellPixels <= 0.0f &&
                              !context_->capabilities().isSoftwareRasterizer;
  std::vector<engine::gpu::LazyPipeline*> set;
  for (int precision = 0; precision < 2; ++precision) {
    if (thinBoxes_ || thinUnmeasured) {
      set.push_back(&p.thinFront[base][precision]);
      set.push_back(&p.thinNear[base][precision]);
    }
    if (!thinBoxes_ || thinUnmeasured) {
      set.push_back(&p.depthFront[boxes][precision]);
      set.push_back(&p.depthNear[boxes][precision]);
    }
  }
  for (engine::gpu::LazyPipeline* next :
       {&p.bricksFront[base], &p.bricksNear[base], &p.runsFront[boxes], &p.runsNear[boxes]})
    set.push_back(next);
  if (early) set.push_back(&p.depthFixup);
  if (early) appendWithoutEarlyStage(set, base);
  return set;
}

// Where the early depth stage is wanted, the cells and runs of a frame that drops it (its objects
// overlap on screen: a second object in view; bricks, tiles) draw with the `base` variants: the
// frame that first adds an overlapping object would otherwise compile them on the render thread
// (the bunny at K = 256 added beside a sphere: 120-260 ms of that frame on lavapipe).
void HermiteCellFeature::appendWithoutEarlyStage(std::vector<engine::gpu::LazyPipeline*>& set, Variant base) {
  Pipelines& p = pipelines_;
  for (int precision = 0; precision < 2; ++precision) {
    set.push_back(&p.depthFront[base][precision]);
    set.push_back(&p.depthNear[base][precision]);
  }
  set.push_back(&p.runsFront[base]);
  set.push_back(&p.runsNear[base]);
}

// What the first frame of cells binds besides its proxies, which frames that drew cells have made
// already (the worker skips them at the cost of a lock) but a session whose objects were all traced
// has not: the shading resolve, and the tiles where the frame would draw them.
void HermiteCellFeature::appendFirstFrame(std::vector<engine::gpu::LazyPipeline*>& set, Variant base) {
  set.push_back(&pipelines_.resolve);
  if (context_->capabilities().drawIndirectCount &&
      tilesWanted(settings_.tiles, context_->capabilities().isSoftwareRasterizer))
    set.push_back(&pipelines_.tiles[base]);
}

// Started by the second frame with objects of the module, drawn here or by a tracer
// (hasSdfObjects, engine::gpu::PipelineWarming): a switch from a tracer to cells then compiles
// nothing in its frame either.
void HermiteCellFeature::warmPipelines(const engine::render::FrameContext& frame) {
  warming_.frame(*context_, settings_.warmPipelines && hasSdfObjects(frame.registry), [&] {
    const Variant base = withoutEarlyStage(prepassVariant(frame));
    std::vector<engine::gpu::LazyPipeline*> set = likelyNextPipelines(base);
    appendFirstFrame(set, base);
    return set;
  });
}

void HermiteCellFeature::waitForWarmPipelines() {
  warming_.wait();
}

}  // namespace hsdf
