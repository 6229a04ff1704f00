#pragma once
// Internal to engine_scene (gltf_convert.cpp): the file's animations read into AnimationData, after
// the nodes (channels name SceneData nodes, not file nodes).
#include <vector>

#include "engine/scene/animation.h"
#include "engine/scene/gltf/gltf_accessors.h"

namespace engine::scene::gltf {

// Every animation of the file, in file order (an animation whose channels were all dropped stays, empty,
// so that indices match the file's). A channel that cannot be played is dropped with a warning naming
// the animation, channel and sampler: a bad sampler (times not FLOAT SCALAR, not strictly increasing
// or not finite; an output count unlike the input's, or not three per key for CUBICSPLINE; an
// output of the wrong type or with NaN), a target node missing or outside the loaded scene, a
// `weights` path (morph weights are applied once at import), or a KHR_animation_pointer target.
std::vector<AnimationData> convertAnimations(ImportContext& context);

}  // namespace engine::scene::gltf
