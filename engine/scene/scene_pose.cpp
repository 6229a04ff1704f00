#include "engine/scene/scene_pose.h"

#include <cmath>

namespace engine::scene {

RestPose restPose(const SceneData& scene) {
  RestPose rest;
  for (const NodeData& node : scene.nodes) {
    rest.locals.push_back(node.local);
    rest.parts.push_back(decompose(node.local));
  }
  return rest;
}

void poseScene(SceneData& scene, const RestPose& rest, const AnimationData& animation, float t) {
  const std::vector<NodePose> pose = poseAt(animation, rest.parts, t);
  std::vector<bool> animated(scene.nodes.size(), false);
  for (const AnimationChannel& channel : animation.channels) animated[std::size_t(channel.node)] = true;
  for (std::size_t i = 0; i < scene.nodes.size(); ++i) {
    NodeData& node = scene.nodes[i];
    // Nodes that are not animated keep their exact matrix (a decomposed one would round).
    node.local = animated[i] ? composeMatrix(pose[i]) : rest.locals[i];
    node.world = node.parent < 0 ? node.local : scene.nodes[std::size_t(node.parent)].world * node.local;
  }
}

float loopTime(const AnimationData& animation, float t) {
  const float length = duration(animation);
  if (t < 0.0f || !(length > 0.0f)) return t;
  return std::fmod(t, length);
}

}  // namespace engine::scene
