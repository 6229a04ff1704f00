#pragma once
// Keyframe animation of node transforms (glTF 2.0 "Animations"): samplers of keyframe times and
// values, channels that drive one node's translation, rotation or scale. Evaluation is pure: the
// pose at time t depends on nothing but the animation and t, so a headless frame at a given time is
// the same on every run and every machine.
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace engine::scene {

enum class Interpolation { Linear, Step, CubicSpline };
enum class AnimatedPath { Translation, Rotation, Scale };

// Times strictly increase. Values: one per time (LINEAR, STEP), or three per time for CUBICSPLINE
// (in-tangent, value, out-tangent). Rotations are quaternions stored as vec4 (x, y, z, w), the glTF
// order; translations and scales use xyz.
struct AnimationSampler {
  std::vector<float> times;
  std::vector<glm::vec4> values;
  Interpolation interpolation = Interpolation::Linear;
};

struct AnimationChannel {
  int sampler = 0;  // index into AnimationData::samplers
  int node = 0;     // index into SceneData::nodes
  AnimatedPath path = AnimatedPath::Translation;
};

struct AnimationData {
  std::string name;
  std::vector<AnimationSampler> samplers;
  std::vector<AnimationChannel> channels;
};

// A node's transform in parts, as glTF animation channels replace them one by one.
struct NodePose {
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
  glm::vec3 scale{1.0f};
};

// The sampler's value at time t: before the first keyframe the first value, after the last the last
// (clamped, as glTF viewers do); STEP holds a keyframe's value until the next; LINEAR lerps (slerps
// the shortest way for rotations); CUBICSPLINE follows the spec's cubic with tangents scaled by the
// keyframe interval, and rotations come out normalized.
glm::vec4 sampleAt(const AnimationSampler& sampler, float t, bool isRotation);

// The last keyframe time over all samplers: one loop of the animation (0 for an empty one).
float duration(const AnimationData& animation);

// `rest` (each animated node's pose without the animation) with every channel's part replaced by its
// sampler's value at time t. Channels must be valid (checked at import).
std::vector<NodePose> poseAt(const AnimationData& animation, const std::vector<NodePose>& rest, float t);

NodePose decompose(const glm::mat4& local);  // the local matrix's translation, rotation and scale (no shear)
glm::mat4 composeMatrix(const NodePose& pose);

}  // namespace engine::scene
