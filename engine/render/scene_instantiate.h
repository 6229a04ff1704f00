#pragma once
// Turns imported scene data into entities: one entity per node (Transform, Parent, Name), one child
// entity per mesh primitive (MeshRenderable, uploaded into the MeshPool), Camera on camera nodes.
#include <vector>

#include "engine/ecs/registry.h"
#include "engine/render/mesh_pool.h"
#include "engine/scene/scene_data.h"

namespace engine::render {

struct InstantiatedScene {
  std::vector<ecs::Entity> nodes;        // entity of SceneData::nodes[i]
  std::vector<ecs::Entity> renderables;  // entities carrying a MeshRenderable
  std::vector<ecs::Entity> cameras;
  glm::vec3 boundsMin{0.0f};             // world bounds of all mesh vertices
  glm::vec3 boundsMax{0.0f};
};

// The entities get Transform, Parent and Name (and MeshRenderable); their WorldTransform comes
// from scene::updateWorldTransforms(registry), which the program runs before renderFrame.
InstantiatedScene instantiateScene(const scene::SceneData& data, ecs::Registry& registry, MeshPool& pool);

}  // namespace engine::render
