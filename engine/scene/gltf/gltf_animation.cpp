#include "engine/scene/gltf/gltf_animation.h"

#include <string>

#include <fmt/format.h>

namespace engine::scene::gltf {
namespace {

Expected<Interpolation> interpolationOf(const std::string& name) {
  if (name == "LINEAR" || name.empty()) return Interpolation::Linear;
  if (name == "STEP") return Interpolation::Step;
  if (name == "CUBICSPLINE") return Interpolation::CubicSpline;
  return makeError(fmt::format("interpolation '{}' is not LINEAR, STEP or CUBICSPLINE", name));
}

Expected<AnimatedPath> pathOf(const tinygltf::AnimationChannel& channel) {
  const std::string& path = channel.target_path;
  if (path == "translation") return AnimatedPath::Translation;
  if (path == "rotation") return AnimatedPath::Rotation;
  if (path == "scale") return AnimatedPath::Scale;
  if (path == "weights")
    return makeError("path 'weights' is not played: morph targets are applied once at import, at the mesh's default "
                     "weights");
  if (path == "pointer") return makeError("KHR_animation_pointer targets are not played");
  return makeError(fmt::format("path '{}' is not translation, rotation, scale or weights", path));
}

Status checkTimes(const std::vector<float>& times) {
  for (std::size_t k = 1; k < times.size(); ++k)
    if (!(times[k] > times[k - 1]))
      return makeError(fmt::format("input times must increase strictly, but key {} is {} after {}", k, times[k], times[k - 1]));
  return {};
}

// Output values as vec4 (xyz for translation and scale; a quaternion xyzw for rotation).
Expected<std::vector<glm::vec4>> readOutput(ImportContext& context, int accessor, AnimatedPath path) {
  if (path == AnimatedPath::Rotation) return readVec4(context, accessor);
  ENGINE_TRY_ASSIGN(const auto vectors, readVec3(context, accessor));
  std::vector<glm::vec4> values;
  values.reserve(vectors.size());
  for (const glm::vec3& v : vectors) values.emplace_back(v, 0.0f);
  return values;
}

Status checkOutputCount(const AnimationSampler& sampler) {
  const std::size_t keys = sampler.times.size();
  const std::size_t perKey = sampler.interpolation == Interpolation::CubicSpline ? 3 : 1;
  if (sampler.values.size() != perKey * keys)
    return makeError(fmt::format("output count {} is not {} ({}the input count{})", sampler.values.size(), perKey * keys,
                                 perKey == 3 ? "3 times " : "",
                                 perKey == 3 ? "; CUBICSPLINE: in-tangent, value, out-tangent per key" : ""));
  return {};
}

Expected<AnimationSampler> readSampler(ImportContext& context, const tinygltf::Animation& animation, int index,
                                       AnimatedPath path) {
  if (!inRange(index, animation.samplers)) return makeError(describeIndexRange("sampler", index, animation.samplers.size()));
  const tinygltf::AnimationSampler& source = animation.samplers[std::size_t(index)];
  const std::string where = fmt::format("sampler {}", index);
  AnimationSampler sampler;
  ENGINE_TRY_ASSIGN(sampler.interpolation, interpolationOf(source.interpolation).withContext(where));
  ENGINE_TRY_ASSIGN(sampler.times, readFloats(context, source.input).withContext(where + " input"));
  ENGINE_TRY(checkTimes(sampler.times).withContext(where + " input"));
  ENGINE_TRY_ASSIGN(sampler.values, readOutput(context, source.output, path).withContext(where + " output"));
  ENGINE_TRY(checkOutputCount(sampler).withContext(where));
  return sampler;
}

Expected<int> targetNode(const ImportContext& context, const tinygltf::AnimationChannel& channel) {
  if (channel.target_node == -1) return makeError("targets no node");
  if (!inRange(channel.target_node, context.model.nodes))
    return makeError(describeIndexRange("target node", channel.target_node, context.model.nodes.size()));
  const int node = context.nodeIndexOf[std::size_t(channel.target_node)];
  if (node < 0) return makeError(fmt::format("target node {} is not in the loaded scene", channel.target_node));
  return node;
}

// One channel with its own copy of its sampler (read as the path's type: a sampler shared by a
// translation and a rotation channel is read twice, which glTF allows but exporters do not write).
Status convertChannel(ImportContext& context, const tinygltf::Animation& source, const tinygltf::AnimationChannel& channel,
                      AnimationData& out) {
  ENGINE_TRY_ASSIGN(const AnimatedPath path, pathOf(channel));
  ENGINE_TRY_ASSIGN(const int node, targetNode(context, channel));
  ENGINE_TRY_ASSIGN(AnimationSampler sampler, readSampler(context, source, channel.sampler, path));
  out.samplers.push_back(std::move(sampler));
  out.channels.push_back(AnimationChannel{int(out.samplers.size() - 1), node, path});
  return {};
}

}  // namespace

std::vector<AnimationData> convertAnimations(ImportContext& context) {
  std::vector<AnimationData> animations;
  for (std::size_t a = 0; a < context.model.animations.size(); ++a) {
    const tinygltf::Animation& source = context.model.animations[a];
    AnimationData animation;
    animation.name = source.name;
    for (std::size_t c = 0; c < source.channels.size(); ++c) {
      const Status converted = convertChannel(context, source, source.channels[c], animation);
      if (!converted.ok())
        context.warnings.push_back(fmt::format("animation {} '{}' channel {}: {}; the channel is not played", a,
                                               source.name, c, converted.error().message));
    }
    animations.push_back(std::move(animation));
  }
  return animations;
}

}  // namespace engine::scene::gltf
