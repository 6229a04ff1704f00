#include "engine/render/scene_instantiate.h"

#include <limits>

#include "engine/render/components.h"
#include "engine/scene/transform.h"

namespace engine::render {
namespace {

void uploadMeshes(const scene::SceneData& data, MeshPool& pool,
                                                   std::vector<std::vector<MeshHandle>>& handles) {
  handles.resize(data.meshes.size());
  for (std::size_t m = 0; m < data.meshes.size(); ++m)
    for (const auto& primitive : data.meshes[m].primitives)
      handles[m].push_back(pool.add(primitive.positions, primitive.normals, primitive.indices));
}

}  // namespace

InstantiatedScene instantiateScene(const scene::SceneData& data, ecs::Registry& registry, MeshPool& pool) {
  InstantiatedScene result;
  std::vector<std::vector<MeshHandle>> handles;
  uploadMeshes(data, pool, handles);
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());

  for (std::size_t n = 0; n < data.nodes.size(); ++n) {
    const scene::NodeData& node = data.nodes[n];
    const ecs::Entity entity = registry.create();
    result.nodes.push_back(entity);
    registry.emplace<scene::Transform>(entity, scene::fromMatrix(node.local));
    registry.emplace<scene::Name>(entity, scene::Name{node.name});
    if (node.parent >= 0 && std::size_t(node.parent) < n)
      registry.emplace<scene::Parent>(entity, scene::Parent{result.nodes[std::size_t(node.parent)]});
    if (node.camera >= 0 && std::size_t(node.camera) < data.cameras.size()) {
      const scene::CameraData& camera = data.cameras[std::size_t(node.camera)];
      registry.emplace<Camera>(entity, Camera{camera.yfov, camera.znear});
      result.cameras.push_back(entity);
    }
    if (node.mesh < 0 || std::size_t(node.mesh) >= data.meshes.size()) continue;
    const scene::MeshData& mesh = data.meshes[std::size_t(node.mesh)];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const scene::MeshPrimitiveData& primitive = mesh.primitives[p];
      MeshRenderable renderable;
      renderable.mesh = handles[std::size_t(node.mesh)][p];
      if (primitive.material >= 0 && std::size_t(primitive.material) < data.materials.size()) {
        const scene::MaterialData& material = data.materials[std::size_t(primitive.material)];
        renderable.color = material.baseColor;
        renderable.roughness = material.roughness;
        renderable.metallic = material.metallic;
      }
      const ecs::Entity part = registry.create();
      registry.emplace<scene::Transform>(part);
      registry.emplace<scene::Parent>(part, scene::Parent{entity});
      registry.emplace<MeshRenderable>(part, renderable);
      result.renderables.push_back(part);
      // What the triangles use (MeshPool::add's bounds): an unused vertex must not frame the scene.
      for (const std::uint32_t index : primitive.indices) {
        const glm::vec3 world = glm::vec3(node.world * glm::vec4(primitive.positions[index], 1.0f));
        lo = glm::min(lo, world);
        hi = glm::max(hi, world);
      }
    }
  }
  if (!result.renderables.empty()) {
    result.boundsMin = lo;
    result.boundsMax = hi;
  }
  return result;
}

}  // namespace engine::render
