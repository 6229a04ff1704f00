#pragma once
// Playing a SceneData's animations: the nodes' matrices at a time t, from the pose they were loaded in.
#include <vector>

#include <glm/glm.hpp>

#include "engine/scene/animation.h"
#include "engine/scene/scene_data.h"

namespace engine::scene {

// The nodes as loaded (every animation starts from here, so that posing at t never depends on the
// times posed before it).
struct RestPose {
  std::vector<glm::mat4> locals;
  std::vector<NodePose> parts;  // each local in translation, rotation and scale
};
RestPose restPose(const SceneData& scene);

// Sets the local matrix of each node `animation` drives to its pose at time t (the others to their
// rest local matrix) and every node's world matrix. `rest` is restPose(scene) of the loaded scene.
void poseScene(SceneData& scene, const RestPose& rest, const AnimationData& animation, float t);

// The time in one loop of the animation for a time `t` since it started (t itself for t < 0 or an
// animation without duration): viewers loop the animation they play.
float loopTime(const AnimationData& animation, float t);

}  // namespace engine::scene
