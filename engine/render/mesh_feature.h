#pragma once
// Draws every entity with MeshRenderable + WorldTransform: depth in the prepass, lit colour in the
// shading pass (depth EQUAL). Objects outside the view frustum are culled on the CPU. Any invertible
// affine world matrix: normals go through the inverse transpose, and objects whose matrix mirrors
// (negative determinant, e.g. a glTF node scaled by -1) are drawn in a second batch that takes
// clockwise triangles as front faces (dynamic state), so back-face culling keeps their outside.
// Double-sided meshes (MeshRenderable::doubleSided, glTF material doubleSided) are drawn after the
// single-sided ones, by pipelines without culling, in both passes; the same front-face state says
// which side the eye sees (gl_FrontFacing), and mesh.frag lights a back face with its normal
// reversed. Each cull mode's pipeline draws its objects in two indirect draws (unmirrored, mirrored).
// Objects whose matrix cannot be inverted (scaled to zero) are skipped.
#include <array>
#include <cstddef>
#include <cstdint>
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
  enum class Sides : std::uint8_t { Single = 0, Double = 1 };  // back faces culled / drawn
  // Draw batches in the order drawn: (single, unmirrored), (single, mirrored), (double, ...), ...
  static constexpr std::size_t kBatchCount = 4;
  static constexpr std::size_t batchOf(Sides sides, bool mirrored) {
    return std::size_t(sides) * 2 + (mirrored ? 1 : 0);
  }
  struct Pipelines {
    std::array<gpu::Pipeline, 2> depth;  // by Sides
    std::array<gpu::Pipeline, 2> shade;
  };
  Expected<Pipelines> createPipelines() const;
  void recordDraws(PassContext& pass, const gpu::Pipeline& pipeline, Sides sides);

  MeshPool& pool_;
  const gpu::Context* context_ = nullptr;
  RendererFormats formats_;
  Pipelines pipelines_;
  PerFrameBuffer indirect_;
  std::vector<VkDrawIndexedIndirectCommand> commands_;  // the batches, in batchOf order
  std::uint32_t drawCount_ = 0;
  std::array<std::uint32_t, kBatchCount + 1> batchFirst_{};  // each batch's first command; then drawCount_
  std::uint32_t culledCount_ = 0;
  gpu::IndirectDraws draws_;
};

}  // namespace engine::render
