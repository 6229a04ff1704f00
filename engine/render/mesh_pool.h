#pragma once
// All triangle meshes in two GPU buffers (vertices and indices), so every mesh draw of a pass is
// one indirect multi-draw with no rebinding. Adding a mesh rebuilds the buffers (rare: at load).
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "engine/gpu/buffer.h"
#include "engine/render/components.h"
#include "engine/render/mesh_textures.h"

namespace engine::render {

struct MeshVertex {
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec2 texcoord;  // glTF TEXCOORD_0; (0, 0) for a mesh without
  glm::vec4 tangent;   // glTF TANGENT (w: handedness); 0 for a mesh without (mesh.frag's derivative frame)
};
static_assert(sizeof(MeshVertex) == 48);

struct MeshRange {
  std::uint32_t firstIndex = 0;
  std::uint32_t indexCount = 0;
  std::int32_t vertexOffset = 0;
  glm::vec3 boundsMin{0.0f};
  glm::vec3 boundsMax{0.0f};
};

struct FrameContext;

class MeshPool {
 public:
  explicit MeshPool(const gpu::Context& context) : context_(context), textures_(context) {}

  // Copies the mesh; it reaches the GPU at the next sync() (render::MeshFeature calls it in its
  // prepare(): a program drawing through the mesh feature never calls it). Indices must be <
  // positions.size(); `texcoords` and `tangents` are each empty or one per position.
  MeshHandle add(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                 std::span<const std::uint32_t> indices, std::span<const glm::vec2> texcoords = {},
                 std::span<const glm::vec4> tangents = {});
  const MeshRange& range(MeshHandle mesh) const { return ranges_[mesh.index]; }
  std::uint32_t meshCount() const { return static_cast<std::uint32_t>(ranges_.size()); }

  // Uploads pending meshes into new buffers; the old ones, which frames in flight and this frame's
  // earlier view regions may draw from, are retired with the frame (FrameContext::retire).
  void sync(const FrameContext& frame);
  const gpu::Buffer& vertexBuffer() const { return vertexBuffer_; }
  const gpu::Buffer& indexBuffer() const { return indexBuffer_; }
  bool empty() const { return indices_.empty(); }
  // The meshes' material textures (MeshRenderable::textures).
  MeshTextures& textures() { return textures_; }
  const MeshTextures& textures() const { return textures_; }

 private:
  const gpu::Context& context_;
  std::vector<MeshVertex> vertices_;
  std::vector<std::uint32_t> indices_;
  std::vector<MeshRange> ranges_;
  bool dirty_ = false;
  gpu::Buffer vertexBuffer_;
  gpu::Buffer indexBuffer_;
  MeshTextures textures_;
};

}  // namespace engine::render
