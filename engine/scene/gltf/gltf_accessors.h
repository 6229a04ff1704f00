#pragma once
// Internal to engine_scene (gltf_loader.cpp's conversion): the conversion's context and checked
// reads of the parsed model's accessors, buffers and numbers. Every read is checked against the
// buffers' real bytes and charged to the file's decode budget before any byte is read.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <tiny_gltf.h>

#include "engine/core/expected.h"
#include "engine/scene/gltf/gltf_document.h"

namespace engine::scene::gltf {

struct ImportContext {
  const tinygltf::Model& model;
  const ExtensionPlan& plan;
  std::vector<std::string>& warnings;
  std::uint64_t decodeBudgetBytes = 0;  // what decoded geometry may still take
  int scene = -1;                       // GltfLoadOptions::scene
  std::vector<std::vector<std::uint8_t>> meshoptViews;  // [bufferView]: decoded bytes (empty: not compressed)
  const ExternalFileAccess* files = nullptr;           // where images beside the file are read (null: nowhere)
  std::vector<int> nodeIndexOf;  // [file node]: its index in SceneData::nodes (-1: outside the loaded scene)
};

// Takes `bytes` from the decode budget, or refuses when the budget has less left.
Status chargeDecode(ImportContext& context, std::uint64_t bytes);

std::string describeIndexRange(const char* kind, int index, std::size_t available);

template <class T>
bool inRange(int index, const std::vector<T>& items) {
  return index >= 0 && std::size_t(index) < items.size();
}

Expected<float> toFiniteFloat(double value, std::string_view what);

// A buffer range of the file, checked to lie inside the buffer.
Expected<std::span<const std::uint8_t>> bufferRange(const tinygltf::Model& model, int bufferIndex, std::uint64_t offset,
                                                    std::uint64_t length);
// The bytes of a bufferView: decoded ones for a meshopt-compressed view, else its buffer range.
Expected<std::span<const std::uint8_t>> bufferViewBytes(const ImportContext& context, int viewIndex);

// VEC2 attribute (TEXCOORD_n: float or normalized integers) as floats; every component must be finite.
Expected<std::vector<glm::vec2>> readVec2(ImportContext& context, int accessorIndex);
// VEC3 attribute (POSITION, NORMAL) as floats; every component must be finite.
Expected<std::vector<glm::vec3>> readVec3(ImportContext& context, int accessorIndex);
// VEC4 elements (an instance's ROTATION quaternion: float or normalized integers) as floats; every
// component must be finite.
Expected<std::vector<glm::vec4>> readVec4(ImportContext& context, int accessorIndex);
// SCALAR FLOAT elements (animation keyframe times); every value must be finite.
Expected<std::vector<float>> readFloats(ImportContext& context, int accessorIndex);
// Primitive indices, widened to 32 bits.
Expected<std::vector<std::uint32_t>> readIndices(ImportContext& context, int accessorIndex);

}  // namespace engine::scene::gltf
