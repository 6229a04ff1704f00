#pragma once
// Draws every entity with MeshRenderable + WorldTransform: depth in the prepass, lit colour in the
// shading pass (depth EQUAL). Objects outside the view frustum are culled on the CPU. Any invertible
// affine world matrix: normals go through the inverse transpose, and objects whose matrix mirrors
// (negative determinant, e.g. a glTF node scaled by -1) are drawn in a second batch that takes
// clockwise triangles as front faces (dynamic state), so back-face culling keeps their outside.
// Double-sided meshes (MeshRenderable::doubleSided, glTF material doubleSided) are drawn after the
// single-sided ones, by pipelines without culling, in both passes; the same front-face state says
// which side the eye sees (gl_FrontFacing), and mesh.frag lights a back face with its normal
// reversed. Meshes with textures (MeshRenderable::textures) are drawn in one batch per material's
// set of textures, the set bound before the batch (MeshTextures: no descriptor indexing needed);
// the rest sample the white texels of set 0. Each batch is two indirect draws (unmirrored,
// mirrored). Meshes with an alpha cutoff (MeshRenderable::alphaCutoff, glTF
// alphaMode MASK) are drawn in the prepass by pipelines of their own (mesh_prepass_masked.frag):
// where a fragment's alpha is below the cutoff it writes the far plane's depth, which the depth
// test rejects, so nothing of it is kept and what lies behind shows; the shading pass then finds
// another surface's depth there (EQUAL) and draws nothing. The opaque meshes' prepass is unchanged.
// Blended meshes (MeshRenderable::alphaBlend, glTF alphaMode BLEND) are in neither the prepass nor
// the shading pass: they are drawn in the renderer's transparent pass, over the finished opaque
// frame (SDF objects included), by mesh.frag's lighting (mesh_blended.frag) with straight-alpha
// blending (glTF's base colour is straight alpha: colour x alpha + frame x (1 - alpha)), tested
// GREATER_OR_EQUAL against the prepass depth (a pane laid on a surface with the same triangles is
// drawn, not lost) and writing none; so they hide nothing behind them, and the visibility buffer
// and hit offsets never name them. They are sorted back to front each frame on the CPU by the view
// distance of their bounds' centre, and drawn in that order (runs of neighbours that share a
// texture and winding in one multi-draw). A double-sided one draws its back faces, then its front
// faces (glTF leaves the order within a mesh undefined; the near side then lies over the far side
// of a convex mesh). The normals and depth views, which show the surfaces of the depth buffer, draw
// no blended mesh; the other views draw them as the frame does.
// The shading and transparent passes draw each mesh by a pipeline of its material's variant
// (Variant): without textures, with textures but no normal texture, with a normal texture (mesh.frag
// compiled with its defines; the cheaper ones hold fewer live values and draw the same pixels);
// batches are grouped by variant within a cull mode and cut-out state, so each is one pipeline change.
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
  bool hasTransparentDraws() const override { return !blendedBatches_.empty(); }
  void recordTransparent(PassContext& pass) override;
  void drawUi() override;
  Status reloadShaders() override;

  std::uint32_t drawnLastFrame() const { return drawCount_; }

 private:
  enum class Sides : std::uint8_t { Single = 0, Double = 1 };  // back faces culled / drawn
  // What a material reads (mesh.frag's variants): no texture, textures but no normal texture, a
  // normal texture (MeshRenderable::normalScale not 0).
  enum class Variant : std::uint8_t { Untextured = 0, Textured = 1, NormalMapped = 2 };
  static constexpr std::size_t kVariants = 3;
  // Draws of one cull mode, one variant, one texture and either opaque or cut out, in commands_:
  // [first, mirroredFirst) unmirrored, then [mirroredFirst, end) mirrored. Batches are drawn
  // single-sided first, then opaque before cut out, then by variant, then by texture. A blended
  // batch is a run of draws in back-to-front order, all mirrored or none.
  struct Batch {
    Sides sides = Sides::Single;
    bool masked = false;
    Variant variant = Variant::Untextured;
    TextureHandle texture;
    std::uint32_t first = 0;
    std::uint32_t mirroredFirst = 0;
    std::uint32_t end = 0;
  };
  struct PendingDraw;
  static Variant variantOf(const MeshRenderable& mesh, std::uint32_t texture);
  void buildBatches(std::vector<PendingDraw>& draws);
  void buildBlendedBatches(std::vector<PendingDraw>& draws);
  void append(std::vector<Batch>& batches, const PendingDraw& draw, bool joinsLast);
  struct Pipelines {
    std::array<gpu::Pipeline, 2> depth;  // by Sides
    std::array<gpu::Pipeline, 2> depthMasked;
    std::array<std::array<gpu::Pipeline, kVariants>, 2> shade;  // by Sides, then Variant
    std::array<gpu::Pipeline, kVariants> blended;  // both sides: the cull mode is dynamic
  };
  Expected<Pipelines> createPipelines() const;
  const gpu::Pipeline& pipelineOf(const Batch& batch, bool prepass) const;
  void bindPipeline(PassContext& pass, const gpu::Pipeline& pipeline) const;
  void recordBatch(PassContext& pass, const Batch& batch) const;

  MeshPool& pool_;
  const gpu::Context* context_ = nullptr;
  RendererFormats formats_;
  Pipelines pipelines_;
  PerFrameBuffer indirect_;
  std::vector<VkDrawIndexedIndirectCommand> commands_;  // the batches' draws, in batch order
  std::vector<Batch> batches_;
  std::vector<Batch> blendedBatches_;  // back to front, after batches_'s draws in commands_
  std::uint32_t drawCount_ = 0;
  std::uint32_t blendedCount_ = 0;
  std::uint32_t doubleSidedCount_ = 0;
  std::uint32_t culledCount_ = 0;
  gpu::IndirectDraws draws_;
};

}  // namespace engine::render
