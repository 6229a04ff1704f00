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
  objects_ = objects;
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
  dropObjectLevels();  // the levels of the old K
  const hsdf::SceneObjects& objects = *baked;
  objects_ = objects;
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

// Levels of detail of scene objects: baked on this thread when first wanted, as the objects are at
// load and re-bake (a mesh's levels together cost less than its level 0); every SDF node carries
// its mesh's levels and the module's system picks a level per node from this frame's camera, so
// near and far instances of one mesh draw different levels in the cells' one draw. A failed bake
// turns levels off and keeps level 0.
void Viewer::updateObjectLevels(bool select) {
  if (!tuning_.lod) return dropObjectLevels();
  if (objectLevels_.empty()) {
    hsdf::BakeSettings settings;
    settings.resolution = bakedResolution_;
    settings.padding = bakedPadding_;
    settings.budget = bakeBudget_;
    const auto start = std::chrono::steady_clock::now();
    auto levels = hsdf::bakeSceneObjectLevels(*objectScene_, objects_, settings);
    if (!levels) {
      bakeError_ = levels.error().message;
      log::warn("{} (levels of detail turned off)", bakeError_);
      tuning_.lod = false;
      return;
    }
    objectLevels_ = std::move(*levels);
    const std::size_t nodes = hsdf::addSdfInstanceLevels(*objectScene_, objects_, objectLevels_, objectNodes_,
                                                         tuning_.lodPixelsPerCell, registry_);
    std::size_t assets = 0;
    for (const auto& mesh : objectLevels_) assets += mesh.size();
    log::info("levels of detail: {} assets for {} meshes from K = {} in {:.2f} s, chosen per node for {} nodes", assets,
              objects_.bakes, bakedResolution_,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), nodes);
  }
  registry_.view<hsdf::HermiteSdfLod>().each(
      [this](ecs::Entity, hsdf::HermiteSdfLod& lod) { lod.pixelsPerCell = tuning_.lodPixelsPerCell; });
  if (select) hsdf::selectSdfLevels(registry_, cameraView(), renderer_->extent().height);
}

// Every SDF node back to its mesh's level 0 (shown or hidden by a mesh method), its levels gone.
void Viewer::dropObjectLevels() {
  if (objectLevels_.empty()) return;
  for (const ecs::Entity entity : objectEntities_) {
    const hsdf::HermiteSdfLod* lod = registry_.tryGet<hsdf::HermiteSdfLod>(entity);
    if (!lod || lod->levels.empty()) continue;
    if (auto* renderable = registry_.tryGet<hsdf::HermiteSdfRenderable>(entity)) renderable->asset = lod->levels.front();
    for (auto& [hidden, renderable] : hiddenObjects_)
      if (hidden == entity) renderable.asset = lod->levels.front();
    registry_.remove<hsdf::HermiteSdfLod>(entity);
  }
  objectLevels_.clear();
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
