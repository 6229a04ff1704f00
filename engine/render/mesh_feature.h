#pragma once
// Draws every entity with MeshRenderable + WorldTransform: depth in the prepass, lit colour in the
// shading pass (depth EQUAL). Objects outside the view frustum are culled on the CPU. Any invertible
// affine world matrix: normals go through the inverse transpose, and objects whose matrix mirrors
// (negative determinant, e.g. a glTF node scaled by -1) are drawn in a second batch that takes
// clockwise triangles as front faces (dynamic state), so back-face culling keeps their outside.
// Objects whose matrix cannot be inverted (scaled to zero) are skipped.
#include <memory>
#include <vector>

#include "engine/gpu/indirect_draws.h"
#include "engine/gpu/pipeline.h"
#include "engine/render/mesh_pool.h"
#include "engine/render/per_frame_buffer.h"
#include "engine/render/render_feature.h"

namespace engine::render {

class MeshFeature final : public RenderFeature {
 public:
  static constexpr std::uint32_t kFeatureId = 1;

  explicit MeshFeature(MeshPool& pool) : pool_(pool) {}
  std::string_view name() const override { return "meshes"; }
  Status initialize(const gpu::Context& context, const RendererFormats& formats, std::uint32_t framesInFlight) override;
  void prepare(FrameContext& frame) override;
  void recordPass(PassContext& pass) override;
  void drawUi() override;
  Status reloadShaders() override;

  std::uint32_t drawnLastFrame() const { return drawCount_; }

 private:
  struct Pipelines {
    gpu::Pipeline depth;
    gpu::Pipeline shade;
  };
  Expected<Pipelines> createPipelines() const;
  void recordDraws(PassContext& pass, const gpu::Pipeline& pipeline);

  MeshPool& pool_;
  const gpu::Context* context_ = nullptr;
  RendererFormats formats_;
  Pipelines pipelines_;
  PerFrameBuffer indirect_;
  std::vector<VkDrawIndexedIndirectCommand> commands_;  // unmirrored objects, then mirrored ones
  std::uint32_t drawCount_ = 0;
  std::uint32_t mirroredFirst_ = 0;  // index of the first mirrored object's command
  std::uint32_t culledCount_ = 0;
  gpu::IndirectDraws draws_;
};

}  // namespace engine::render
