#include "sdf_objects.h"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <unordered_set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/core/log.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/render/scene_objects.h"

namespace samples {

using namespace engine;

Status SdfObjects::add(std::shared_ptr<const scene::SceneData> scene, std::span<const ecs::Entity> nodes,
                       std::span<const ecs::Entity> parts, std::vector<ecs::Entity>& meshes) {
  options_.defaultDraw = tuning_.nodeDraw;
  options_.triangleNodes = tuning_.triangleNodes;
  // Bad extras and unknown node names are refused at load, whichever method draws first.
  ENGINE_TRY(hsdf::chooseNodeDraws(*scene, options_));
  scene_ = std::move(scene);
  nodes_.assign(nodes.begin(), nodes.end());
  parts_.assign(parts.begin(), parts.end());
  if (isSdfMethod(tuning_.method)) return bake(meshes);
  log::info("the scene's {} meshes are baked into SDF objects when an SDF method is chosen", scene_->meshes.size());
  return {};
}

Status SdfObjects::bakeIfWanted(std::vector<ecs::Entity>& meshes) {
  if (!loaded() || baked_ || !isSdfMethod(tuning_.method)) return {};
  return bake(meshes).withContext("baking the scene's meshes into SDF objects");
}

Status SdfObjects::bake(std::vector<ecs::Entity>& meshes) {
  const scene::SceneData& data = *scene_;
  hsdf::BakeSettings settings;
  setBakeKey(bakeKey(tuning_), settings);
  settings.budget = bakes_.budget();
  const auto start = std::chrono::steady_clock::now();
  ENGINE_TRY_ASSIGN(const hsdf::SceneObjects objects, hsdf::bakeSceneObjects(data, options_, settings));
  entities_ = hsdf::addSdfInstances(data, objects, nodes_, registry_);
  baked_ = true;
  bakeCount_ = objects.bakes;
  objects_ = objects;
  bakes_.setBaked(bakeKey(settings));
  // The triangles of SDF nodes give way to the SDF; those of triangle nodes always draw. (A set:
  // a scene of instanced meshes has as many parts as SDF nodes, a million or so.)
  const std::unordered_set<ecs::Entity> sdfNodes(entities_.begin(), entities_.end());
  for (const ecs::Entity part : parts_)
    if (sdfNodes.contains(registry_.get<scene::Parent>(part).entity)) meshes.push_back(part);
  parts_ = {};
  std::size_t triangleNodes = 0;
  for (std::size_t n = 0; n < data.nodes.size(); ++n)
    triangleNodes += data.nodes[n].mesh >= 0 && objects.draws[n] == hsdf::NodeDraw::Triangles &&
                     !data.meshes[std::size_t(data.nodes[n].mesh)].primitives.empty();
  for (const std::string& fallback : objects.fallbacks) log::warn("{}", fallback);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  log::info("{} meshes baked at K = {} in {:.2f} s into {} SDF assets, drawn by {} nodes; {} mesh nodes drawn as "
            "triangles",
            objects.bakes, settings.resolution, seconds,
            std::count_if(objects.meshAssets.begin(), objects.meshAssets.end(), [](const auto& a) { return a != nullptr; }),
            entities_.size(), triangleNodes);
  return {};
}

// On this thread, as at load (the meshes of a scene bake in parallel inside bakeSceneObjects). A
// failed bake keeps the assets drawn and puts their K back into the tuning.
Status SdfObjects::rebake() {
  hsdf::BakeSettings settings;
  setBakeKey(bakeKey(tuning_), settings);
  settings.budget = bakes_.budget();
  const auto start = std::chrono::steady_clock::now();
  auto baked = hsdf::bakeSceneObjects(*scene_, options_, settings);
  // A mesh that is an SDF at one K and cannot be at the other (a thin part gone, or back) would
  // change which nodes draw triangles: the entities were made for the load's choice, so that K is
  // refused, naming the mesh, rather than drawn half.
  if (baked && baked->draws != objects_.draws) {
    const auto list = [](const std::vector<std::string>& fallbacks) {
      return fallbacks.empty() ? std::string("none") : fmt::format("{}", fmt::join(fallbacks, "; "));
    };
    baked = engine::makeError(fmt::format("the meshes drawn as triangles would change (at resolution {}: {}; at the "
                                          "resolution drawn, {}: {}); reload the scene at this resolution",
                                          settings.resolution, list(baked->fallbacks), bakes_.resolution(),
                                          list(objects_.fallbacks)));
  }
  if (!baked) {
    setBakeKey(bakes_.baked(), tuning_);
    return baked.error().withContext(fmt::format("re-baking the scene's objects at resolution {}", settings.resolution));
  }
  dropLevels();  // the levels of the old K
  const hsdf::SceneObjects& objects = *baked;
  objects_ = objects;
  HiddenAssets hiddenAssets;  // a mesh method hides them: they draw the new asset when shown
  for (std::size_t n = 0; n < scene_->nodes.size() && n < nodes_.size(); ++n) {
    const int mesh = scene_->nodes[n].mesh;
    if (mesh < 0 || objects.draws[n] != hsdf::NodeDraw::Sdf || !objects.meshAssets[std::size_t(mesh)]) continue;
    const ecs::Entity entity = nodes_[n];
    const auto& asset = objects.meshAssets[std::size_t(mesh)];
    if (auto* renderable = registry_.tryGet<hsdf::HermiteSdfRenderable>(entity)) renderable->asset = asset;
    else if (!hidden_.empty()) hiddenAssets.emplace(entity, asset);
  }
  setHiddenAssets(hiddenAssets);
  bakeCount_ += objects.bakes;
  bakes_.setBaked(bakeKey(settings));
  log::info("{} meshes baked again at K = {} in {:.2f} s", objects.bakes, settings.resolution,
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return {};
}

// Levels of detail of scene objects: baked on this thread when first wanted, as the objects are at
// load and re-bake (a mesh's levels together cost less than its level 0); every SDF node carries
// its mesh's levels and the module's system picks a level per node from this frame's camera, so
// near and far instances of one mesh draw different levels in the cells' one draw. A failed bake
// turns levels off and keeps level 0. A mesh method draws no SDF: the levels wait until an SDF
// method is picked (baked under --method mesh they cost the load 0.7-1.4 s for the grid scene, and
// went to no node: the renderables were hidden).
bool SdfObjects::updateLevels() {
  if (!tuning_.lod) {
    dropLevels();
    return false;
  }
  if (levels_.empty() && !isSdfMethod(tuning_.method)) return false;
  if (levels_.empty()) {
    hsdf::BakeSettings settings;
    setBakeKey(bakes_.baked(), settings);
    settings.budget = bakes_.budget();
    const auto start = std::chrono::steady_clock::now();
    auto levels = hsdf::bakeSceneObjectLevels(*scene_, objects_, settings);
    if (!levels) {
      bakes_.setError(levels.error().message);
      log::warn("{} (levels of detail turned off)", bakes_.error());
      tuning_.lod = false;
      return false;
    }
    levels_ = std::move(*levels);
    const std::size_t nodes = hsdf::addSdfInstanceLevels(*scene_, objects_, levels_, nodes_,
                                                         tuning_.lodPixelsPerCell, registry_);
    std::size_t assets = 0;
    for (const auto& mesh : levels_) assets += mesh.size();
    log::info("levels of detail: {} assets for {} meshes from K = {} in {:.2f} s, chosen per node for {} nodes", assets,
              objects_.bakes, bakes_.resolution(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), nodes);
  }
  registry_.view<hsdf::HermiteSdfLod>().each(
      [this](ecs::Entity, hsdf::HermiteSdfLod& lod) { lod.pixelsPerCell = tuning_.lodPixelsPerCell; });
  return true;
}

// Every SDF node back to its mesh's level 0 (shown or hidden by a mesh method), its levels gone.
void SdfObjects::dropLevels() {
  if (levels_.empty()) return;
  HiddenAssets hiddenAssets;
  for (const ecs::Entity entity : entities_) {
    const hsdf::HermiteSdfLod* lod = registry_.tryGet<hsdf::HermiteSdfLod>(entity);
    if (!lod || lod->levels.empty()) continue;
    if (auto* renderable = registry_.tryGet<hsdf::HermiteSdfRenderable>(entity)) renderable->asset = lod->levels.front();
    else if (!hidden_.empty()) hiddenAssets.emplace(entity, lod->levels.front());
    registry_.remove<hsdf::HermiteSdfLod>(entity);
  }
  setHiddenAssets(hiddenAssets);
  levels_.clear();
}

// The renderables hidden by a mesh method take these assets (one pass: hidden_ keeps the nodes'
// order, which a shown scene's draw order follows).
void SdfObjects::setHiddenAssets(const HiddenAssets& assets) {
  if (assets.empty()) return;
  for (auto& [entity, renderable] : hidden_)
    if (const auto found = assets.find(entity); found != assets.end()) renderable.asset = found->second;
}

// Method::Mesh hides the SDF objects (their renderables wait in hidden_), an SDF method shows them.
void SdfObjects::setShown(bool sdfShown) {
  if (sdfShown && !hidden_.empty()) {
    for (auto& [entity, renderable] : hidden_) registry_.emplace<hsdf::HermiteSdfRenderable>(entity, renderable);
    hidden_.clear();
  } else if (!sdfShown && hidden_.empty()) {
    for (const ecs::Entity entity : entities_) {
      hidden_.emplace_back(entity, registry_.get<hsdf::HermiteSdfRenderable>(entity));
      registry_.remove<hsdf::HermiteSdfRenderable>(entity);
    }
  }
}

}  // namespace samples
