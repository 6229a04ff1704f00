// Viewer::loadScene with SceneDesc::objects: a glTF scene's meshes as separate SDF objects, each
// baked once (hsdf::bakeSceneObjects) and drawn at every node that places it.
#include <algorithm>
#include <chrono>
#include <cstddef>

#include <fmt/format.h>

#include "engine/core/log.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/render/scene_objects.h"
#include "viewer.h"

namespace samples {

using namespace engine;

Status Viewer::addSceneObjects(std::shared_ptr<const scene::SceneData> scene, std::span<const ecs::Entity> nodes,
                               std::span<const ecs::Entity> parts) {
  const scene::SceneData& data = *scene;
  hsdf::SceneObjectOptions options;
  options.defaultDraw = tuning_.nodeDraw;
  options.triangleNodes = tuning_.triangleNodes;
  hsdf::BakeSettings settings;
  settings.resolution = tuning_.resolution;
  settings.padding = tuning_.padding;
  settings.budget = bakeBudget_;
  const auto start = std::chrono::steady_clock::now();
  ENGINE_TRY_ASSIGN(const hsdf::SceneObjects objects, hsdf::bakeSceneObjects(data, options, settings));
  objectEntities_ = hsdf::addSdfInstances(data, objects, nodes, registry_);
  objectScene_ = std::move(scene);
  objectNodes_.assign(nodes.begin(), nodes.end());
  objectOptions_ = options;
  objectBakes_ = objects.bakes;
  bakedResolution_ = settings.resolution;
  bakedPadding_ = settings.padding;
  // The triangles of SDF nodes give way to the SDF; those of triangle nodes always draw.
  for (const ecs::Entity part : parts) {
    const ecs::Entity node = registry_.get<scene::Parent>(part).entity;
    if (std::find(objectEntities_.begin(), objectEntities_.end(), node) != objectEntities_.end())
      meshEntities_.push_back(part);
  }
  std::size_t triangleNodes = 0;
  for (std::size_t n = 0; n < data.nodes.size(); ++n)
    triangleNodes += data.nodes[n].mesh >= 0 && objects.draws[n] == hsdf::NodeDraw::Triangles;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  log::info("{} meshes baked at K = {} in {:.2f} s into {} SDF assets, drawn by {} nodes; {} mesh nodes drawn as "
            "triangles",
            objects.bakes, settings.resolution, seconds, objects.bakes, objectEntities_.size(), triangleNodes);
  return {};
}

// On this thread, as at load (the meshes of a scene bake in parallel inside bakeSceneObjects). A
// failed bake keeps the assets drawn and puts their K back into the tuning.
Status Viewer::rebakeSceneObjects() {
  hsdf::BakeSettings settings;
  settings.resolution = tuning_.resolution;
  settings.padding = tuning_.padding;
  settings.budget = bakeBudget_;
  const auto start = std::chrono::steady_clock::now();
  auto baked = hsdf::bakeSceneObjects(*objectScene_, objectOptions_, settings);
  if (!baked) {
    tuning_.resolution = bakedResolution_;
    tuning_.padding = bakedPadding_;
    return baked.error().withContext(fmt::format("re-baking the scene's objects at resolution {}", settings.resolution));
  }
  const hsdf::SceneObjects& objects = *baked;
  for (std::size_t n = 0; n < objectScene_->nodes.size() && n < objectNodes_.size(); ++n) {
    const int mesh = objectScene_->nodes[n].mesh;
    if (mesh < 0 || objects.draws[n] != hsdf::NodeDraw::Sdf || !objects.meshAssets[std::size_t(mesh)]) continue;
    const ecs::Entity entity = objectNodes_[n];
    const auto& asset = objects.meshAssets[std::size_t(mesh)];
    if (auto* renderable = registry_.tryGet<hsdf::HermiteSdfRenderable>(entity)) renderable->asset = asset;
    for (auto& [hidden, renderable] : hiddenObjects_)  // a mesh method hides them: they draw it when shown
      if (hidden == entity) renderable.asset = asset;
  }
  objectBakes_ += objects.bakes;
  bakedResolution_ = settings.resolution;
  bakedPadding_ = settings.padding;
  log::info("{} meshes baked again at K = {} in {:.2f} s", objects.bakes, settings.resolution,
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return {};
}

// Method::Mesh hides the SDF objects (their renderables wait in hiddenObjects_), an SDF method
// shows them.
void Viewer::updateObjectVisibility(bool sdfShown) {
  if (sdfShown && !hiddenObjects_.empty()) {
    for (auto& [entity, renderable] : hiddenObjects_) registry_.emplace<hsdf::HermiteSdfRenderable>(entity, renderable);
    hiddenObjects_.clear();
  } else if (!sdfShown && hiddenObjects_.empty()) {
    for (const ecs::Entity entity : objectEntities_) {
      hiddenObjects_.emplace_back(entity, registry_.get<hsdf::HermiteSdfRenderable>(entity));
      registry_.remove<hsdf::HermiteSdfRenderable>(entity);
    }
  }
}

}  // namespace samples
