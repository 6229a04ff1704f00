#pragma once
// Internal to engine_scene (gltf_loader.cpp's last stage): the parsed, sanitised model converted
// into SceneData, checking what tinygltf leaves unchecked (ranges against the buffers' real bytes,
// the node graph, finiteness) before any byte is read, and decoding compressed geometry.
#include <cstdint>

#include <tiny_gltf.h>

#include "engine/core/expected.h"
#include "engine/scene/gltf/gltf_accessors.h"
#include "engine/scene/scene_data.h"

namespace engine::scene::gltf {

Expected<SceneData> convertModel(ImportContext& context);

// What decoded geometry may take for a file of `fileBytes` whose buffers `model` holds.
std::uint64_t decodeBudget(std::uint64_t fileBytes, const tinygltf::Model& model);

}  // namespace engine::scene::gltf
