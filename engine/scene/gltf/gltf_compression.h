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
  std::vector<glm::vec2> texcoords;  // empty without a TEXCOORD_0 attribute id, or when it cannot be read:
  std::string texcoordProblem;       // then why (a warning: the mesh is drawn without its texture)
  std::vector<std::uint32_t> indices;  // triangle list
};

// The Draco attribute ids (the extension's `attributes` object) of what is decoded.
struct DracoAttributeIds {
  std::uint32_t position = 0;
  std::optional<std::uint32_t> normal;
  std::optional<std::uint32_t> texcoord;
};

// What a Draco triangle-mesh stream declares in its header, read before the decoder runs: the
// decoder sizes its tables from these counts before it reads the data that would contradict them,
// so a stream of a few bytes could otherwise ask for gigabytes.
struct DracoCounts {
  std::uint64_t faces = 0;
  std::uint64_t vertices = 0;  // edgebreaker: encoded position vertices; sequential: points
  // The least the decoded geometry can take: 3 indices per face, a position (a normal, a texture
  // coordinate) per vertex.
  std::uint64_t decodedBytes(const DracoAttributeIds& ids) const {
    return faces * 12 + vertices * (12 + (ids.normal ? 12 : 0) + (ids.texcoord ? 8 : 0));
  }
};

// Reads the header (skipping its metadata) and the connectivity counts of a Draco triangle mesh,
// bitstream versions 1.x and 2.0-2.2 (what libdraco decodes); a cut or unknown header is an error.
Expected<DracoCounts> readDracoCounts(std::span<const std::uint8_t> compressed);

// Decodes a Draco triangle mesh and reads the attributes with the given unique ids (the values of
// the extension's `attributes` object). Every value must be finite and the point count must fit
// 32-bit indices.
Expected<DracoPrimitive> decodeDracoPrimitive(std::span<const std::uint8_t> compressed, const DracoAttributeIds& ids);

}  // namespace engine::scene
