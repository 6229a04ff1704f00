#include "animation_player.h"

#include <charconv>

#include <fmt/format.h>

#include "engine/scene/transform.h"

namespace samples {

using namespace engine;

namespace {

std::string animationNames(const scene::SceneData& scene) {
  std::string names;
  for (std::size_t a = 0; a < scene.animations.size(); ++a)
    names += fmt::format("{}{} '{}'", a == 0 ? "" : ", ", a, scene.animations[a].name);
  return names.empty() ? "none" : names;
}

}  // namespace

Expected<std::optional<std::size_t>> chooseAnimation(const scene::SceneData& scene, std::string_view which) {
  if (which == "none" || (which.empty() && scene.animations.empty())) return std::optional<std::size_t>{};
  if (which.empty()) return std::optional<std::size_t>{0};
  for (std::size_t a = 0; a < scene.animations.size(); ++a)
    if (scene.animations[a].name == which) return std::optional<std::size_t>{a};
  std::size_t index = 0;
  const auto [end, error] = std::from_chars(which.data(), which.data() + which.size(), index);
  if (error == std::errc() && end == which.data() + which.size() && index < scene.animations.size())
    return std::optional<std::size_t>{index};
  return makeError(fmt::format("--animation '{}': no such animation (the file has: {})", which, animationNames(scene)));
}

AnimationPlayer::AnimationPlayer(scene::AnimationData animation, scene::RestPose rest, float startSeconds)
    : animation_(std::move(animation)), rest_(std::move(rest)), time_(startSeconds) {}

void AnimationPlayer::step(ecs::Registry& registry, float seconds) {
  const std::vector<scene::NodePose> pose = scene::poseAt(animation_, rest_.parts, scene::loopTime(animation_, time_));
  for (const scene::AnimationChannel& channel : animation_.channels) {
    const scene::NodePose& node = pose[std::size_t(channel.node)];
    registry.get<scene::Transform>(nodes_[std::size_t(channel.node)]) = scene::Transform{node.translation, node.rotation, node.scale};
  }
  time_ += seconds;
}

}  // namespace samples
