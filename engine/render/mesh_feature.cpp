#include "engine/render/mesh_feature.h"

#include <algorithm>
#include <array>
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
  return layout;
}

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
  ENGINE_TRY_ASSIGN(gpu::ShaderModule frag, gpu::ShaderModule::load(context, "mesh.frag"));
  ENGINE_TRY_ASSIGN(gpu::ShaderModule prepassFrag, gpu::ShaderModule::load(context, "mesh_prepass.frag"));
  ENGINE_TRY_ASSIGN(gpu::ShaderModule maskedFrag, gpu::ShaderModule::load(context, "mesh_prepass_masked.frag"));

  // One prepass and one shading pipeline per cull mode: a primitive is drawn with the same cull
  // mode in both passes, or its back faces would have depth and no colour (or colour tested
  // against depth the prepass never wrote).
  Pipelines pipelines;
  for (const Sides sides : {Sides::Single, Sides::Double}) {
    const bool both = sides == Sides::Double;
    gpu::GraphicsPipelineDesc desc;
    desc.vertex = vert.handle();
    desc.fragment = prepassFrag.handle();
    desc.colorFormats = formats_.prepassColorFormats();
    desc.vertexLayout = meshVertexLayout();
    desc.depthFormat = formats_.depth;
    desc.pushConstantBytes = sizeof(shader::DrawPushConstants);
    // The base colour texture (mesh.frag). The prepass reads none but has the same layout: both
    // passes run mesh.vert in one pipeline layout, which Vulkan's invariance rules ask for (the
    // shading pass tests depth EQUAL).
    desc.setLayouts = {pool_.textures().layout()};
    desc.cullMode = both ? VK_CULL_MODE_NONE : VK_CULL_MODE_BACK_BIT;
    desc.name = both ? "mesh depth prepass, double-sided" : "mesh depth prepass";
    desc.depthCompare = VK_COMPARE_OP_GREATER;
    // Clockwise for mirrored objects: what culling keeps, and gl_FrontFacing (which side is lit).
    desc.extraDynamicStates = {VK_DYNAMIC_STATE_FRONT_FACE};
    ENGINE_TRY_ASSIGN(pipelines.depth[std::size_t(sides)], gpu::Pipeline::createGraphics(context, desc));

    desc.name = both ? "mesh depth prepass, double-sided, cut out" : "mesh depth prepass, cut out";
    desc.fragment = maskedFrag.handle();
    ENGINE_TRY_ASSIGN(pipelines.depthMasked[std::size_t(sides)], gpu::Pipeline::createGraphics(context, desc));

    desc.name = both ? "mesh shading, double-sided" : "mesh shading";
    desc.fragment = frag.handle();
    desc.colorFormats = {formats_.color};
    desc.depthWrite = false;
    desc.depthCompare = VK_COMPARE_OP_EQUAL;  // depth is final after the prepass
    ENGINE_TRY_ASSIGN(pipelines.shade[std::size_t(sides)], gpu::Pipeline::createGraphics(context, desc));
  }
  return pipelines;
}

struct MeshFeature::PendingDraw {
  Sides sides;
  bool masked;
  std::uint32_t texture;
  bool mirrored;
  VkDrawIndexedIndirectCommand command;
};

void MeshFeature::prepare(FrameContext& frame) {
  pool_.sync(frame);
  culledCount_ = 0;
  std::vector<PendingDraw> draws;
  const math::Frustum frustum = math::extractFrustum(frame.camera.proj * frame.camera.view);
  frame.registry.view<MeshRenderable, scene::WorldTransform>().each(
      [&](ecs::Entity, const MeshRenderable& mesh, const scene::WorldTransform& world) {
        if (!mesh.mesh.valid() || mesh.mesh.index >= pool_.meshCount() || !drawableTransform(world.matrix)) return;
        const MeshRange& range = pool_.range(mesh.mesh);
        if (!math::intersects(frustum, world.matrix, range.boundsMin, range.boundsMax)) {
          ++culledCount_;
          return;
        }
        shader::ObjectData object = GpuScene::makeObject(world.matrix, mesh.color, mesh.roughness, mesh.metallic, kFeatureId);
        object.emission = glm::vec4(mesh.emissive, 0.0f);
        object.material.z = mesh.alphaCutoff.value_or(0.0f);  // mesh_prepass_masked.frag
        const std::uint32_t index = frame.scene.addObject(object);
        const std::uint32_t texture = mesh.baseColorTexture.index < pool_.textures().count() ? mesh.baseColorTexture.index : 0;
        draws.push_back({mesh.doubleSided ? Sides::Double : Sides::Single, mesh.alphaCutoff.has_value(), texture,
                         mirrors(world.matrix),
                         {range.indexCount, 1, range.firstIndex, range.vertexOffset, index}});
      });
  buildBatches(draws);
  if (!commands_.empty()) indirect_.upload(frame.frameSlot, commands_);
}

// Single-sided objects first, as they were drawn before double-sided ones existed; opaque before
// cut out (one pipeline change); then by texture (one descriptor set bind each), unmirrored before
// mirrored (one front-face change each).
void MeshFeature::buildBatches(std::vector<PendingDraw>& draws) {
  std::stable_sort(draws.begin(), draws.end(), [](const PendingDraw& a, const PendingDraw& b) {
    return std::tie(a.sides, a.masked, a.texture, a.mirrored) < std::tie(b.sides, b.masked, b.texture, b.mirrored);
  });
  commands_.clear();
  batches_.clear();
  doubleSidedCount_ = 0;
  for (const PendingDraw& draw : draws) {
    const auto at = static_cast<std::uint32_t>(commands_.size());
    if (batches_.empty() || batches_.back().sides != draw.sides || batches_.back().masked != draw.masked ||
        batches_.back().texture.index != draw.texture)
      batches_.push_back({draw.sides, draw.masked, TextureHandle{draw.texture}, at, at, at});
    Batch& batch = batches_.back();
    if (!draw.mirrored) batch.mirroredFirst = at + 1;
    batch.end = at + 1;
    commands_.push_back(draw.command);
    doubleSidedCount_ += draw.sides == Sides::Double;
  }
  drawCount_ = static_cast<std::uint32_t>(commands_.size());
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

const gpu::Pipeline& MeshFeature::pipelineOf(const Batch& batch, bool prepass) const {
  const auto sides = std::size_t(batch.sides);
  if (!prepass) return pipelines_.shade[sides];
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
    ImGui::TextWrapped("drawn: %u (double-sided: %u, in %zu batches), culled: %u", drawCount_, doubleSidedCount_,
                       batches_.size(), culledCount_);
  }
}

}  // namespace engine::render
