#include "engine/scene/animation.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace engine::scene {
namespace {

glm::quat toQuat(const glm::vec4& v) { return glm::quat(v.w, v.x, v.y, v.z); }
glm::vec4 toVec4(const glm::quat& q) { return glm::vec4(q.x, q.y, q.z, q.w); }

// Spherical interpolation the short way round: q and -q are the same rotation, so the end whose
// dot with the start is negative is flipped first (else the node spins the long way, ~360 - angle).
// glm::slerp flips too, today; the flip here keeps the rule whatever the library does.
glm::vec4 slerpShortest(const glm::vec4& a, glm::vec4 b, float u) {
  if (glm::dot(a, b) < 0.0f) b = -b;
  const glm::quat q = glm::slerp(toQuat(a), toQuat(b), u);
  return toVec4(glm::normalize(q));
}

// The spec's cubic (Appendix C): p(u) = (2u^3-3u^2+1)v0 + (u^3-2u^2+u)h*b0 + (-2u^3+3u^2)v1 + (u^3-u^2)h*a1,
// with h the keyframe interval, b0 the first key's out-tangent and a1 the second's in-tangent.
glm::vec4 cubic(const glm::vec4& v0, const glm::vec4& b0, const glm::vec4& a1, const glm::vec4& v1, float h, float u) {
  const float u2 = u * u;
  const float u3 = u2 * u;
  return (2.0f * u3 - 3.0f * u2 + 1.0f) * v0 + (u3 - 2.0f * u2 + u) * h * b0 + (-2.0f * u3 + 3.0f * u2) * v1 +
         (u3 - u2) * h * a1;
}

// The value of keyframe k (the middle of its triplet for CUBICSPLINE).
glm::vec4 keyValue(const AnimationSampler& sampler, std::size_t k) {
  return sampler.interpolation == Interpolation::CubicSpline ? sampler.values[3 * k + 1] : sampler.values[k];
}

glm::vec4 normalizedIfRotation(const glm::vec4& v, bool isRotation) {
  return isRotation && glm::dot(v, v) > 0.0f ? glm::normalize(v) : v;
}

}  // namespace

glm::vec4 sampleAt(const AnimationSampler& sampler, float t, bool isRotation) {
  const std::vector<float>& times = sampler.times;
  if (times.empty()) return glm::vec4(0.0f);
  if (!(t > times.front())) return normalizedIfRotation(keyValue(sampler, 0), isRotation);
  if (t >= times.back()) return normalizedIfRotation(keyValue(sampler, times.size() - 1), isRotation);
  // times[k] <= t < times[k + 1]
  const std::size_t k = std::size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
  const float h = times[k + 1] - times[k];
  const float u = (t - times[k]) / h;
  switch (sampler.interpolation) {
    case Interpolation::Step: return normalizedIfRotation(keyValue(sampler, k), isRotation);
    case Interpolation::Linear: {
      const glm::vec4 a = sampler.values[k];
      const glm::vec4 b = sampler.values[k + 1];
      return isRotation ? slerpShortest(a, b, u) : a + (b - a) * u;
    }
    case Interpolation::CubicSpline: {
      const auto& v = sampler.values;
      return normalizedIfRotation(cubic(v[3 * k + 1], v[3 * k + 2], v[3 * (k + 1)], v[3 * (k + 1) + 1], h, u), isRotation);
    }
  }
  return keyValue(sampler, k);
}

float duration(const AnimationData& animation) {
  float last = 0.0f;
  for (const AnimationSampler& sampler : animation.samplers)
    if (!sampler.times.empty()) last = std::max(last, sampler.times.back());
  return last;
}

std::vector<NodePose> poseAt(const AnimationData& animation, const std::vector<NodePose>& rest, float t) {
  std::vector<NodePose> pose = rest;
  for (const AnimationChannel& channel : animation.channels) {
    const AnimationSampler& sampler = animation.samplers[std::size_t(channel.sampler)];
    NodePose& node = pose[std::size_t(channel.node)];
    const glm::vec4 value = sampleAt(sampler, t, channel.path == AnimatedPath::Rotation);
    switch (channel.path) {
      case AnimatedPath::Translation: node.translation = glm::vec3(value); break;
      case AnimatedPath::Rotation: node.rotation = toQuat(value); break;
      case AnimatedPath::Scale: node.scale = glm::vec3(value); break;
    }
  }
  return pose;
}

NodePose decompose(const glm::mat4& local) {
  NodePose pose;
  pose.translation = glm::vec3(local[3]);
  pose.scale = glm::vec3(glm::length(glm::vec3(local[0])), glm::length(glm::vec3(local[1])), glm::length(glm::vec3(local[2])));
  // A zero scale (a node hidden by flattening it) has no rotation to recover: the identity, not NaN.
  if (pose.scale.x == 0.0f || pose.scale.y == 0.0f || pose.scale.z == 0.0f) return pose;
  glm::mat3 rotation{glm::vec3(local[0]) / pose.scale.x, glm::vec3(local[1]) / pose.scale.y, glm::vec3(local[2]) / pose.scale.z};
  // A mirroring matrix keeps its mirror in the scale, so that the rotation is a proper one.
  if (glm::determinant(rotation) < 0.0f) {
    pose.scale.x = -pose.scale.x;
    rotation[0] = -rotation[0];
  }
  pose.rotation = glm::normalize(glm::quat_cast(rotation));
  return pose;
}

glm::mat4 composeMatrix(const NodePose& pose) {
  return glm::translate(glm::mat4(1.0f), pose.translation) * glm::mat4_cast(pose.rotation) *
         glm::scale(glm::mat4(1.0f), pose.scale);
}

}  // namespace engine::scene
