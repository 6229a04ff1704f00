#pragma once
// The Viewer scene's one SDF entity (baked from a glTF scene or an analytic shape, or read from a
// .hsdf file) and its bakes: the re-bake at a new K, padding or shell on a worker thread (hsdf::BakeJob;
// the old field keeps drawing until the new one is ready), its coarser levels of detail
// (TuningState::lod), and the fallback to the old field when the GPU refuses the new one. A failed
// or refused bake puts the tuning back to what is drawn; the reason stays in error().
#include <memory>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "engine/core/expected.h"
#include "engine/ecs/registry.h"
#include "hermite_sdf/core/bake_job.h"
#include "hermite_sdf/render/renderable.h"
#include "tuning.h"

namespace engine::render {
class Renderer;
}

namespace samples {

class SdfBakes {
 public:
  // The entity lives in `registry`; `tuning` is the Viewer's (bakes follow it and put it back).
  SdfBakes(engine::ecs::Registry& registry, TuningState& tuning) : registry_(registry), tuning_(tuning) {}

  // The SDF entity, drawing `asset` with the tuning (and the color of setColor) at `offset`.
  void add(std::shared_ptr<const hsdf::SdfAsset> asset, const glm::vec3& offset);
  // What re-bakes are made from (none for a .hsdf file: canRebake() is false).
  // `origin`: where the source's space lies in the world (a scene far from the world origin is
  // baked about its centre, Viewer::loadGltf); the SDF entity is placed there.
  void setSource(hsdf::BakeSource source, const glm::vec3& origin = glm::vec3(0.0f)) {
    source_ = std::move(source);
    origin_ = origin;
  }
  const hsdf::BakeSource* source() const { return source_ ? &*source_ : nullptr; }
  // The SDF looks like the mesh it stands for.
  void setColor(const glm::vec4& color) { color_ = color; }
  void setBudget(const hsdf::BakeBudget& budget) { budget_ = budget; }
  const hsdf::BakeBudget& budget() const { return budget_; }
  // A bake at the tuning's K, padding, shell and band, within the budget.
  hsdf::BakeSettings settings() const;

  const std::optional<engine::ecs::Entity>& entity() const { return entity_; }
  // The entity's renderable (shown or hidden by the method), or null.
  hsdf::HermiteSdfRenderable* renderable();
  const hsdf::SdfAsset* asset() const;
  // The asset baked at resolution() (level 0 when levels of detail draw another), or null.
  std::shared_ptr<const hsdf::SdfAsset> bakedAsset();
  // Hides the renderable (kept here) or shows it again.
  void setShown(bool shown);
  // The K, padding and shell drawn (also those of the scene objects: Viewer::addSceneObjects).
  const BakeKey& baked() const { return baked_; }
  int resolution() const { return baked_.resolution; }
  void setBaked(const BakeKey& key) { baked_ = key; }

  // Starts a re-bake when the tuning asks for another field than is drawn or being baked (or for
  // the first one, when an SDF method or a comparison is picked in a scene loaded as meshes).
  void followTuning();
  hsdf::BakeJob* job() { return job_.get(); }
  // The level of detail being baked, or null.
  hsdf::BakeJob* levelJob() { return levelJob_.get(); }
  // Swaps the finished re-bake's asset into the entity (waiting for it).
  engine::Status finish();
  // Cancels the re-bake, else the level of detail being baked (finished by the next step).
  void cancel();
  // Stops every bake (the Viewer closing).
  void stop();
  // Why the last bake failed or was refused (budget, cancelled), or empty.
  const std::string& error() const { return error_; }
  void setError(std::string error) { error_ = std::move(error); }

  // The levels of detail follow TuningState::lod (finishing every level when `wait`); whether the
  // entity has levels to choose from this frame (hsdf::selectSdfLevels).
  bool updateLevels(bool wait);
  // After the first frame that drew a re-baked field: the old field back if the GPU refused the
  // new one (the error, also in error()).
  std::optional<std::string> restoreRefused(engine::render::Renderer& renderer);

 private:
  void start();
  void startLevels(std::shared_ptr<const hsdf::SdfAsset> finest);
  void startNextLevel(const hsdf::BakeSettings& previous);
  engine::Status finishLevels(bool wait);

  engine::ecs::Registry& registry_;
  TuningState& tuning_;
  std::optional<hsdf::BakeSource> source_;
  glm::vec3 origin_{0.0f};
  std::optional<engine::ecs::Entity> entity_;
  std::optional<hsdf::HermiteSdfRenderable> hidden_;  // the renderable while a mesh method hides it
  std::optional<glm::vec4> color_;
  BakeKey baked_;
  std::unique_ptr<hsdf::BakeJob> job_;
  std::unique_ptr<hsdf::BakeJob> levelJob_;  // the next coarser level of detail (TuningState::lod)
  // The field a finished re-bake replaced, kept until the first frame after the swap has shown
  // whether the GPU took the new one (restoreRefused).
  struct ReplacedField {
    std::shared_ptr<const hsdf::SdfAsset> asset;
    BakeKey key;
  };
  ReplacedField replaced_;
  hsdf::BakeBudget budget_;
  std::string error_;
};

}  // namespace samples
