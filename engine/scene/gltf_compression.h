#pragma once
// Decoders for the glTF geometry compression extensions, on bytes the glTF importer has already
// range-checked. Both take untrusted input: a malformed stream is an error naming the problem.
//  - EXT_meshopt_compression: one compressed bufferView -> its plain bytes (meshoptimizer's
//    decoders and filters, Debian libmeshoptimizer-dev).
//  - KHR_draco_mesh_compression: one primitive's Draco stream -> positions, normals, triangles
//    (Debian libdraco-dev).
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/expected.h"

namespace engine::scene {

// bufferView.extensions.EXT_meshopt_compression, already checked for types.
struct MeshoptViewDesc {
  std::string mode;    // "ATTRIBUTES", "TRIANGLES" or "INDICES"
  std::string filter;  // "NONE", "OCTAHEDRAL", "QUATERNION" or "EXPONENTIAL"
  std::uint64_t count = 0;
  std::uint64_t byteStride = 0;
};

// Checks the mode / filter / stride combination the extension allows; decoded size count * byteStride.
Status checkMeshoptView(const MeshoptViewDesc& view);

// Decodes `compressed` into count * byteStride bytes (checkMeshoptView first).
Expected<std::vector<std::uint8_t>> decodeMeshoptView(std::span<const std::uint8_t> compressed,
                                                      const MeshoptViewDesc& view);

struct DracoPrimitive {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // empty without a NORMAL attribute id
  std::vector<std::uint32_t> indices;  // triangle list
};

// Decodes a Draco triangle mesh and reads the attributes with the given unique ids (the values of
// the extension's `attributes` object). Every value must be finite and the point count must fit
// 32-bit indices.
Expected<DracoPrimitive> decodeDracoPrimitive(std::span<const std::uint8_t> compressed, std::uint32_t positionId,
                                              std::optional<std::uint32_t> normalId);

}  // namespace engine::scene
