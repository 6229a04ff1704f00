// glTF model -> SceneData (gltf_convert.h): primitives, materials and cameras, nodes, the whole model.
#include "engine/scene/gltf/gltf_convert.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include "engine/core/log.h"
#include "engine/core/named_list.h"
#include "engine/scene/gltf/gltf_animation.h"
#include "engine/scene/tangents.h"
#include "engine/scene/gltf/gltf_compression.h"
#include "engine/scene/gltf/gltf_textures.h"
#include "engine/scene/transform.h"

namespace engine::scene::gltf {
namespace {

// Decoded geometry may legitimately be larger than its encoding (uint8 indices become uint32,
// quantized positions become floats, normals are generated), but a small file must not be able
// to demand gigabytes by referencing one accessor from thousands of primitives.
constexpr std::uint64_t kDecodeBudgetFloorBytes = std::uint64_t(64) << 20;
constexpr std::uint64_t kDecodeBudgetPerInputByte = 16;
// Mesh instances a file may place through EXT_mesh_gpu_instancing: each becomes a scene node (an
// entity, a draw or an SDF instance), so a forged count of billions must stop here.
constexpr std::size_t kMaxMeshInstances = std::size_t(1) << 20;
constexpr std::string_view kInstancingExtension = "EXT_mesh_gpu_instancing";
constexpr std::string_view kEmissiveStrengthExtension = "KHR_materials_emissive_strength";

using Json = nlohmann::json;

// ---------------------------------------------------------------------------------------------
// Primitives

Expected<std::vector<std::uint32_t>> sequentialIndices(ImportContext& context, std::size_t vertexCount) {
  ENGINE_TRY(chargeDecode(context, std::uint64_t(vertexCount) * sizeof(std::uint32_t)));
  std::vector<std::uint32_t> indices(vertexCount);
  for (std::size_t i = 0; i < vertexCount; ++i) indices[i] = static_cast<std::uint32_t>(i);
  return indices;
}

// Triangle strips and fans as lists, with the vertex order the glTF specification gives (so the
// winding of every triangle matches the first one).
Expected<std::vector<std::uint32_t>> toTriangleList(int mode, std::vector<std::uint32_t> indices) {
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    if (indices.size() % 3 != 0)
      return makeError(fmt::format("{} indices do not make whole triangles", indices.size()));
    return indices;
  }
  std::vector<std::uint32_t> list;
  if (indices.size() < 3) return list;
  list.reserve((indices.size() - 2) * 3);
  for (std::size_t i = 0; i + 2 < indices.size(); ++i) {
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      const std::size_t odd = i % 2;
      list.insert(list.end(), {indices[i], indices[i + 1 + odd], indices[i + 2 - odd]});
    } else {  // fan
      list.insert(list.end(), {indices[i + 1], indices[i + 2], indices[0]});
    }
  }
  return list;
}

// Smooth normals: each triangle adds its unnormalised face normal (length = twice its area) to its
// corners, so large triangles weigh more than slivers. Accumulated in double so that positions near
// the float range do not overflow the cross products. Vertices without area get +Y.
std::vector<glm::vec3> smoothNormals(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& indices) {
  std::vector<glm::dvec3> sums(positions.size(), glm::dvec3(0.0));
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const glm::dvec3 a = positions[indices[t]];
    const glm::dvec3 b = positions[indices[t + 1]];
    const glm::dvec3 c = positions[indices[t + 2]];
    const glm::dvec3 faceNormal = glm::cross(b - a, c - a);
    for (std::size_t k = 0; k < 3; ++k) sums[indices[t + k]] += faceNormal;
  }
  std::vector<glm::vec3> normals(positions.size());
  for (std::size_t v = 0; v < sums.size(); ++v) {
    const double length = glm::length(sums[v]);
    normals[v] = length > 0.0 && std::isfinite(length) ? glm::vec3(sums[v] / length) : glm::vec3(0.0f, 1.0f, 0.0f);
  }
  return normals;
}

int findAttribute(const tinygltf::Primitive& primitive, const char* name) {
  const auto it = primitive.attributes.find(name);
  return it == primitive.attributes.end() ? -2 : it->second;  // -2: absent (-1 could be in the file)
}

Status checkIndicesInRange(const std::vector<std::uint32_t>& indices, std::size_t vertexCount) {
  for (std::size_t i = 0; i < indices.size(); ++i)
    if (indices[i] >= vertexCount)
      return makeError(fmt::format("index {} (at position {}) is out of range of the {} vertices", indices[i], i, vertexCount));
  return {};
}

// Which primitive of which mesh, with what the sanitiser lifted out of it.
struct PrimitiveRef {
  const tinygltf::Primitive& primitive;
  int indices = -1;                          // index accessor, -1 none
  const DracoExtension* draco = nullptr;     // KHR_draco_mesh_compression, when compressed
  const std::vector<double>& morphWeights;   // the mesh's default morph target weights (may be empty)
};

Expected<std::vector<std::uint32_t>> readPrimitiveTriangles(ImportContext& context, const PrimitiveRef& ref,
                                                            std::size_t vertexCount) {
  std::vector<std::uint32_t> indices;
  if (ref.indices >= 0) {
    ENGINE_TRY_ASSIGN(indices, readIndices(context, ref.indices).withContext("indices"));
  } else {
    ENGINE_TRY_ASSIGN(indices, sequentialIndices(context, vertexCount));
  }
  ENGINE_TRY(checkIndicesInRange(indices, vertexCount));
  return toTriangleList(ref.primitive.mode, std::move(indices));
}

// The accessor a primitive names for `semantic` must exist; its count is what the decoded
// attribute must have (KHR_draco_mesh_compression keeps count, type and bounds in the accessors).
Expected<std::uint64_t> accessorCount(const ImportContext& context, int accessorIndex, const char* what) {
  if (!inRange(accessorIndex, context.model.accessors))
    return makeError(fmt::format("{}: {}", what, describeIndexRange("accessor", accessorIndex, context.model.accessors.size())));
  return std::uint64_t(context.model.accessors[std::size_t(accessorIndex)].count);
}

// libdraco sizes its tables from the stream's declared counts before reading the data that would
// contradict them (a 1 KB stream declaring 10^9 faces allocates gigabytes): the least those counts
// decode to must fit what the file may still decode (the charge itself follows the decoding).
Status checkDracoCounts(const ImportContext& context, std::span<const std::uint8_t> compressed, const DracoAttributeIds& ids) {
  ENGINE_TRY_ASSIGN(const DracoCounts declared, readDracoCounts(compressed));
  const std::uint64_t bytes = declared.decodedBytes(ids);
  if (bytes > context.decodeBudgetBytes)
    return makeError(fmt::format("the Draco stream declares {} faces and {} vertices ({} bytes decoded), over the limit for "
                                 "this file ({} bytes left)",
                                 declared.faces, declared.vertices, bytes, context.decodeBudgetBytes));
  return {};
}

// The ids of the Draco attributes the primitive is drawn with (its extension's `attributes`).
Expected<DracoAttributeIds> dracoAttributeIds(const DracoExtension& draco) {
  const auto id = [&](const char* semantic) -> std::optional<std::uint32_t> {
    const auto found = draco.attributes.find(semantic);
    return found == draco.attributes.end() ? std::nullopt : std::optional(found->second);
  };
  const auto position = id("POSITION");
  if (!position) return makeError("KHR_draco_mesh_compression has no POSITION attribute");
  return DracoAttributeIds{*position, id("NORMAL"), id("TEXCOORD_0")};
}

// Positions, indices and (when compressed too) normals and texture coordinates from the primitive's
// Draco stream, checked against the counts its accessors declare. A TEXCOORD_0 that cannot be read
// is a warning, as an uncompressed one (readTexcoords).
Expected<MeshPrimitiveData> decodeDracoGeometry(ImportContext& context, const PrimitiveRef& ref, const std::string& where) {
  const DracoExtension& draco = *ref.draco;
  if (ref.primitive.mode != TINYGLTF_MODE_TRIANGLES)
    return makeError(fmt::format("KHR_draco_mesh_compression on mode {} (only TRIANGLES is supported)", ref.primitive.mode));
  ENGINE_TRY_ASSIGN(const DracoAttributeIds ids, dracoAttributeIds(draco));
  ENGINE_TRY_ASSIGN(const auto compressed, bufferViewBytes(context, draco.bufferView).withContext("KHR_draco_mesh_compression"));
  ENGINE_TRY(checkDracoCounts(context, compressed, ids).withContext("KHR_draco_mesh_compression"));
  ENGINE_TRY_ASSIGN(const DracoPrimitive decoded, decodeDracoPrimitive(compressed, ids).withContext("KHR_draco_mesh_compression"));
  ENGINE_TRY(chargeDecode(context, (decoded.positions.size() + decoded.normals.size()) * sizeof(glm::vec3) +
                                       decoded.texcoords.size() * sizeof(glm::vec2) +
                                       decoded.indices.size() * sizeof(std::uint32_t)));
  if (!decoded.texcoordProblem.empty())
    context.warnings.push_back(fmt::format("{}: TEXCOORD_0 not read: {}", where, decoded.texcoordProblem));
  ENGINE_TRY_ASSIGN(const std::uint64_t vertexCount, accessorCount(context, findAttribute(ref.primitive, "POSITION"), "POSITION"));
  if (decoded.positions.size() != vertexCount)
    return makeError(fmt::format("the Draco stream has {} points but the POSITION accessor says {}", decoded.positions.size(),
                                 vertexCount));
  if (ref.indices >= 0) {
    ENGINE_TRY_ASSIGN(const std::uint64_t indexCount, accessorCount(context, ref.indices, "indices"));
    if (decoded.indices.size() != indexCount)
      return makeError(fmt::format("the Draco stream has {} indices but the indices accessor says {}", decoded.indices.size(),
                                   indexCount));
  }
  MeshPrimitiveData out;
  out.positions = decoded.positions;
  out.normals = decoded.normals;
  out.texcoords = decoded.texcoords;
  out.indices = decoded.indices;
  return out;
}

Expected<MeshPrimitiveData> readUncompressedGeometry(ImportContext& context, const PrimitiveRef& ref) {
  MeshPrimitiveData out;
  const int positionAccessor = findAttribute(ref.primitive, "POSITION");
  ENGINE_TRY_ASSIGN(out.positions, readVec3(context, positionAccessor).withContext("POSITION"));
  if (out.positions.size() > std::numeric_limits<std::uint32_t>::max())
    return makeError(fmt::format("{} vertices do not fit 32-bit indices", out.positions.size()));
  ENGINE_TRY_ASSIGN(out.indices, readPrimitiveTriangles(context, ref, out.positions.size()));
  return out;
}

// The NORMAL accessor, or smooth normals when the primitive has none.
Expected<std::vector<glm::vec3>> readOrGenerateNormals(ImportContext& context, const tinygltf::Primitive& primitive,
                                                       const MeshPrimitiveData& geometry) {
  const int normalAccessor = findAttribute(primitive, "NORMAL");
  if (normalAccessor == -2) {
    ENGINE_TRY(chargeDecode(context, geometry.positions.size() * sizeof(glm::vec3)));
    return smoothNormals(geometry.positions, geometry.indices);
  }
  ENGINE_TRY_ASSIGN(auto normals, readVec3(context, normalAccessor).withContext("NORMAL"));
  if (normals.size() != geometry.positions.size())
    return makeError(fmt::format("NORMAL has {} elements but POSITION has {}", normals.size(), geometry.positions.size()));
  return normals;
}

// glTF's shape of a mesh with morph targets when nothing animates it: the base plus each target's
// offsets (`semantic`: POSITION or NORMAL) times the mesh's default weight (a shape key an artist
// left at a non-zero value is exported so). Targets of weight 0 are not read.
Status addMorphTargets(ImportContext& context, const PrimitiveRef& ref, const char* semantic, std::vector<glm::vec3>& values) {
  const auto& targets = ref.primitive.targets;
  const auto& weights = ref.morphWeights;
  if (targets.empty() || weights.empty()) return {};
  if (weights.size() != targets.size())
    return makeError(fmt::format("the mesh has {} morph weights for {} morph targets", weights.size(), targets.size()));
  for (std::size_t t = 0; t < targets.size(); ++t) {
    const std::string where = fmt::format("morph target {} {}", t, semantic);
    ENGINE_TRY_ASSIGN(const float weight, toFiniteFloat(weights[t], "morph weight").withContext(where));
    const auto accessor = targets[t].find(semantic);
    if (weight == 0.0f || accessor == targets[t].end()) continue;
    ENGINE_TRY_ASSIGN(const auto offsets, readVec3(context, accessor->second).withContext(where));
    if (offsets.size() != values.size())
      return makeError(fmt::format("{}: {} elements for {} vertices", where, offsets.size(), values.size()));
    for (std::size_t v = 0; v < values.size(); ++v) values[v] += weight * offsets[v];
  }
  return {};
}

// Morphed normals are sums of unit vectors and offsets: normalized again (a zero sum keeps +Y, as
// smoothNormals does).
void renormalize(std::vector<glm::vec3>& normals) {
  for (auto& n : normals) {
    const float length = glm::length(n);
    n = length > 0.0f && std::isfinite(length) ? n / length : glm::vec3(0.0f, 1.0f, 0.0f);
  }
}

// TEXCOORD_0 (what a base colour texture is read through). The importer did not read it before
// textures were drawn, so a broken one is a warning, not an error: the primitive keeps no texture
// coordinates and is drawn in its material's factor, as it was. (A Draco primitive's come from its
// stream when the extension's `attributes` name them, decodeDracoGeometry; else from the accessor,
// as KHR_draco_mesh_compression has the attributes it does not compress read as usual.)
void readTexcoords(ImportContext& context, const PrimitiveRef& ref, const std::string& where, MeshPrimitiveData& out) {
  const int accessor = findAttribute(ref.primitive, "TEXCOORD_0");
  if (accessor == -2 || (ref.draco && ref.draco->attributes.contains("TEXCOORD_0"))) return;
  auto texcoords = readVec2(context, accessor);
  if (!texcoords.ok()) {
    context.warnings.push_back(fmt::format("{}: TEXCOORD_0 not read: {}", where, texcoords.error().message));
    return;
  }
  if (texcoords->size() != out.positions.size()) {
    context.warnings.push_back(fmt::format("{}: TEXCOORD_0 not read: {} elements for {} positions", where,
                                           texcoords->size(), out.positions.size()));
    return;
  }
  out.texcoords = std::move(*texcoords);
}

// TANGENT (the normal texture's frame; glTF: "when tangents are specified, client implementations
// SHOULD use them"). As TEXCOORD_0, a broken one is a warning: the primitive keeps no tangents and
// its normal texture is read in the frame of the screen derivatives, as before tangents were read.
// glTF says tangents given with no normals MUST be ignored (flat normals); a Draco primitive's are
// in its stream, not decoded.
void readTangents(ImportContext& context, const PrimitiveRef& ref, const std::string& where, MeshPrimitiveData& out) {
  const int accessor = findAttribute(ref.primitive, "TANGENT");
  if (accessor == -2 || out.flatNormals) return;
  if (ref.draco) {
    context.warnings.push_back(fmt::format("{}: TANGENT of a Draco-compressed primitive not read (generated from the texcoords instead)", where));
    return;
  }
  auto tangents = readVec4(context, accessor);
  if (!tangents.ok()) {
    context.warnings.push_back(fmt::format("{}: TANGENT not read: {}", where, tangents.error().message));
    return;
  }
  if (tangents->size() != out.positions.size()) {
    context.warnings.push_back(fmt::format("{}: TANGENT not read: {} elements for {} positions", where, tangents->size(),
                                           out.positions.size()));
    return;
  }
  for (glm::vec4& t : *tangents) t.w = t.w < 0.0f ? -1.0f : 1.0f;  // glTF's w is +-1: its sign, whatever quantization left
  out.tangents = std::move(*tangents);
}

Expected<MeshPrimitiveData> convertTrianglePrimitive(ImportContext& context, const PrimitiveRef& ref, const std::string& where) {
  const auto& primitive = ref.primitive;
  if (findAttribute(primitive, "POSITION") == -2) return makeError("has no POSITION attribute");
  MeshPrimitiveData out;
  if (ref.draco) {
    ENGINE_TRY_ASSIGN(out, decodeDracoGeometry(context, ref, where));
  } else {
    ENGINE_TRY_ASSIGN(out, readUncompressedGeometry(context, ref));
  }

  const bool morphed = !ref.draco && !primitive.targets.empty() && !ref.morphWeights.empty();
  if (morphed) ENGINE_TRY(addMorphTargets(context, ref, "POSITION", out.positions));
  if (out.normals.empty()) {  // not decoded from Draco with the positions
    out.flatNormals = findAttribute(primitive, "NORMAL") == -2;
    ENGINE_TRY_ASSIGN(out.normals, readOrGenerateNormals(context, primitive, out));
    if (morphed && !out.flatNormals) {  // generated normals already follow the morphed positions
      ENGINE_TRY(addMorphTargets(context, ref, "NORMAL", out.normals));
      renormalize(out.normals);
    }
  }

  if (primitive.material != -1 && !inRange(primitive.material, context.model.materials))
    return makeError(describeIndexRange("material", primitive.material, context.model.materials.size()));
  out.material = primitive.material;
  return out;
}

// The sanitiser's plan has one entry per primitive tinygltf parsed; anything else is a bug here.
Expected<PrimitiveRef> primitiveRef(const ImportContext& context, int meshIndex, std::size_t p) {
  const auto& plan = context.plan;
  const auto m = std::size_t(meshIndex);
  if (m >= plan.primitiveIndices.size() || p >= plan.primitiveIndices[m].size())
    return makeError("internal error: the primitive is missing from the extension plan");
  const auto& draco = plan.draco[m][p];
  const auto& mesh = context.model.meshes[m];
  return PrimitiveRef{mesh.primitives[p], plan.primitiveIndices[m][p], draco ? &*draco : nullptr, mesh.weights};
}

bool isTriangleMode(int mode) {
  return mode == TINYGLTF_MODE_TRIANGLES || mode == TINYGLTF_MODE_TRIANGLE_STRIP || mode == TINYGLTF_MODE_TRIANGLE_FAN;
}

bool isPointOrLineMode(int mode) { return mode >= TINYGLTF_MODE_POINTS && mode <= TINYGLTF_MODE_LINE_STRIP; }

const char* pointOrLineModeName(int mode) {
  constexpr std::array<const char*, 4> kNames{"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"};
  return kNames[std::size_t(mode)];
}

// Points and lines (a DCC file's guides, curves, helper wires) are skipped: every method draws
// triangles. Said once for the file, naming a few (a CAD export has thousands of curves), since a
// mesh of them alone draws nothing, with any method, one SDF or --objects.
void notePointAndLinePrimitives(const tinygltf::Model& model, std::vector<std::string>& warnings) {
  std::vector<std::string> named;
  std::size_t total = 0;
  for (std::size_t m = 0; m < model.meshes.size(); ++m)
    for (std::size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
      const int mode = model.meshes[m].primitives[p].mode;
      if (!isPointOrLineMode(mode)) continue;
      if (named.size() < kNamedInMessages)
        named.push_back(fmt::format("mesh {} '{}' primitive {} ({})", m, model.meshes[m].name, p, pointOrLineModeName(mode)));
      ++total;
    }
  if (total == 0) return;
  warnings.push_back(fmt::format("{} primitive{} of points or lines {} not drawn (only triangles are drawn): {}", total,
                                 total == 1 ? "" : "s", total == 1 ? "is" : "are", namedList(named, total)));
}

Expected<MeshData> convertMesh(ImportContext& context, int meshIndex) {
  const auto& mesh = context.model.meshes[std::size_t(meshIndex)];
  MeshData out;
  out.name = mesh.name;
  for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
    const auto& primitive = mesh.primitives[p];
    const std::string where = fmt::format("mesh {} '{}' primitive {}", meshIndex, mesh.name, p);
    if (isPointOrLineMode(primitive.mode)) continue;  // said once for the file: notePointAndLinePrimitives
    if (!isTriangleMode(primitive.mode)) return makeError(fmt::format("{}: unknown mode {}", where, primitive.mode));
    ENGINE_TRY_ASSIGN(const PrimitiveRef ref, primitiveRef(context, meshIndex, p).withContext(where));
    ENGINE_TRY_ASSIGN(auto converted, convertTrianglePrimitive(context, ref, where).withContext(where));
    readTexcoords(context, ref, where, converted);
    readTangents(context, ref, where, converted);
    if (ref.draco && !primitive.targets.empty() && !mesh.weights.empty())  // libdraco may reorder the points
      context.warnings.push_back(fmt::format("{}: morph targets of a Draco-compressed primitive are not applied", where));
    if (converted.indices.empty()) {  // a strip or fan of fewer than 3 vertices: nothing to draw
      context.warnings.push_back(fmt::format("{}: mode {} with fewer than 3 vertices has no triangles, skipped", where,
                                             primitive.mode));
      continue;
    }
    out.primitives.push_back(std::move(converted));
  }
  return out;
}

// A normal-mapped primitive without TANGENT gets generated ones (glTF: clients SHOULD), made from
// the texcoords as its material's textures read them (after KHR_texture_transform). Without them the
// normal texture is read in the screen-derivative frame, which turns with each triangle of a curved
// surface. Flat normals (no NORMAL in the file) keep that frame: it is each face's exact frame.
void addMissingTangents(const std::vector<MaterialData>& materials, const std::string& where,
                        MeshPrimitiveData& primitive, std::vector<std::string>& warnings) {
  const bool normalMapped = primitive.material >= 0 && std::size_t(primitive.material) < materials.size() &&
                            materials[std::size_t(primitive.material)].normalTexture >= 0;
  if (!normalMapped || !primitive.tangents.empty() || primitive.flatNormals || primitive.texcoords.empty()) return;
  auto tangents = generateTangents(primitive);
  if (!tangents) {
    warnings.push_back(fmt::format("{}: tangents not generated ({}): the normal texture is read in the screen-derivative "
                                   "frame",
                                   where, tangents.error().message));
    return;
  }
  primitive.tangents = std::move(*tangents);
}

// ---------------------------------------------------------------------------------------------
// Materials and cameras

// What of a material the renderer does not draw, named in one note: silently, it would look like a
// rendering defect. (A texture that cannot be drawn gets its own warning.)
std::optional<std::string> ignoredMaterialFields(const tinygltf::Material& material) {
  std::vector<std::string> ignored;
  if (material.alphaMode != "OPAQUE" && material.alphaMode != "MASK" && material.alphaMode != "BLEND")
    ignored.push_back(fmt::format("alphaMode '{}', which glTF does not define (drawn opaque)", material.alphaMode));
  if (ignored.empty()) return std::nullopt;
  return fmt::format("'{}': {} ignored", material.name, fmt::join(ignored, ", "));
}

// emissiveFactor (checkGltfSchema: 3 numbers in [0, 1]) times KHR_materials_emissive_strength's
// emissiveStrength (>= 0; 1 when absent), which lets a lamp glow brighter than 1.
Expected<glm::vec3> emission(const tinygltf::Material& material) {
  if (material.emissiveFactor.size() != 3)
    return makeError(fmt::format("emissiveFactor has {} components, expected 3", material.emissiveFactor.size()));
  double strength = 1.0;
  const auto extension = material.extensions.find(std::string(kEmissiveStrengthExtension));
  if (extension != material.extensions.end() && extension->second.Has("emissiveStrength"))
    strength = extension->second.Get("emissiveStrength").GetNumberAsDouble();
  glm::vec3 emissive;
  for (int c = 0; c < 3; ++c) {
    ENGINE_TRY_ASSIGN(emissive[c], toFiniteFloat(material.emissiveFactor[std::size_t(c)] * strength, "emission"));
  }
  return emissive;
}

Expected<MaterialData> convertMaterial(const tinygltf::Material& material) {
  const auto& pbr = material.pbrMetallicRoughness;
  if (pbr.baseColorFactor.size() != 4)
    return makeError(fmt::format("baseColorFactor has {} components, expected 4", pbr.baseColorFactor.size()));
  MaterialData out;
  out.name = material.name;
  for (int c = 0; c < 4; ++c) {
    ENGINE_TRY_ASSIGN(const float value, toFiniteFloat(pbr.baseColorFactor[std::size_t(c)], "baseColorFactor component"));
    out.baseColor[c] = std::clamp(value, 0.0f, 1.0f);
  }
  ENGINE_TRY_ASSIGN(const float metallic, toFiniteFloat(pbr.metallicFactor, "metallicFactor"));
  ENGINE_TRY_ASSIGN(const float roughness, toFiniteFloat(pbr.roughnessFactor, "roughnessFactor"));
  out.metallic = std::clamp(metallic, 0.0f, 1.0f);
  out.roughness = std::clamp(roughness, 0.0f, 1.0f);
  out.doubleSided = material.doubleSided;  // a boolean (checkGltfSchema), false when absent
  ENGINE_TRY_ASSIGN(out.emissive, emission(material));
  // occlusionTexture.strength: in [0, 1] (glTF's schema; clamped as the factors are), 1 when absent.
  ENGINE_TRY_ASSIGN(const float strength, toFiniteFloat(material.occlusionTexture.strength, "occlusionTexture strength"));
  out.occlusionStrength = std::clamp(strength, 0.0f, 1.0f);
  // normalTexture.scale: any finite number (glTF gives no range), 1 when absent.
  ENGINE_TRY_ASSIGN(out.normalScale, toFiniteFloat(material.normalTexture.scale, "normalTexture scale"));
  if (material.alphaMode == "MASK") {  // alphaCutoff: >= 0 (checkGltfSchema), 0.5 when absent
    ENGINE_TRY_ASSIGN(const float cutoff, toFiniteFloat(material.alphaCutoff, "alphaCutoff"));
    out.alphaCutoff = cutoff;
  }
  out.alphaBlend = material.alphaMode == "BLEND";  // the alpha: baseColor's (kept above) times the texture's
  return out;
}

Expected<CameraData> convertPerspectiveCamera(const tinygltf::Camera& camera) {
  const auto& p = camera.perspective;
  CameraData out;
  out.name = camera.name;
  ENGINE_TRY_ASSIGN(out.yfov, toFiniteFloat(p.yfov, "yfov"));
  ENGINE_TRY_ASSIGN(out.znear, toFiniteFloat(p.znear, "znear"));
  if (!(out.yfov > 0.0f && out.yfov < glm::pi<float>()))
    return makeError(fmt::format("yfov {} is not in (0, pi)", out.yfov));
  if (!(out.znear > 0.0f)) return makeError(fmt::format("znear {} is not positive", out.znear));
  if (p.zfar != 0.0) {  // tinygltf's 0 means absent: infinite projection
    ENGINE_TRY_ASSIGN(const float zfar, toFiniteFloat(p.zfar, "zfar"));
    if (!(zfar > out.znear)) return makeError(fmt::format("zfar {} is not beyond znear {}", zfar, out.znear));
    out.zfar = zfar;
  }
  if (p.aspectRatio != 0.0) {
    ENGINE_TRY_ASSIGN(const float aspect, toFiniteFloat(p.aspectRatio, "aspectRatio"));
    if (!(aspect > 0.0f)) return makeError(fmt::format("aspectRatio {} is not positive", aspect));
    out.aspectRatio = aspect;
  }
  return out;
}

// glTF 2.0 orthographic: xmag and ymag non-zero (a negative one, which the schema discourages,
// would mirror the image: refused too), zfar > znear >= 0, all required.
Expected<CameraData> convertOrthographicCamera(const tinygltf::Camera& camera) {
  const auto& o = camera.orthographic;
  CameraData out;
  out.name = camera.name;
  out.orthographic = true;
  ENGINE_TRY_ASSIGN(out.xmag, toFiniteFloat(o.xmag, "xmag"));
  ENGINE_TRY_ASSIGN(out.ymag, toFiniteFloat(o.ymag, "ymag"));
  ENGINE_TRY_ASSIGN(out.znear, toFiniteFloat(o.znear, "znear"));
  ENGINE_TRY_ASSIGN(const float zfar, toFiniteFloat(o.zfar, "zfar"));
  if (!(out.xmag > 0.0f)) return makeError(fmt::format("xmag {} is not positive", out.xmag));
  if (!(out.ymag > 0.0f)) return makeError(fmt::format("ymag {} is not positive", out.ymag));
  if (!(out.znear >= 0.0f)) return makeError(fmt::format("znear {} is negative", out.znear));
  if (!(zfar > out.znear)) return makeError(fmt::format("zfar {} is not beyond znear {}", zfar, out.znear));
  out.zfar = zfar;
  return out;
}

// Fills scene.cameras with the file's cameras, in file order (the parser refuses a type other than
// perspective and orthographic); returns, for each file camera, its index in scene.cameras.
Expected<std::vector<int>> convertCameras(ImportContext& context, SceneData& scene) {
  std::vector<int> remap;
  for (std::size_t i = 0; i < context.model.cameras.size(); ++i) {
    const auto& camera = context.model.cameras[i];
    Expected<CameraData> converted = camera.type == "orthographic" ? convertOrthographicCamera(camera)
                                                                   : convertPerspectiveCamera(camera);
    ENGINE_TRY_ASSIGN(auto valid, std::move(converted).withContext(fmt::format("camera {} '{}'", i, camera.name)));
    remap.push_back(int(scene.cameras.size()));
    scene.cameras.push_back(std::move(valid));
  }
  return remap;
}

// ---------------------------------------------------------------------------------------------
// Nodes

// translate(t) * rotate(r: a quaternion stored x, y, z, w as glTF does; normalized here) * scale(s).
Expected<glm::mat4> trsMatrix(const glm::vec3& t, const glm::vec4& r, const glm::vec3& s) {
  const float rotationLength = glm::length(r);
  if (!(rotationLength > 0.0f) || !std::isfinite(rotationLength))
    return makeError("rotation quaternion has zero (or non-finite) length");
  const glm::quat q = glm::quat(r.w, r.x, r.y, r.z) / rotationLength;
  return glm::translate(glm::mat4(1.0f), t) * glm::mat4_cast(q) * glm::scale(glm::mat4(1.0f), s);
}

// Whether `m` is its own TRS decomposition up to an exporter's rounding (4 digits): the 3x3 part within 1e-4
// of its longest column, the bottom row (0, 0, 0, 1) within 1e-6.
bool isTrsMatrix(const glm::mat4& m, const glm::mat4& trs) {
  float longest = 0.0f;
  for (int c = 0; c < 3; ++c) longest = std::max(longest, glm::length(glm::vec3(m[c])));
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      if (!(std::abs(m[c][r] - trs[c][r]) <= 1e-4f * longest)) return false;
  for (int c = 0; c < 4; ++c)
    if (!(std::abs(m[c][3] - trs[c][3]) <= 1e-6f)) return false;
  return true;
}

// glTF requires a node's `matrix` to be translation * rotation * scale, but some exporters write
// shear or a projective row. An entity's Transform holds TRS only, so the triangles would be drawn
// by the TRS part and the SDF baked by the whole matrix: every path takes the TRS part, with a
// warning naming the node (`where`).
glm::mat4 trsPartOf(const glm::mat4& m, const std::string& where, std::vector<std::string>& warnings) {
  const glm::mat4 trs = toMatrix(fromMatrix(m));
  // Columns too long for a float's square (1e19) have no float decomposition: kept as they are.
  const bool decomposed = std::isfinite(glm::determinant(glm::mat3(trs)));
  if (!decomposed || isTrsMatrix(m, trs)) return m;
  warnings.push_back(fmt::format("{}: its matrix shears or projects, which glTF forbids (a matrix must be "
                                 "translation * rotation * scale); drawn as its translation, rotation and scale",
                                 where));
  return trs;
}

Expected<glm::mat4> localMatrix(const tinygltf::Node& node, const std::string& where, std::vector<std::string>& warnings) {
  if (!node.matrix.empty()) {  // glTF allows matrix or TRS; with both, tinygltf keeps only the matrix
    if (node.matrix.size() != 16) return makeError(fmt::format("matrix has {} elements, expected 16", node.matrix.size()));
    glm::mat4 m(1.0f);
    for (std::size_t i = 0; i < 16; ++i) {  // glTF and GLM are both column-major
      ENGINE_TRY_ASSIGN(glm::value_ptr(m)[i], toFiniteFloat(node.matrix[i], "matrix element"));
    }
    return trsPartOf(m, where, warnings);
  }
  auto vectorOf = [](const std::vector<double>& values, std::size_t size, const char* name, glm::vec4 fallback) -> Expected<glm::vec4> {
    if (values.empty()) return fallback;
    if (values.size() != size) return makeError(fmt::format("{} has {} elements, expected {}", name, values.size(), size));
    for (std::size_t i = 0; i < size; ++i) {
      ENGINE_TRY_ASSIGN(fallback[int(i)], toFiniteFloat(values[i], name));
    }
    return fallback;
  };
  ENGINE_TRY_ASSIGN(const glm::vec4 t, vectorOf(node.translation, 3, "translation", glm::vec4(0.0f)));
  ENGINE_TRY_ASSIGN(const glm::vec4 r, vectorOf(node.rotation, 4, "rotation", glm::vec4(0.0f, 0.0f, 0.0f, 1.0f)));
  ENGINE_TRY_ASSIGN(const glm::vec4 s, vectorOf(node.scale, 3, "scale", glm::vec4(1.0f)));
  return trsMatrix(glm::vec3(t), r, glm::vec3(s));
}

// EXT_mesh_gpu_instancing: the local matrices of a node's mesh instances (translation, rotation
// and scale per instance, each attribute optional), or none when the node has no such extension.
// `placed`: the instances of the nodes before it, counted against kMaxMeshInstances.
Expected<std::vector<glm::mat4>> meshInstances(ImportContext& context, const tinygltf::Node& node, std::size_t placed) {
  const auto extension = node.extensions.find(std::string(kInstancingExtension));
  if (extension == node.extensions.end()) return std::vector<glm::mat4>{};
  const tinygltf::Value& value = extension->second;
  if (!value.IsObject() || !value.Has("attributes") || !value.Get("attributes").IsObject())
    return makeError("attributes is missing or not an object");
  const tinygltf::Value& attributes = value.Get("attributes");
  std::vector<glm::vec3> translations, scales;
  std::vector<glm::vec4> rotations;
  std::size_t count = 0;
  for (const std::string& name : attributes.Keys()) {
    const tinygltf::Value& index = attributes.Get(name);
    if (!index.IsInt()) return makeError(fmt::format("attribute {} is not an accessor index", name));
    const std::string where = fmt::format("attribute {}", name);
    std::size_t read = 0;
    if (name == "TRANSLATION") {
      ENGINE_TRY_ASSIGN(translations, readVec3(context, index.Get<int>()).withContext(where));
      read = translations.size();
    } else if (name == "ROTATION") {
      ENGINE_TRY_ASSIGN(rotations, readVec4(context, index.Get<int>()).withContext(where));
      read = rotations.size();
    } else if (name == "SCALE") {
      ENGINE_TRY_ASSIGN(scales, readVec3(context, index.Get<int>()).withContext(where));
      read = scales.size();
    } else {
      context.warnings.push_back(fmt::format("node '{}': {} attribute {} ignored", node.name, kInstancingExtension, name));
      continue;
    }
    if (count != 0 && read != count)
      return makeError(fmt::format("attribute {} has {} instances, the others {}", name, read, count));
    count = read;
  }
  if (count == 0) return makeError("no TRANSLATION, ROTATION or SCALE attribute");
  if (count > kMaxMeshInstances - placed)
    return makeError(fmt::format("{} instances here after {} before: more than the {} mesh instances a file may place",
                                 count, placed, kMaxMeshInstances));
  std::vector<glm::mat4> instances(count);
  for (std::size_t i = 0; i < count; ++i) {
    const glm::vec3 t = translations.empty() ? glm::vec3(0.0f) : translations[i];
    const glm::vec4 r = rotations.empty() ? glm::vec4(0.0f, 0.0f, 0.0f, 1.0f) : rotations[i];
    const glm::vec3 s = scales.empty() ? glm::vec3(1.0f) : scales[i];
    ENGINE_TRY_ASSIGN(instances[i], trsMatrix(t, r, s).withContext(fmt::format("instance {}", i)));
  }
  return instances;
}

// Parent of every node, checking that children exist, are not the node itself and have one parent.
Expected<std::vector<int>> nodeParents(const tinygltf::Model& model) {
  std::vector<int> parent(model.nodes.size(), -1);
  for (std::size_t n = 0; n < model.nodes.size(); ++n) {
    for (const int child : model.nodes[n].children) {
      if (!inRange(child, model.nodes))
        return makeError(fmt::format("node {}: child {}", n, describeIndexRange("node", child, model.nodes.size())));
      if (std::size_t(child) == n) return makeError(fmt::format("node {} lists itself as a child", n));
      if (parent[std::size_t(child)] != -1)
        return makeError(fmt::format("node {} has two parents (node {} and node {})", child, parent[std::size_t(child)], n));
      parent[std::size_t(child)] = int(n);
    }
  }
  return parent;
}

// With one parent per node, a node that is not reachable from any root lies on (or hangs off) a
// cycle. Checked iteratively: a cyclic file must not be able to exhaust the stack.
Status checkAcyclic(const tinygltf::Model& model, const std::vector<int>& parent) {
  std::vector<bool> reached(model.nodes.size(), false);
  std::vector<int> pending;
  for (std::size_t n = 0; n < parent.size(); ++n)
    if (parent[n] == -1) pending.push_back(int(n));
  while (!pending.empty()) {
    const int node = pending.back();
    pending.pop_back();
    reached[std::size_t(node)] = true;
    for (const int child : model.nodes[std::size_t(node)].children) pending.push_back(child);
  }
  for (std::size_t n = 0; n < reached.size(); ++n)
    if (!reached[n]) return makeError(fmt::format("node hierarchy has a cycle through node {}", n));
  return {};
}

// The scene to load: the one asked for, else the file's default, else scene 0. With several
// scenes, a note says which one was loaded.
Expected<int> chooseScene(const ImportContext& context) {
  const auto& model = context.model;
  if (context.scene >= 0) {
    if (!inRange(context.scene, model.scenes))
      return makeError(fmt::format("scene {} was requested but the file has {} scene(s)", context.scene, model.scenes.size()));
    return context.scene;
  }
  const int sceneIndex = model.defaultScene == -1 ? 0 : model.defaultScene;
  if (!inRange(sceneIndex, model.scenes))
    return makeError(describeIndexRange("default scene", sceneIndex, model.scenes.size()));
  return sceneIndex;
}

Expected<std::vector<int>> sceneRoots(ImportContext& context, const std::vector<int>& parent) {
  const auto& model = context.model;
  std::vector<int> roots;
  if (model.scenes.empty()) {
    if (model.defaultScene != -1) return makeError(fmt::format("default scene {} given but the file has no scenes", model.defaultScene));
    if (context.scene >= 0) return makeError(fmt::format("scene {} was requested but the file has no scenes", context.scene));
    for (std::size_t n = 0; n < parent.size(); ++n)
      if (parent[n] == -1) roots.push_back(int(n));
    return roots;
  }
  ENGINE_TRY_ASSIGN(const int sceneIndex, chooseScene(context));
  if (model.scenes.size() > 1)
    context.warnings.push_back(fmt::format("the file has {} scenes; loaded scene {} '{}' ({}), the others are ignored",
                                           model.scenes.size(), sceneIndex, model.scenes[std::size_t(sceneIndex)].name,
                                           context.scene >= 0 ? "as requested" : "the file's default"));
  std::vector<bool> listed(parent.size(), false);
  for (const int node : model.scenes[std::size_t(sceneIndex)].nodes) {
    if (!inRange(node, model.nodes))
      return makeError(fmt::format("scene {}: {}", sceneIndex, describeIndexRange("node", node, model.nodes.size())));
    if (parent[std::size_t(node)] != -1)
      return makeError(fmt::format("scene {} lists node {}, which is a child of node {}", sceneIndex, node, parent[std::size_t(node)]));
    if (listed[std::size_t(node)]) return makeError(fmt::format("scene {} lists node {} twice", sceneIndex, node));
    listed[std::size_t(node)] = true;
    roots.push_back(node);
  }
  return roots;
}

Status checkNodeReferences(const tinygltf::Model& model, std::size_t n) {
  const auto& node = model.nodes[n];
  if (node.mesh != -1 && !inRange(node.mesh, model.meshes))
    return makeError(describeIndexRange("mesh", node.mesh, model.meshes.size()));
  if (node.camera != -1 && !inRange(node.camera, model.cameras))
    return makeError(describeIndexRange("camera", node.camera, model.cameras.size()));
  return {};
}

bool isFinite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

// tinygltf's parsed `extras` back as JSON, so that scene_data.h stays free of tinygltf. Depth is
// bounded by kMaxJsonDepth, which the document passed before tinygltf parsed it.
Json toJson(const tinygltf::Value& value) {
  if (value.IsBool()) return value.Get<bool>();
  if (value.IsInt()) return value.Get<int>();
  if (value.IsNumber()) return value.GetNumberAsDouble();
  if (value.IsString()) return value.Get<std::string>();
  if (value.IsArray()) {
    Json array = Json::array();
    for (std::size_t i = 0; i < value.ArrayLen(); ++i) array.push_back(toJson(value.Get(int(i))));
    return array;
  }
  if (value.IsObject()) {
    Json object = Json::object();
    for (const std::string& key : value.Keys()) object[key] = toJson(value.Get(key));
    return object;
  }
  return nullptr;  // null, or binary (never in JSON extras)
}

// EXT_mesh_gpu_instancing's instances of node `self` as its children, one NodeData each: named
// "node[i]", the node's mesh and extras (per-node choices made in extras apply to every instance).
Status addInstanceNodes(std::vector<NodeData>& out, int self, int mesh, const std::vector<glm::mat4>& instances) {
  for (std::size_t i = 0; i < instances.size(); ++i) {
    const NodeData& node = out[std::size_t(self)];
    NodeData instance;
    instance.name = fmt::format("{}[{}]", node.name, i);
    instance.parent = self;
    instance.local = instances[i];
    instance.world = node.world * instance.local;
    if (!isFinite(instance.world))
      return makeError(fmt::format("node '{}': {} instance {}: world matrix is not finite", node.name,
                                   kInstancingExtension, i));
    instance.mesh = mesh;
    instance.extras = node.extras;
    out.push_back(std::move(instance));
  }
  return {};
}

// Scene nodes in depth-first pre-order (parents before children), with world matrices; the
// instances of EXT_mesh_gpu_instancing follow their node as its first children.
Expected<std::vector<NodeData>> convertNodes(ImportContext& context, const std::vector<int>& cameraRemap) {
  const auto& model = context.model;
  ENGINE_TRY_ASSIGN(const auto parent, nodeParents(model));
  ENGINE_TRY(checkAcyclic(model, parent));
  ENGINE_TRY_ASSIGN(const auto roots, sceneRoots(context, parent));

  std::vector<NodeData> out;
  context.nodeIndexOf.assign(model.nodes.size(), -1);
  std::size_t instanceCount = 0;
  std::vector<std::pair<int, int>> pending;  // (file node, index of its parent in `out`)
  for (auto root = roots.rbegin(); root != roots.rend(); ++root) pending.emplace_back(*root, -1);
  while (!pending.empty()) {
    const auto [fileIndex, outParent] = pending.back();
    pending.pop_back();
    const auto& node = model.nodes[std::size_t(fileIndex)];
    const std::string where = fmt::format("node {} '{}'", fileIndex, node.name);
    ENGINE_TRY(checkNodeReferences(model, std::size_t(fileIndex)).withContext(where));
    NodeData data;
    data.name = node.name;
    data.parent = outParent;
    ENGINE_TRY_ASSIGN(data.local, localMatrix(node, where, context.warnings).withContext(where));
    data.world = outParent == -1 ? data.local : out[std::size_t(outParent)].world * data.local;
    if (!isFinite(data.world)) return makeError(fmt::format("{}: world matrix is not finite", where));
    data.mesh = node.mesh;
    if (node.extras.Type() != tinygltf::NULL_TYPE) data.extras = toJson(node.extras).dump();
    data.camera = node.camera == -1 ? -1 : cameraRemap[std::size_t(node.camera)];
    if (node.mesh != -1 && !node.weights.empty() && node.weights != model.meshes[std::size_t(node.mesh)].weights)
      context.warnings.push_back(fmt::format("{}: its own morph weights are not applied (its mesh's are, to every node)", where));
    if (node.mesh != -1 && node.skin != -1)
      context.warnings.push_back(fmt::format("{}: skin {} ignored: the mesh is drawn as its vertices lie in the file (the "
                                             "bind pose), placed by this node, not by the skin's joints",
                                             where, node.skin));
    std::vector<glm::mat4> instances;
    if (node.mesh == -1 && node.extensions.count(std::string(kInstancingExtension)) != 0) {
      // Nothing to instance: the extension is not read, so its contents cannot fail the file.
      context.warnings.push_back(fmt::format("{}: {} on a node without a mesh ignored", where, kInstancingExtension));
    } else if (node.mesh != -1) {
      ENGINE_TRY_ASSIGN(instances, meshInstances(context, node, instanceCount)
                                       .withContext(fmt::format("{}: {}", where, kInstancingExtension)));
    }
    if (!instances.empty()) {
      instanceCount += instances.size();
      data.mesh = -1;  // the mesh is drawn at its instances only
    }
    out.push_back(std::move(data));
    const int self = int(out.size() - 1);
    context.nodeIndexOf[std::size_t(fileIndex)] = self;
    if (node.mesh != -1) ENGINE_TRY(addInstanceNodes(out, self, node.mesh, instances));
    for (auto child = node.children.rbegin(); child != node.children.rend(); ++child) pending.emplace_back(*child, self);
  }
  return out;
}

// Each mesh instance's world-space bounds must stay finite, so flattening never yields inf.
Status checkInstancesFinite(const SceneData& scene) {
  for (const auto& node : scene.nodes) {
    if (node.mesh < 0) continue;
    for (const auto& primitive : scene.meshes[std::size_t(node.mesh)].primitives) {
      glm::vec3 lo(std::numeric_limits<float>::max());
      glm::vec3 hi(-std::numeric_limits<float>::max());
      for (const auto& p : primitive.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
      }
      for (int corner = 0; corner < 8 && !primitive.positions.empty(); ++corner) {
        const glm::vec3 local((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y, (corner & 4) ? hi.z : lo.z);
        const glm::vec4 world = node.world * glm::vec4(local, 1.0f);
        if (!std::isfinite(world.x) || !std::isfinite(world.y) || !std::isfinite(world.z))
          return makeError(fmt::format("node '{}': mesh {} placed by its world matrix has non-finite positions", node.name, node.mesh));
      }
    }
  }
  return {};
}

// ---------------------------------------------------------------------------------------------
// Whole model

// Every EXT_meshopt_compression bufferView, decoded once (and charged to the decode budget) before
// the accessors read them. The decoded size must be the view's byteLength.
Status decodeMeshoptViews(ImportContext& context) {
  const auto& plan = context.plan;
  context.meshoptViews.resize(plan.meshopt.size());
  for (std::size_t v = 0; v < plan.meshopt.size(); ++v) {
    if (!plan.meshopt[v]) continue;
    const MeshoptExtension& meshopt = *plan.meshopt[v];
    const auto where = fmt::format("bufferView {}: EXT_meshopt_compression", v);
    if (v >= context.model.bufferViews.size()) return makeError(fmt::format("{}: internal error: view not parsed", where));
    const std::uint64_t decodedBytes = meshopt.desc.count * meshopt.desc.byteStride;  // both checked small (<= 2^64 / 256)
    if (meshopt.desc.count > (std::uint64_t(1) << 48) || decodedBytes != context.model.bufferViews[v].byteLength)
      return makeError(fmt::format("{}: count {} x byteStride {} is not the view's byteLength {}", where, meshopt.desc.count,
                                   meshopt.desc.byteStride, context.model.bufferViews[v].byteLength));
    ENGINE_TRY(chargeDecode(context, decodedBytes).withContext(where));
    ENGINE_TRY_ASSIGN(const auto compressed, bufferRange(context.model, meshopt.buffer, meshopt.byteOffset, meshopt.byteLength)
                                                 .withContext(where));
    ENGINE_TRY_ASSIGN(context.meshoptViews[v], decodeMeshoptView(compressed, meshopt.desc).withContext(where));
  }
  return {};
}

}  // namespace

// A glTF material's textureInfo of one kind: its texture, its texCoord and its extensions.
struct TextureInfoRef {
  int index;
  int texCoord;
  const tinygltf::ExtensionMap& extensions;
};

template <class Info>
TextureInfoRef infoRef(const Info& info) {
  return {info.index, info.texCoord, info.extensions};
}

// A material texture's glTF name, where the file and MaterialData keep it, and what the material
// is drawn in without it.
struct TextureKind {
  const char* name;
  const char* fallback;
  TextureInfoRef (*info)(const tinygltf::Material&);
  int MaterialData::*texture;
};
// Every kind, the one list of them.
constexpr TextureKind kTextureKinds[] = {
    {"baseColorTexture", "drawn in baseColorFactor",
     [](const tinygltf::Material& m) { return infoRef(m.pbrMetallicRoughness.baseColorTexture); },
     &MaterialData::baseColorTexture},
    {"metallicRoughnessTexture", "drawn in metallicFactor and roughnessFactor",
     [](const tinygltf::Material& m) { return infoRef(m.pbrMetallicRoughness.metallicRoughnessTexture); },
     &MaterialData::metallicRoughnessTexture},
    {"occlusionTexture", "drawn without occlusion", [](const tinygltf::Material& m) { return infoRef(m.occlusionTexture); },
     &MaterialData::occlusionTexture},
    {"emissiveTexture", "drawn in emissiveFactor", [](const tinygltf::Material& m) { return infoRef(m.emissiveTexture); },
     &MaterialData::emissiveTexture},
    {"normalTexture", "drawn with its vertex normals", [](const tinygltf::Material& m) { return infoRef(m.normalTexture); },
     &MaterialData::normalTexture},
};

// Each glTF texture a material uses, decoded once into SceneData::textures.
class TextureImport {
 public:
  explicit TextureImport(ImportContext& context) : context_(context) {}

  // `material`'s textures into `out` as SceneData::textures indices: -1 for one absent, or with a
  // warning naming the material, the texture and the problem (drawn without it).
  void materialTextures(const tinygltf::Material& material, std::size_t m, MaterialData& out,
                        std::vector<TextureData>& textures) {
    MaterialRef ref{material, m, std::nullopt};
    for (const TextureKind& kind : kTextureKinds) out.*kind.texture = texture(ref, kind, kind.info(material), textures);
    if (ref.transform && *ref.transform != glm::mat3(1.0f)) transforms_[int(m)] = *ref.transform;
  }

  // The primitive's TEXCOORD_0 turned into the coordinates its material's textures are read at
  // (KHR_texture_transform: an atlas region, a tiled or rotated texture; gltfpack writes one to
  // undo its quantization of texture coordinates).
  void transformTexcoords(MeshPrimitiveData& primitive) const {
    const auto transform = transforms_.find(primitive.material);
    if (transform == transforms_.end()) return;
    for (glm::vec2& uv : primitive.texcoords) uv = glm::vec2(transform->second * glm::vec3(uv, 1.0f));
  }

 private:
  // The material being read, and the KHR_texture_transform of its first texture read: the one
  // transform its TEXCOORD_0 goes through, for every texture of it.
  struct MaterialRef {
    const tinygltf::Material& material;
    std::size_t index;
    std::optional<glm::mat3> transform;
  };

  // The material's texture of `kind` (its glTF textureInfo `info`) as a SceneData::textures index,
  // or -1 (absent, or a warning).
  int texture(MaterialRef& ref, const TextureKind& kind, const TextureInfoRef& info, std::vector<TextureData>& textures) {
    if (info.index == -1) return -1;  // tinygltf's "absent"
    const std::string where = fmt::format("material {} '{}': {}", ref.index, ref.material.name, kind.name);
    const auto coordinates = textureCoordinates(info.texCoord, info.extensions);
    if (!coordinates.ok()) return warn(where, coordinates.error().message, kind);
    if (coordinates->set != 0)
      return warn(where, fmt::format("texCoord {} is not read (only TEXCOORD_0)", coordinates->set), kind);
    if (ref.transform && *ref.transform != coordinates->transform)
      return warn(where, "its KHR_texture_transform differs from the material's first texture's (one is applied to TEXCOORD_0)",
                  kind);
    const int slot = convertedTexture(info.index, where, kind, textures);
    if (slot >= 0 && !ref.transform) ref.transform = coordinates->transform;
    return slot;
  }

  // glTF texture `index` decoded once: its SceneData::textures index, or -1 (with a warning).
  int convertedTexture(int index, const std::string& where, const TextureKind& kind, std::vector<TextureData>& textures) {
    const auto known = converted_.find(index);
    if (known != converted_.end()) {
      if (known->second < 0) warn(where, fmt::format("texture {} cannot be read (said above)", index), kind);
      return known->second;
    }
    auto texture = convertTexture(context_, index);
    int& slot = converted_[index];
    slot = -1;
    if (!texture.ok()) return warn(where, texture.error().message, kind);
    textures.push_back(std::move(*texture));
    slot = int(textures.size() - 1);
    return slot;
  }
  int warn(const std::string& where, const std::string& problem, const TextureKind& kind) {
    context_.warnings.push_back(fmt::format("{}: {}; {}", where, problem, kind.fallback));
    return -1;
  }
  ImportContext& context_;
  std::map<int, int> converted_;  // glTF texture -> SceneData::textures index, -1: failed
  std::map<int, glm::mat3> transforms_;  // material -> its KHR_texture_transform, when not the identity
};

// The glTF names of the textures `material` has.
std::vector<std::string> textureKinds(const MaterialData& material) {
  std::vector<std::string> kinds;
  for (const TextureKind& kind : kTextureKinds)
    if (material.*kind.texture >= 0) kinds.push_back(kind.name);
  return kinds;
}

// A textured material on a primitive without TEXCOORD_0 draws in its factors: said once per primitive.
void noteUntexturedPrimitives(const SceneData& scene, std::vector<std::string>& warnings) {
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const MeshData& mesh = scene.meshes[m];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const MeshPrimitiveData& primitive = mesh.primitives[p];
      if (primitive.material < 0 || !primitive.texcoords.empty()) continue;
      const MaterialData& material = scene.materials[std::size_t(primitive.material)];
      const std::vector<std::string> kinds = textureKinds(material);
      if (kinds.empty()) continue;
      warnings.push_back(fmt::format("mesh {} '{}' primitive {}: material {} '{}' has a {} but the primitive no "
                                     "TEXCOORD_0; drawn in its factors",
                                     m, mesh.name, p, primitive.material, material.name, fmt::join(kinds, ", ")));
    }
  }
}

Expected<SceneData> convertModel(ImportContext& context) {
  const auto& model = context.model;
  ENGINE_TRY(decodeMeshoptViews(context));
  SceneData scene;
  TextureImport textures(context);
  for (std::size_t m = 0; m < model.materials.size(); ++m) {
    ENGINE_TRY_ASSIGN(auto material, convertMaterial(model.materials[m]).withContext(fmt::format("material {}", m)));
    textures.materialTextures(model.materials[m], m, material, scene.textures);
    scene.materials.push_back(std::move(material));
    if (auto note = ignoredMaterialFields(model.materials[m]))
      context.warnings.push_back(fmt::format("material {} {}", m, *note));
  }
  ENGINE_TRY_ASSIGN(const auto cameraRemap, convertCameras(context, scene));
  for (std::size_t m = 0; m < model.meshes.size(); ++m) {
    ENGINE_TRY_ASSIGN(auto mesh, convertMesh(context, int(m)));
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      textures.transformTexcoords(mesh.primitives[p]);
      addMissingTangents(scene.materials, fmt::format("mesh {} '{}' primitive {}", m, mesh.name, p), mesh.primitives[p],
                         context.warnings);
    }
    scene.meshes.push_back(std::move(mesh));
  }
  noteUntexturedPrimitives(scene, context.warnings);
  notePointAndLinePrimitives(model, context.warnings);
  ENGINE_TRY_ASSIGN(scene.nodes, convertNodes(context, cameraRemap));
  ENGINE_TRY(checkInstancesFinite(scene));
  scene.animations = convertAnimations(context);
  return scene;
}

std::uint64_t decodeBudget(std::uint64_t fileBytes, const tinygltf::Model& model) {
  std::uint64_t inputBytes = fileBytes;
  for (const auto& buffer : model.buffers) inputBytes += buffer.data.size();
  return kDecodeBudgetFloorBytes + kDecodeBudgetPerInputByte * inputBytes;
}

}  // namespace engine::scene::gltf
