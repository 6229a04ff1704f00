#pragma once
// Plays one of a glTF scene's animations on the entities of its nodes: each frame step sets the
// Transform of every node the animation drives to its pose at the time played (looped), then moves
// the clock on. The triangles and the per-node SDF objects (--objects) follow through the nodes'
// world transforms: rigid motion, no re-bake.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/expected.h"
#include "engine/ecs/registry.h"
#include "engine/scene/scene_data.h"
#include "engine/scene/scene_pose.h"

namespace samples {

// The animation a SceneDesc asks for: by index or name; "none" plays nothing. An empty `which` means
// the first one (glTF viewers play one animation at a time, the first by default). A file without
// animations plays nothing. Errors name the file's animations.
engine::Expected<std::optional<std::size_t>> chooseAnimation(const engine::scene::SceneData& scene, std::string_view which);

class AnimationPlayer {
 public:
  AnimationPlayer(engine::scene::AnimationData animation, engine::scene::RestPose rest, float startSeconds);
  // The entities of SceneData::nodes (render::instantiateScene's), which step() moves.
  void attach(std::vector<engine::ecs::Entity> nodes) { nodes_ = std::move(nodes); }
  const engine::scene::RestPose& rest() const { return rest_; }
  // Poses the nodes at the time played now, then moves the clock on by `seconds`.
  void step(engine::ecs::Registry& registry, float seconds);
  float time() const { return time_; }

 private:
  engine::scene::AnimationData animation_;
  engine::scene::RestPose rest_;
  std::vector<engine::ecs::Entity> nodes_;  // entity of SceneData::nodes[i]
  float time_ = 0.0f;
};

}  // namespace samples
