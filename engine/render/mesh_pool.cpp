#include "engine/render/mesh_pool.h"

#include <stdexcept>
#include <utility>

#include "engine/gpu/context.h"
#include "engine/render/render_feature.h"

namespace engine::render {

MeshHandle MeshPool::add(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                         std::span<const std::uint32_t> indices, std::span<const glm::vec2> texcoords,
                         std::span<const glm::vec4> tangents) {
  if (normals.size() != positions.size()) throw std::invalid_argument("MeshPool::add: one normal per position");
  if (!texcoords.empty() && texcoords.size() != positions.size())
    throw std::invalid_argument("MeshPool::add: texture coordinates for none or every position");
  if (!tangents.empty() && tangents.size() != positions.size())
    throw std::invalid_argument("MeshPool::add: tangents for none or every position");
  MeshRange range;
  range.firstIndex = static_cast<std::uint32_t>(indices_.size());
  range.indexCount = static_cast<std::uint32_t>(indices.size());
  range.vertexOffset = static_cast<std::int32_t>(vertices_.size());
  range.boundsMin = glm::vec3(std::numeric_limits<float>::max());
  range.boundsMax = glm::vec3(std::numeric_limits<float>::lowest());
  for (std::size_t i = 0; i < positions.size(); ++i)
    vertices_.push_back({positions[i], normals[i], texcoords.empty() ? glm::vec2(0.0f) : texcoords[i],
                         tangents.empty() ? glm::vec4(0.0f) : tangents[i]});
  // The bounds of what is drawn: a vertex no triangle uses (a glTF accessor may hold any) must not
  // frame the scene, size its ground or set its near plane.
  for (std::uint32_t index : indices) {
    if (index >= positions.size()) throw std::out_of_range("MeshPool::add: index out of range");
    indices_.push_back(index);
    range.boundsMin = glm::min(range.boundsMin, positions[index]);
    range.boundsMax = glm::max(range.boundsMax, positions[index]);
  }
  ranges_.push_back(range);
  dirty_ = true;
  return MeshHandle{static_cast<std::uint32_t>(ranges_.size() - 1)};
}

void MeshPool::sync(const FrameContext& frame) {
  if (!dirty_ || indices_.empty()) return;
  gpu::Buffer vertices = gpu::createBufferWithData(context_, vertices_.data(), vertices_.size() * sizeof(MeshVertex),
                                                   VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, "mesh pool vertices");
  gpu::Buffer indices = gpu::createBufferWithData(context_, indices_.data(), indices_.size() * sizeof(std::uint32_t),
                                                  VK_BUFFER_USAGE_INDEX_BUFFER_BIT, "mesh pool indices");
  if (vertexBuffer_) frame.retire(std::move(vertexBuffer_));
  if (indexBuffer_) frame.retire(std::move(indexBuffer_));
  vertexBuffer_ = std::move(vertices);
  indexBuffer_ = std::move(indices);
  dirty_ = false;
}

}  // namespace engine::render
