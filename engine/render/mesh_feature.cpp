#include "engine/render/mesh_feature.h"

#include <algorithm>
#include <array>
#include <string>
#include <tuple>

#include <imgui.h>

#include "engine/core/math.h"
#include "engine/ecs/registry.h"
#include "engine/gpu/context.h"
#include "engine/render/gpu_scene.h"
#include "engine/scene/transform.h"

namespace engine::render {
namespace {

gpu::VertexLayout meshVertexLayout() {
  gpu::VertexLayout layout;
  layout.bindings.push_back({0, sizeof(MeshVertex), VK_VERTEX_INPUT_RATE_VERTEX});
  layout.attributes.push_back({0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(MeshVertex, position)});
  layout.attributes.push_back({1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(MeshVertex, normal)});
  layout.attributes.push_back({2, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(MeshVertex, texcoord)});
  layout.attributes.push_back({3, 0, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(MeshVertex, tangent)});
  return layout;
}

// mesh.frag's SPIR-V of each material variant (MeshFeature::Variant), shaded and blended
// (shaders/CMakeLists.txt), and the words its pipelines' names end in.
struct VariantShaders {
  const char* shade;
  const char* blended;
  const char* name;
};
constexpr std::array<VariantShaders, 3> kVariantShaders = {{
    {"mesh_untextured.frag", "mesh_blended_untextured.frag", "untextured"},
    {"mesh_textured.frag", "mesh_blended_textured.frag", "textured"},
    {"mesh.frag", "mesh_blended.frag", "normal-mapped"},
}};

}  // namespace

Status MeshFeature::initialize(const gpu::Context& context, const RendererFormats& formats, std::uint32_t framesInFlight) {
  context_ = &context;
  formats_ = formats;
  draws_ = gpu::IndirectDraws(context);
  indirect_ = PerFrameBuffer(context, framesInFlight, VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT, "mesh indirect draws");
  ENGINE_TRY_ASSIGN(pipelines_, createPipelines());
  return {};
}

// Built aside and swapped in only when all of them were created: a failure keeps the old ones.
Status MeshFeature::reloadShaders() {
  ENGINE_TRY_ASSIGN(Pipelines fresh, createPipelines());
  context_->waitIdle();  // frames in flight may still use the old pipelines
  pipelines_ = std::move(fresh);
  return {};
}

Expected<MeshFeature::Pipelines> MeshFeature::createPipelines() const {
  const gpu::Context& context = *context_;
  ENGINE_TRY_ASSIGN(gpu::ShaderModule vert, gpu::ShaderModule::load(context, "mesh.vert"));
  ENGINE_TRY_ASSIGN(gpu::ShaderModule prepassFrag, gpu::ShaderModule::load(context, "mesh_prepass.frag"));
  ENGINE_TRY_ASSIGN(gpu::ShaderModule maskedFrag, gpu::ShaderModule::load(context, "mesh_prepass_masked.frag"));
  static_assert(kVariantShaders.size() == kVariants);
  std::array<gpu::ShaderModule, kVariants> frags, blendedFrags;
  for (std::size_t v = 0; v < kVariants; ++v) {
    ENGINE_TRY_ASSIGN(frags[v], gpu::ShaderModule::load(context, kVariantShaders[v].shade));
    ENGINE_TRY_ASSIGN(blendedFrags[v], gpu::ShaderModule::load(context, kVariantShaders[v].blended));
  }

  // What every mesh pipeline shares: mesh.vert with its vertex layout and push constants, the
  // base colour texture (mesh.frag). The prepass reads none but has the same layout: all passes
  // run mesh.vert in one pipeline layout, which Vulkan's invariance rules ask for (the shading pass
  // tests depth EQUAL). Clockwise front faces for mirrored objects: what culling keeps, and
  // gl_FrontFacing (which side is lit).
  gpu::GraphicsPipelineDesc base;
  base.vertex = vert.handle();
  base.vertexLayout = meshVertexLayout();
  base.depthFormat = formats_.depth;
  base.pushConstantBytes = sizeof(shader::DrawPushConstants);
  base.setLayouts = {pool_.textures().layout()};
  base.extraDynamicStates = {VK_DYNAMIC_STATE_FRONT_FACE};

  // One prepass and one shading pipeline per cull mode: a primitive is drawn with the same cull
  // mode in both passes, or its back faces would have depth and no colour (or colour tested
  // against depth the prepass never wrote).
  Pipelines pipelines;
  for (const Sides sides : {Sides::Single, Sides::Double}) {
    const bool both = sides == Sides::Double;
    gpu::GraphicsPipelineDesc desc = base;
    desc.fragment = prepassFrag.handle();
    desc.colorFormats = formats_.prepassColorFormats();
    desc.cullMode = both ? VK_CULL_MODE_NONE : VK_CULL_MODE_BACK_BIT;
    desc.name = both ? "mesh depth prepass, double-sided" : "mesh depth prepass";
    desc.depthCompare = VK_COMPARE_OP_GREATER;
    ENGINE_TRY_ASSIGN(pipelines.depth[std::size_t(sides)], gpu::Pipeline::createGraphics(context, desc));

    desc.name = both ? "mesh depth prepass, double-sided, cut out" : "mesh depth prepass, cut out";
    desc.fragment = maskedFrag.handle();
    ENGINE_TRY_ASSIGN(pipelines.depthMasked[std::size_t(sides)], gpu::Pipeline::createGraphics(context, desc));

    desc.colorFormats = {formats_.color};
    desc.depthWrite = false;
    desc.depthCompare = VK_COMPARE_OP_EQUAL;  // depth is final after the prepass
    for (std::size_t v = 0; v < kVariants; ++v) {
      desc.name = std::string(both ? "mesh shading, double-sided, " : "mesh shading, ") + kVariantShaders[v].name;
      desc.fragment = frags[v].handle();
      ENGINE_TRY_ASSIGN(pipelines.shade[std::size_t(sides)][v], gpu::Pipeline::createGraphics(context, desc));
    }
  }

  // The transparent pass: blended over the frame by straight alpha (glTF's), in front of or on
  // the prepass depth (GREATER_OR_EQUAL: a pane on a surface of the same triangles is kept),
  // writing none. One pipeline for both sides: a double-sided mesh is drawn twice with the cull
  // mode set between (back faces, then front faces).
  gpu::GraphicsPipelineDesc desc = base;
  desc.colorFormats = {formats_.color};
  desc.depthWrite = false;
  desc.depthCompare = VK_COMPARE_OP_GREATER_OR_EQUAL;
  desc.alphaBlend = true;
  desc.extraDynamicStates.push_back(VK_DYNAMIC_STATE_CULL_MODE);
  for (std::size_t v = 0; v < kVariants; ++v) {
    desc.name = std::string("mesh blended, ") + kVariantShaders[v].name;
    desc.fragment = blendedFrags[v].handle();
    ENGINE_TRY_ASSIGN(pipelines.blended[v], gpu::Pipeline::createGraphics(context, desc));
  }
  return pipelines;
}

struct MeshFeature::PendingDraw {
  Sides sides;
  bool masked;
  Variant variant;
  std::uint32_t texture;
  bool mirrored;
  VkDrawIndexedIndirectCommand command;
  float viewDistance;  // of the bounds' centre (blended draws are sorted by it)
};

namespace {

// The normals and depth views show the surfaces of the depth buffer, which no blended mesh is in
// (a normal or depth blended over another is neither); the other views draw them as the frame does.
bool drawsBlended(std::uint32_t debugView) { return debugView != DEBUG_VIEW_NORMALS && debugView != DEBUG_VIEW_DEPTH; }

}  // namespace

// The cheapest variant that draws `mesh` as the whole shader does: a normal texture is read when its
// scale is not 0 (mesh.frag), the other textures when the set is not set 0 (the white texels).
MeshFeature::Variant MeshFeature::variantOf(const MeshRenderable& mesh, std::uint32_t texture) {
  if (mesh.normalScale != 0.0f) return Variant::NormalMapped;
  return texture != 0 ? Variant::Textured : Variant::Untextured;
}

void MeshFeature::prepare(FrameContext& frame) {
  pool_.sync(frame);
  culledCount_ = 0;
  std::vector<PendingDraw> draws, blended;
  const math::Frustum frustum = math::extractFrustum(frame.camera.proj * frame.camera.view);
  frame.registry.view<MeshRenderable, scene::WorldTransform>().each(
      [&](ecs::Entity, const MeshRenderable& mesh, const scene::WorldTransform& world) {
        if (!mesh.mesh.valid() || mesh.mesh.index >= pool_.meshCount() || !drawableTransform(world.matrix)) return;
        if (mesh.alphaBlend && !drawsBlended(frame.debugView)) return;
        const MeshRange& range = pool_.range(mesh.mesh);
        if (!math::intersects(frustum, world.matrix, range.boundsMin, range.boundsMax)) {
          ++culledCount_;
          return;
        }
        shader::ObjectData object = GpuScene::makeObject(world.matrix, mesh.color, mesh.roughness, mesh.metallic, kFeatureId);
        object.emission = glm::vec4(mesh.emissive, mesh.normalScale);  // mesh.frag
        object.material.z = mesh.alphaCutoff.value_or(0.0f);  // mesh_prepass_masked.frag
        object.material.w = mesh.occlusionStrength;
        const std::uint32_t index = frame.scene.addObject(object);
        const std::uint32_t texture = mesh.textures.index < pool_.textures().count() ? mesh.textures.index : 0;
        // Only blended draws are sorted, by the view distance of their bounds' centre.
        const float viewDistance =
            mesh.alphaBlend ? frame.camera.viewDistance(world.matrix * glm::vec4(0.5f * (range.boundsMin + range.boundsMax), 1.0f))
                            : 0.0f;
        (mesh.alphaBlend ? blended : draws)
            .push_back({mesh.doubleSided ? Sides::Double : Sides::Single, mesh.alphaCutoff.has_value(),
                        variantOf(mesh, texture), texture,
                        mirrors(world.matrix), {range.indexCount, 1, range.firstIndex, range.vertexOffset, index},
                        viewDistance});
      });
  buildBatches(draws);
  buildBlendedBatches(blended);
  drawCount_ = static_cast<std::uint32_t>(commands_.size());
  if (!commands_.empty()) indirect_.upload(frame.frameSlot, commands_);
}

// Single-sided objects first, as they were drawn before double-sided ones existed; opaque before
// cut out (one prepass pipeline change); then by variant (one shading pipeline change), by texture
// (one descriptor set bind each), unmirrored before mirrored (one front-face change each).
void MeshFeature::buildBatches(std::vector<PendingDraw>& draws) {
  std::stable_sort(draws.begin(), draws.end(), [](const PendingDraw& a, const PendingDraw& b) {
    return std::tie(a.sides, a.masked, a.variant, a.texture, a.mirrored) <
           std::tie(b.sides, b.masked, b.variant, b.texture, b.mirrored);
  });
  commands_.clear();
  batches_.clear();
  doubleSidedCount_ = 0;
  for (const PendingDraw& draw : draws) {
    const bool joins = !batches_.empty() && batches_.back().sides == draw.sides && batches_.back().masked == draw.masked &&
                       batches_.back().variant == draw.variant && batches_.back().texture.index == draw.texture;
    append(batches_, draw, joins);
  }
}

// Back to front, after the opaque draws in commands_. Neighbours in that order share a batch (one
// multi-draw, which draws its commands in order) when single-sided with the same texture and
// winding and variant; a double-sided draw is a batch of its own, its back faces drawn before its
// front faces.
void MeshFeature::buildBlendedBatches(std::vector<PendingDraw>& draws) {
  std::stable_sort(draws.begin(), draws.end(),
                   [](const PendingDraw& a, const PendingDraw& b) { return a.viewDistance > b.viewDistance; });
  blendedBatches_.clear();
  for (const PendingDraw& draw : draws) {
    const Batch* last = blendedBatches_.empty() ? nullptr : &blendedBatches_.back();
    const bool joins = last && last->sides == Sides::Single && draw.sides == Sides::Single && last->variant == draw.variant &&
                       last->texture.index == draw.texture && (last->mirroredFirst != last->end) == draw.mirrored;
    append(blendedBatches_, draw, joins);
  }
  blendedCount_ = static_cast<std::uint32_t>(draws.size());
}

// The draw's command at the end of commands_, in the last of `batches` or in a new one.
void MeshFeature::append(std::vector<Batch>& batches, const PendingDraw& draw, bool joinsLast) {
  const auto at = static_cast<std::uint32_t>(commands_.size());
  if (!joinsLast) batches.push_back({draw.sides, draw.masked, draw.variant, TextureHandle{draw.texture}, at, at, at});
  Batch& batch = batches.back();
  if (!draw.mirrored) batch.mirroredFirst = at + 1;
  batch.end = at + 1;
  commands_.push_back(draw.command);
  doubleSidedCount_ += draw.sides == Sides::Double;
}

void MeshFeature::recordPass(PassContext& pass) {
  if (commands_.empty() || pool_.empty()) return;
  const bool prepass = pass.pass == Pass::DepthPrepass;
  const gpu::Pipeline* bound = nullptr;
  for (const Batch& batch : batches_) {
    const gpu::Pipeline& pipeline = pipelineOf(batch, prepass);
    if (&pipeline != bound) bindPipeline(pass, pipeline);
    bound = &pipeline;
    // The opaque prepass reads no texture; a cut-out one reads the alpha.
    if (!prepass || batch.masked) pool_.textures().bind(pass.cmd, pipeline.layout(), batch.texture);
    recordBatch(pass, batch);
  }
}

void MeshFeature::recordTransparent(PassContext& pass) {
  if (blendedBatches_.empty() || pool_.empty()) return;
  const gpu::Pipeline* bound = nullptr;
  for (const Batch& batch : blendedBatches_) {
    const gpu::Pipeline& pipeline = pipelines_.blended[std::size_t(batch.variant)];
    if (&pipeline != bound) bindPipeline(pass, pipeline);
    bound = &pipeline;
    pool_.textures().bind(pass.cmd, pipeline.layout(), batch.texture);
    if (batch.sides == Sides::Double) {  // the far side first, under the near one
      vkCmdSetCullMode(pass.cmd, VK_CULL_MODE_FRONT_BIT);
      recordBatch(pass, batch);
    }
    vkCmdSetCullMode(pass.cmd, VK_CULL_MODE_BACK_BIT);
    recordBatch(pass, batch);
  }
}

const gpu::Pipeline& MeshFeature::pipelineOf(const Batch& batch, bool prepass) const {
  const auto sides = std::size_t(batch.sides);
  if (!prepass) return pipelines_.shade[sides][std::size_t(batch.variant)];
  return batch.masked ? pipelines_.depthMasked[sides] : pipelines_.depth[sides];
}

void MeshFeature::bindPipeline(PassContext& pass, const gpu::Pipeline& pipeline) const {
  VkCommandBuffer cmd = pass.cmd;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.handle());
  shader::DrawPushConstants push{};
  push.frameGlobals = pass.frameGlobals;
  push.objects = pass.objects;
  push.debugView = pass.frame.debugView;
  vkCmdPushConstants(cmd, pipeline.layout(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                     sizeof(push), &push);
  const VkBuffer vertexBuffer = pool_.vertexBuffer().handle();
  const VkDeviceSize offset = 0;
  vkCmdBindVertexBuffers(cmd, 0, 1, &vertexBuffer, &offset);
  vkCmdBindIndexBuffer(cmd, pool_.indexBuffer().handle(), 0, VK_INDEX_TYPE_UINT32);
}

void MeshFeature::recordBatch(PassContext& pass, const Batch& batch) const {
  const VkBuffer indirect = indirect_.buffer(pass.frame.frameSlot).handle();
  vkCmdSetFrontFace(pass.cmd, VK_FRONT_FACE_COUNTER_CLOCKWISE);
  draws_.drawIndexed(pass.cmd, indirect, batch.first, batch.mirroredFirst - batch.first);
  vkCmdSetFrontFace(pass.cmd, VK_FRONT_FACE_CLOCKWISE);
  draws_.drawIndexed(pass.cmd, indirect, batch.mirroredFirst, batch.end - batch.mirroredFirst);
}

void MeshFeature::drawUi() {
  if (ImGui::CollapsingHeader("Meshes")) {
    ImGui::Text("meshes in pool: %u", pool_.meshCount());
    ImGui::TextWrapped("drawn: %u (double-sided: %u, blended: %u, in %zu batches), culled: %u", drawCount_,
                       doubleSidedCount_, blendedCount_, batches_.size() + blendedBatches_.size(), culledCount_);
  }
}

}  // namespace engine::render
