#pragma once
// A glTF scene as separate SDF objects (SceneDesc::objects): each mesh baked once
// (hsdf::bakeSceneObjects) into an asset drawn at every node that places it, except nodes drawn as
// triangles; baked again at a new K, padding or shell, hidden by a mesh method, and with TuningState::lod
// each mesh's levels of detail, chosen per node. The K and padding drawn, the budget and the last
// error are the Viewer's SdfBakes'.
#include <memory>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include "engine/core/expected.h"
#include "engine/ecs/registry.h"
#include "hermite_sdf/render/scene_objects.h"
#include "sdf_bakes.h"
#include "tuning.h"

namespace engine::scene {
struct SceneData;
}

namespace samples {

class SdfObjects {
 public:
  SdfObjects(engine::ecs::Registry& registry, TuningState& tuning, SdfBakes& bakes)
      : registry_(registry), tuning_(tuning), bakes_(bakes) {}

  // Bakes the meshes of `scene` at the tuning's K and padding and draws them at its nodes
  // (`nodes`: the scene's node entities, `parts`: the entities of their mesh primitives); the
  // triangles of SDF nodes go into `meshes` (they give way to the SDF), those of triangle nodes
  // always draw.
  engine::Status add(std::shared_ptr<const engine::scene::SceneData> scene, std::span<const engine::ecs::Entity> nodes,
                     std::span<const engine::ecs::Entity> parts, std::vector<engine::ecs::Entity>& meshes);
  bool loaded() const { return scene_ != nullptr; }
  // A K, padding or shell change: every mesh baked again and every SDF node drawing its mesh's new asset.
  engine::Status rebake();
  // A mesh method hides the SDF nodes, an SDF method shows them.
  void setShown(bool sdfShown);
  // The levels of detail follow TuningState::lod; whether the nodes have levels to choose from
  // this frame (hsdf::selectSdfLevels).
  bool updateLevels();

  // The entities drawing a mesh's shared asset (one per SDF node), and the bakes that made those
  // assets (one per mesh they use).
  const std::vector<engine::ecs::Entity>& entities() const { return entities_; }
  int bakes() const { return bakeCount_; }

 private:
  void dropLevels();
  using HiddenAssets = std::unordered_map<engine::ecs::Entity, std::shared_ptr<const hsdf::SdfAsset>>;
  void setHiddenAssets(const HiddenAssets& assets);

  engine::ecs::Registry& registry_;
  TuningState& tuning_;
  SdfBakes& bakes_;
  // The SDF nodes' entities, their renderables while a mesh method hides them.
  std::vector<engine::ecs::Entity> entities_;
  std::vector<std::pair<engine::ecs::Entity, hsdf::HermiteSdfRenderable>> hidden_;
  int bakeCount_ = 0;
  // What a re-bake at another K needs: the scene, its node entities, the options of the load.
  std::shared_ptr<const engine::scene::SceneData> scene_;
  std::vector<engine::ecs::Entity> nodes_;
  hsdf::SceneObjectOptions options_;
  hsdf::SceneObjects objects_;     // the nodes' draws and the meshes' assets baked at K
  hsdf::SceneObjectLevels levels_;  // with TuningState::lod: [mesh] its levels (empty: none baked)
};

}  // namespace samples
