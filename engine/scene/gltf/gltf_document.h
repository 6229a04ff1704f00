#pragma once
// Internal to engine_scene (gltf_loader.cpp's first stages): the file as a document tinygltf may
// parse. The GLB container is checked and rebuilt, the JSON checked against the schema's ranges
// (gltf_validate.h), its nesting limited, its images removed and its compression extensions read
// into an ExtensionPlan (tinygltf 2.7 cannot read them); then tinygltf parses it with file access
// confined to the caller's folder. See gltf_loader.cpp for why each check exists.
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "engine/core/expected.h"
#include "engine/scene/gltf/gltf_compression.h"

namespace engine::scene::gltf {

struct DracoExtension {
  int bufferView = -1;
  std::map<std::string, std::uint32_t> attributes;  // semantic -> Draco attribute unique id
};

struct MeshoptExtension {
  int buffer = -1;
  std::uint64_t byteOffset = 0;
  std::uint64_t byteLength = 0;
  MeshoptViewDesc desc;
};

// A glTF image as the sanitiser read it (tinygltf never sees images: gltf_loader.cpp).
struct ImageSource {
  std::string name;
  std::string uri;      // a data: URI or a file relative to the .gltf's folder; empty with a bufferView
  int bufferView = -1;  // -1: none
};

// What the sanitiser read from the JSON for the conversion, indexed like tinygltf's arrays.
struct ExtensionPlan {
  std::vector<ImageSource> images;                                      // [image]
  std::vector<std::vector<int>> primitiveIndices;                       // [mesh][primitive]: accessor, -1 none
  std::vector<std::vector<std::optional<DracoExtension>>> draco;        // [mesh][primitive]
  std::vector<std::optional<MeshoptExtension>> meshopt;                 // [bufferView]
  std::vector<bool> fallbackBuffer;                                     // [buffer]: meshopt fallback, no data
};

// The document handed to tinygltf, and what the sanitiser read from it.
struct SanitizedDocument {
  std::vector<std::uint8_t> bytes;  // sanitised JSON, or a GLB rebuilt around the sanitised JSON
  ExtensionPlan plan;
};

// External files may only come from the base directory the caller named, and not be too large.
struct ExternalFileAccess {
  std::string baseDir;  // empty: no external files at all
  std::uint64_t maxBytes = 0;
  std::string problem;  // why the last lookup failed, for the error message
};

bool isGlb(std::span<const std::uint8_t> bytes);

// A file named by a URI relative to the glTF file's folder (an image), with the checks external
// buffers get: none without a folder, none outside it, none over the size limit.
Expected<std::vector<std::uint8_t>> readFileBesideGltf(const ExternalFileAccess& access, const std::string& uri);

// The sanitised document of a glTF or GLB file's bytes; errors name the problem.
Expected<SanitizedDocument> sanitizedDocument(std::span<const std::uint8_t> bytes, std::vector<std::string>& warnings);

// `document` is sanitised JSON text or a rebuilt GLB.
Expected<tinygltf::Model> parseWithTinygltf(std::span<const std::uint8_t> document, bool binary,
                                            ExternalFileAccess& access, std::vector<std::string>& warnings);

}  // namespace engine::scene::gltf
