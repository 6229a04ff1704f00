// glTF import: GLB container check -> JSON sanitising and extension plan -> tinygltf parse
// (gltf_document.h) -> compressed bufferViews decoded -> validated conversion (gltf_convert.h,
// reading through gltf_accessors.h).
//
// tinygltf 2.7 parses the JSON and fetches buffers, but it trusts most indices and offsets, and a few
// of its own reads are unchecked, so it only ever sees input that has passed the checks below:
//  - GLB: it accepts a BIN chunk whose length runs up to 8 bytes past the end of the file (it forgets
//    the chunk header) and then copies from there. The container is validated here and rebuilt.
//  - JSON: it converts `extras`/`extensions` recursively, so a deeply nested document overflows the
//    stack; nesting is limited while parsing here.
//  - images: it indexes buffer.data[bufferView.byteOffset] unchecked for images stored in buffer
//    views, and reads external image files. So images are removed from the JSON before tinygltf
//    sees it (the sanitiser keeps their sources in the ExtensionPlan, and gltf_textures.cpp reads
//    them through the checked bufferView and file paths), and a no-op image loader is installed as
//    a second line of defence.
//  - extensions: tinygltf 2.7 (Debian's build, without Draco) refuses a primitive whose index
//    accessor has no bufferView (every Draco file) and copies the GLB BIN chunk into every buffer
//    without a uri (meshopt's fallback buffers, which hold no data). So the sanitiser lifts
//    `indices` out of the primitives and reads the KHR_draco_mesh_compression and
//    EXT_meshopt_compression objects itself (an ExtensionPlan), and gives fallback buffers a
//    4-byte data: URI; the conversion decodes them (gltf_compression.h).
// The JSON is checked against the glTF 2.0 schema's ranges first (gltf_validate.h: tinygltf drops
// or wraps some out-of-range numbers silently). Everything else tinygltf leaves unchecked (ranges
// against the buffers' real bytes, node graph, finiteness) is checked in the conversion below
#include "engine/scene/gltf/gltf_loader.h"

#include <cstdint>
#include <string>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "engine/core/files.h"
#include "engine/core/log.h"
#include "engine/scene/gltf/gltf_convert.h"
#include "engine/scene/gltf/gltf_document.h"

namespace engine::scene {
namespace {

using namespace gltf;

Expected<SceneData> loadChecked(std::span<const std::uint8_t> bytes, const std::filesystem::path& baseDir,
                                const GltfLoadOptions& options, std::vector<std::string>& warnings) {
  if (bytes.size() > options.maxFileBytes)
    return makeError(fmt::format("{} bytes is over the {}-byte limit for glTF files", bytes.size(), options.maxFileBytes));
  if (bytes.empty()) return makeError("file is empty");
  ENGINE_TRY_ASSIGN(const SanitizedDocument document, sanitizedDocument(bytes, warnings));
  ExternalFileAccess access{baseDir.empty() ? std::string() : baseDir.string(), options.maxFileBytes, {}};
  ENGINE_TRY_ASSIGN(const tinygltf::Model model, parseWithTinygltf(document.bytes, isGlb(bytes), access, warnings));
  ImportContext context{model, document.plan, warnings, decodeBudget(bytes.size(), model), options.scene, {}, &access};
  return convertModel(context);
}

}  // namespace

Expected<SceneData> loadGltfFromMemory(std::span<const std::uint8_t> bytes, std::string_view nameForErrors,
                                       const std::filesystem::path& baseDir, const GltfLoadOptions& options) {
  std::vector<std::string> warnings;
  auto scene = loadChecked(bytes, baseDir, options, warnings).withContext(std::string(nameForErrors));
  for (auto& warning : warnings) {
    warning = fmt::format("{}: {}", nameForErrors, warning);
    log::warn("{}", warning);
  }
  if (scene.ok()) scene->warnings = std::move(warnings);
  return scene;
}

Expected<SceneData> loadGltf(const std::filesystem::path& path, const GltfLoadOptions& options) {
  const std::string name = path.string();
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec && size > options.maxFileBytes)
    return makeError(fmt::format("{}: {} bytes is over the {}-byte limit for glTF files", name, size, options.maxFileBytes));
  ENGINE_TRY_ASSIGN(const auto bytes, readBinaryFile(path, options.maxFileBytes));
  std::filesystem::path baseDir = path.parent_path();
  if (baseDir.empty()) baseDir = ".";
  return loadGltfFromMemory(bytes, name, baseDir, options);
}

Status checkFlattenable(const SceneData& scene, std::uint64_t maxVertices) {
  std::uint64_t vertices = 0;
  std::uint64_t instances = 0;
  for (const auto& node : scene.nodes) {
    if (node.mesh < 0 || std::size_t(node.mesh) >= scene.meshes.size()) continue;
    ++instances;
    for (const auto& primitive : scene.meshes[std::size_t(node.mesh)].primitives) vertices += primitive.positions.size();
  }
  if (vertices <= maxVertices) return {};
  return makeError(fmt::format("its {} mesh instances flatten to {} vertices, over the limit of {} (meshes placed by "
                               "many nodes)",
                               instances, vertices, maxVertices));
}

TriangleSoup flattenTriangles(const SceneData& scene, const glm::dvec3& origin) {
  TriangleSoup soup;
  for (std::size_t n = 0; n < scene.nodes.size(); ++n) {
    const NodeData& node = scene.nodes[n];
    if (node.mesh < 0 || std::size_t(node.mesh) >= scene.meshes.size()) continue;
    const bool mirrored = glm::determinant(node.world) < 0.0f;
    for (const auto& primitive : scene.meshes[std::size_t(node.mesh)].primitives) {
      const std::uint64_t base = soup.positions.size();
      if (base + primitive.positions.size() > std::numeric_limits<std::uint32_t>::max()) {
        log::error("flattenTriangles: node '{}' would push the vertex count past 2^32-1; instance left out", node.name);
        continue;
      }
      const glm::dmat4 world(node.world);
      for (const auto& p : primitive.positions)
        soup.positions.push_back(glm::vec3(glm::dvec3(world * glm::dvec4(glm::dvec3(p), 1.0)) - origin));
      for (std::size_t t = 0; t + 2 < primitive.indices.size(); t += 3) {
        const std::uint32_t a = primitive.indices[t], b = primitive.indices[t + 1], c = primitive.indices[t + 2];
        const auto offset = static_cast<std::uint32_t>(base);
        soup.indices.insert(soup.indices.end(), {offset + a, offset + (mirrored ? c : b), offset + (mirrored ? b : c)});
        soup.triangleNodes.push_back(std::uint32_t(n));
        soup.triangleMaterials.push_back(std::int32_t(primitive.material));
      }
    }
  }
  return soup;
}

}  // namespace engine::scene
