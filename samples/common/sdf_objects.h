#pragma once
// A glTF scene as separate SDF objects (SceneDesc::objects): each mesh baked once
// (hsdf::bakeSceneObjects) into an asset drawn at every node that places it, except nodes drawn as
// triangles; baked when an SDF method first draws them (not at a mesh method's load); baked again at a new K, padding or shell, hidden by a mesh method, and with TuningState::lod
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

  // Takes `scene` (`nodes`: the scene's node entities, `parts`: the entities of their mesh
  // primitives) and checks its nodes' choices; when the tuning's method draws an SDF, bakes its
  // meshes at the tuning's K and padding and draws them at its nodes now, else at the first
  // bakeIfWanted with an SDF method. The triangles of SDF nodes go into `meshes` (they give way to
  // the SDF), those of triangle nodes always draw.
  engine::Status add(std::shared_ptr<const engine::scene::SceneData> scene, std::span<const engine::ecs::Entity> nodes,
                     std::span<const engine::ecs::Entity> parts, std::vector<engine::ecs::Entity>& meshes);
  bool loaded() const { return scene_ != nullptr; }
  // Whether the meshes are baked (false while a mesh method has drawn the scene since its load).
  bool baked() const { return baked_; }
  // The first bake, once the tuning's method draws an SDF (nothing to do otherwise, or when baked).
  // A scene loaded under a mesh method waits for it: the grid scene's load took 5.1-5.4 s for SDFs
  // nothing drew. A failed bake leaves the scene unbaked (its meshes drawn) and returns the error.
  engine::Status bakeIfWanted(std::vector<engine::ecs::Entity>& meshes);
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
  engine::Status bake(std::vector<engine::ecs::Entity>& meshes);
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
  std::vector<engine::ecs::Entity> parts_;  // until the first bake sorts them
  bool baked_ = false;
  hsdf::SceneObjectOptions options_;
  hsdf::SceneObjects objects_;     // the nodes' draws and the meshes' assets baked at K
  hsdf::SceneObjectLevels levels_;  // with TuningState::lod: [mesh] its levels (empty: none baked)
};

}  // namespace samples
