// The glTF document before conversion (gltf_document.h): GLB container, JSON sanitising and the
// extension plan, tinygltf with our own file access.
#include "engine/scene/gltf/gltf_document.h"

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
#include <nlohmann/json.hpp>

#include "engine/core/files.h"
#include "engine/core/log.h"
#include "engine/scene/gltf/gltf_validate.h"

namespace engine::scene::gltf {
namespace {

constexpr std::uint32_t kGlbMagic = 0x46546C67;   // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kChunkBin = 0x004E4942;   // "BIN\0"
constexpr std::size_t kGlbHeaderBytes = 12;
constexpr std::size_t kChunkHeaderBytes = 8;

// glTF documents are shallow (the deepest standard path is about 6 levels); 64 leaves ample room
// for extras while keeping tinygltf's recursive conversion far from the stack limit.
constexpr int kMaxJsonDepth = 64;

// Extensions that change how geometry is stored, all decoded here.
constexpr std::array<std::string_view, 4> kGeometryExtensions = {
    "KHR_mesh_quantization",       // integer/normalized vertex attributes
    "KHR_draco_mesh_compression",  // Draco-compressed primitives
    "EXT_meshopt_compression",     // meshopt-compressed bufferViews
    "EXT_mesh_gpu_instancing",     // a node's mesh placed many times (gltf_convert.cpp)
};
// Material extensions the importer reads (gltf_convert.cpp): used, they need no note.
constexpr std::array<std::string_view, 2> kReadMaterialExtensions = {
    "KHR_materials_emissive_strength",  // MaterialData::emissive
    "KHR_texture_transform",            // on a material's textures: applied to MeshPrimitiveData::texcoords
};
// Extensions (by prefix) that only describe materials, textures, images, lights or metadata: the
// importer reads none of those, so a file that uses or even requires them loads the same geometry.
constexpr std::array<std::string_view, 7> kNonGeometryExtensionPrefixes = {
    "KHR_materials_", "KHR_texture_", "EXT_texture_", "KHR_lights_punctual", "EXT_lights_image_based", "KHR_xmp",
    "KHR_animation_pointer",
};

// The 4-byte stand-in for a meshopt fallback buffer (its bytes are never read).
constexpr std::string_view kFallbackBufferUri = "data:application/octet-stream;base64,AAAAAA==";

// ---------------------------------------------------------------------------------------------
// GLB container

std::uint32_t readLittleEndianU32(std::span<const std::uint8_t> bytes, std::size_t offset) {
  return std::uint32_t(bytes[offset]) | std::uint32_t(bytes[offset + 1]) << 8 |
         std::uint32_t(bytes[offset + 2]) << 16 | std::uint32_t(bytes[offset + 3]) << 24;
}

void appendLittleEndianU32(std::vector<std::uint8_t>& out, std::uint32_t value) {
  for (int shift = 0; shift < 32; shift += 8) out.push_back(std::uint8_t(value >> shift));
}

}  // namespace

bool isGlb(std::span<const std::uint8_t> bytes) {
  return bytes.size() >= 4 && readLittleEndianU32(bytes, 0) == kGlbMagic;
}

namespace {

struct GlbChunks {
  std::span<const std::uint8_t> json;
  std::span<const std::uint8_t> bin;  // empty when the file has no BIN chunk
};

Status checkGlbHeader(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kGlbHeaderBytes)
    return makeError(fmt::format("truncated GLB: {} bytes, the header alone needs {}", bytes.size(),
                                 kGlbHeaderBytes));
  const std::uint32_t version = readLittleEndianU32(bytes, 4);
  if (version != 2) return makeError(fmt::format("GLB version {} is not supported (only 2)", version));
  const std::uint32_t declaredLength = readLittleEndianU32(bytes, 8);
  if (declaredLength != bytes.size())
    return makeError(fmt::format("GLB header says the file is {} bytes but it is {} (truncated or corrupt)",
                                 declaredLength, bytes.size()));
  return {};
}

// Walks the chunk list; every chunk must lie wholly inside the file. The first chunk is the JSON,
// a BIN chunk may follow, later chunks are ignored as the specification asks.
Expected<GlbChunks> parseGlbChunks(std::span<const std::uint8_t> bytes) {
  ENGINE_TRY(checkGlbHeader(bytes));
  GlbChunks chunks;
  std::size_t offset = kGlbHeaderBytes;
  for (int index = 0; offset < bytes.size(); ++index) {
    if (bytes.size() - offset < kChunkHeaderBytes)
      return makeError(fmt::format("GLB chunk {} at byte {}: truncated chunk header", index, offset));
    const std::uint32_t length = readLittleEndianU32(bytes, offset);
    const std::uint32_t type = readLittleEndianU32(bytes, offset + 4);
    const std::size_t payloadStart = offset + kChunkHeaderBytes;
    if (length > bytes.size() - payloadStart)
      return makeError(fmt::format("GLB chunk {} at byte {}: length {} runs past the end of the file ({} bytes left)",
                                   index, offset, length, bytes.size() - payloadStart));
    if (length % 4 != 0)
      return makeError(fmt::format("GLB chunk {} at byte {}: length {} is not a multiple of 4", index, offset, length));
    if (index == 0 && type != kChunkJson)
      return makeError(fmt::format("GLB chunk 0 has type 0x{:08x}, expected JSON (0x{:08x})", type, kChunkJson));
    if (index == 0) chunks.json = bytes.subspan(payloadStart, length);
    if (index == 1 && type == kChunkBin) chunks.bin = bytes.subspan(payloadStart, length);
    offset = payloadStart + length;
  }
  if (chunks.json.empty()) return makeError("GLB has no JSON chunk (or an empty one)");
  return chunks;
}

// A GLB with exactly the validated JSON and BIN chunks, laid out as tinygltf expects.
std::vector<std::uint8_t> buildGlb(std::string_view json, std::span<const std::uint8_t> bin) {
  const std::size_t jsonPadded = (json.size() + 3) / 4 * 4;
  const std::size_t total = kGlbHeaderBytes + kChunkHeaderBytes + jsonPadded +
                            (bin.empty() ? 0 : kChunkHeaderBytes + bin.size());
  std::vector<std::uint8_t> glb;
  glb.reserve(total);
  appendLittleEndianU32(glb, kGlbMagic);
  appendLittleEndianU32(glb, 2);
  appendLittleEndianU32(glb, std::uint32_t(total));
  appendLittleEndianU32(glb, std::uint32_t(jsonPadded));
  appendLittleEndianU32(glb, kChunkJson);
  glb.insert(glb.end(), json.begin(), json.end());
  glb.resize(glb.size() + (jsonPadded - json.size()), ' ');
  if (!bin.empty()) {
    appendLittleEndianU32(glb, std::uint32_t(bin.size()));
    appendLittleEndianU32(glb, kChunkBin);
    glb.insert(glb.end(), bin.begin(), bin.end());
  }
  return glb;
}

// ---------------------------------------------------------------------------------------------
// JSON sanitising and the extension plan

using Json = nlohmann::json;

struct SanitizedJson {
  std::string text;
  ExtensionPlan plan;
};

bool isGeometryExtension(std::string_view name) {
  return std::find(kGeometryExtensions.begin(), kGeometryExtensions.end(), name) != kGeometryExtensions.end();
}

bool isNonGeometryExtension(std::string_view name) {
  return std::any_of(kNonGeometryExtensionPrefixes.begin(), kNonGeometryExtensionPrefixes.end(),
                     [&](std::string_view prefix) { return name.substr(0, prefix.size()) == prefix; });
}

// A non-negative integer member; `fallback` when absent (nullopt: required).
Expected<std::uint64_t> jsonUnsigned(const Json& object, const char* key, std::optional<std::uint64_t> fallback = {}) {
  const auto it = object.find(key);
  if (it == object.end()) {
    if (fallback) return *fallback;
    return makeError(fmt::format("{} is missing", key));
  }
  if (!it->is_number_unsigned()) return makeError(fmt::format("{} is a JSON {}, not a non-negative integer", key, it->type_name()));
  return it->get<std::uint64_t>();
}

// An index into a top-level array (int, as tinygltf stores them).
Expected<int> jsonIndex(const Json& object, const char* key) {
  ENGINE_TRY_ASSIGN(const std::uint64_t value, jsonUnsigned(object, key));
  if (value > std::uint64_t(std::numeric_limits<int>::max())) return makeError(fmt::format("{} {} is too large", key, value));
  return int(value);
}

Expected<std::string> jsonString(const Json& object, const char* key, std::optional<std::string> fallback = {}) {
  const auto it = object.find(key);
  if (it == object.end()) {
    if (fallback) return *fallback;
    return makeError(fmt::format("{} is missing", key));
  }
  if (!it->is_string()) return makeError(fmt::format("{} is a JSON {}, not a string", key, it->type_name()));
  return it->get<std::string>();
}

// object.extensions.<name> when present and an object.
const Json* findExtension(const Json& object, std::string_view name) {
  const auto extensions = object.find("extensions");
  if (extensions == object.end() || !extensions->is_object()) return nullptr;
  const auto it = extensions->find(std::string(name));
  return it != extensions->end() && it->is_object() ? &*it : nullptr;
}

Expected<DracoExtension> readDracoExtension(const Json& extension) {
  DracoExtension draco;
  ENGINE_TRY_ASSIGN(draco.bufferView, jsonIndex(extension, "bufferView"));
  const auto attributes = extension.find("attributes");
  if (attributes == extension.end() || !attributes->is_object()) return makeError("attributes is missing or not an object");
  for (const auto& [semantic, id] : attributes->items()) {
    if (!id.is_number_unsigned() || id.get<std::uint64_t>() > std::numeric_limits<std::uint32_t>::max())
      return makeError(fmt::format("attributes.{} is not a Draco attribute id (a JSON {})", semantic, id.type_name()));
    draco.attributes[semantic] = id.get<std::uint32_t>();
  }
  return draco;
}

Expected<MeshoptExtension> readMeshoptExtension(const Json& extension) {
  MeshoptExtension meshopt;
  ENGINE_TRY_ASSIGN(meshopt.buffer, jsonIndex(extension, "buffer"));
  ENGINE_TRY_ASSIGN(meshopt.byteOffset, jsonUnsigned(extension, "byteOffset", 0));
  ENGINE_TRY_ASSIGN(meshopt.byteLength, jsonUnsigned(extension, "byteLength"));
  ENGINE_TRY_ASSIGN(meshopt.desc.byteStride, jsonUnsigned(extension, "byteStride"));
  ENGINE_TRY_ASSIGN(meshopt.desc.count, jsonUnsigned(extension, "count"));
  ENGINE_TRY_ASSIGN(meshopt.desc.mode, jsonString(extension, "mode"));
  ENGINE_TRY_ASSIGN(meshopt.desc.filter, jsonString(extension, "filter", "NONE"));
  ENGINE_TRY(checkMeshoptView(meshopt.desc));
  return meshopt;
}

// The elements of document[key] when it is an array (else none: tinygltf reports the problem).
std::vector<Json*> arrayItems(Json& document, const char* key) {
  std::vector<Json*> items;
  const auto it = document.find(key);
  if (it == document.end() || !it->is_array()) return items;
  for (auto& item : *it) items.push_back(&item);
  return items;
}

// Lifts `indices` out of every primitive (tinygltf refuses index accessors without a bufferView)
// and reads the Draco extension objects.
Status planPrimitives(Json& document, ExtensionPlan& plan) {
  for (Json* mesh : arrayItems(document, "meshes")) {
    auto& indices = plan.primitiveIndices.emplace_back();
    auto& draco = plan.draco.emplace_back();
    if (!mesh->is_object()) continue;
    for (Json* primitive : arrayItems(*mesh, "primitives")) {
      const std::string where = fmt::format("mesh {} primitive {}", plan.draco.size() - 1, indices.size());
      indices.push_back(-1);
      draco.emplace_back();
      if (!primitive->is_object()) continue;
      if (primitive->contains("indices")) {
        ENGINE_TRY_ASSIGN(indices.back(), jsonIndex(*primitive, "indices").withContext(where));
        primitive->erase("indices");
      }
      if (const Json* extension = findExtension(*primitive, "KHR_draco_mesh_compression")) {
        ENGINE_TRY_ASSIGN(draco.back(), readDracoExtension(*extension).withContext(where + ": KHR_draco_mesh_compression"));
      }
    }
  }
  return {};
}

// Reads the meshopt bufferView objects and gives fallback buffers (no uri, no data) a stand-in
// tinygltf can load; their bytes are never read (a bufferView that is not compressed may not use
// them, checked in bufferViewBytes).
Status planBuffers(Json& document, ExtensionPlan& plan) {
  for (Json* view : arrayItems(document, "bufferViews")) {
    auto& meshopt = plan.meshopt.emplace_back();
    if (!view->is_object()) continue;
    if (const Json* extension = findExtension(*view, "EXT_meshopt_compression")) {
      ENGINE_TRY_ASSIGN(meshopt, readMeshoptExtension(*extension)
                                     .withContext(fmt::format("bufferView {}: EXT_meshopt_compression", plan.meshopt.size() - 1)));
    }
  }
  for (Json* buffer : arrayItems(document, "buffers")) {
    const Json* extension = buffer->is_object() ? findExtension(*buffer, "EXT_meshopt_compression") : nullptr;
    const auto flag = extension ? extension->find("fallback") : Json::const_iterator();
    const bool fallback = extension && flag != extension->end() && flag->is_boolean() && flag->get<bool>() &&
                          !buffer->contains("uri");
    plan.fallbackBuffer.push_back(fallback);
    if (fallback) *buffer = Json{{"byteLength", 4}, {"uri", kFallbackBufferUri}};
  }
  return {};
}

Expected<std::vector<std::string>> extensionNames(const Json& document, const char* key) {
  std::vector<std::string> names;
  const auto it = document.find(key);
  if (it == document.end()) return names;
  if (!it->is_array()) return makeError(fmt::format("{} is not an array", key));
  for (const auto& name : *it) {
    if (!name.is_string()) return makeError(fmt::format("{} holds a JSON {}, not an extension name", key, name.type_name()));
    names.push_back(name.get<std::string>());
  }
  return names;
}

// Checked before anything else is read: a file that needs an extension this importer lacks would
// otherwise fail later with a message about a symptom (an accessor without data, say).
Status checkExtensions(const Json& document, std::vector<std::string>& warnings) {
  ENGINE_TRY_ASSIGN(const auto required, extensionNames(document, "extensionsRequired"));
  for (const auto& name : required) {
    if (!isGeometryExtension(name) && !isNonGeometryExtension(name))
      return makeError(fmt::format("requires extension {}, which this loader does not support (it decodes "
                                   "KHR_draco_mesh_compression, EXT_meshopt_compression and KHR_mesh_quantization, places "
                                   "EXT_mesh_gpu_instancing's instances and ignores material, texture and light extensions)",
                                   name));
  }
  ENGINE_TRY_ASSIGN(const auto used, extensionNames(document, "extensionsUsed"));
  for (const auto& name : used) {
    if (isGeometryExtension(name)) continue;
    if (std::find(kReadMaterialExtensions.begin(), kReadMaterialExtensions.end(), name) != kReadMaterialExtensions.end())
      continue;
    if (isNonGeometryExtension(name))
      warnings.push_back(fmt::format("extension {} ignored: it does not affect geometry", name));
    else
      warnings.push_back(fmt::format("extension {} is not supported and was ignored (the file does not require it)", name));
  }
  return {};
}

// The images' names, URIs and bufferViews; a member of the wrong JSON type reads as absent (the
// texture that uses the image then fails to load, with a warning).
std::vector<ImageSource> imageSources(const Json& document) {
  std::vector<ImageSource> images;
  const auto it = document.find("images");
  if (it == document.end() || !it->is_array()) return images;
  for (const Json& image : *it) {
    ImageSource source;
    if (image.is_object()) {
      if (image.contains("name") && image["name"].is_string()) source.name = image["name"].get<std::string>();
      if (image.contains("uri") && image["uri"].is_string()) source.uri = image["uri"].get<std::string>();
      if (image.contains("bufferView") && image["bufferView"].is_number_integer() &&
          image["bufferView"].get<std::int64_t>() >= 0 && image["bufferView"].get<std::int64_t>() <= INT32_MAX)
        source.bufferView = int(image["bufferView"].get<std::int64_t>());
    }
    images.push_back(std::move(source));
  }
  return images;
}

// Parses the document with a nesting limit, checks its extensions, builds the extension plan and
// re-serialises it without `images`.
Expected<SanitizedJson> sanitizeJson(std::span<const std::uint8_t> text, std::vector<std::string>& warnings) {
  bool tooDeep = false;
  // Discarding every value deeper than the limit keeps the parsed document shallow; the parser
  // itself is iterative, so it walks the rest without recursing.
  auto limitDepth = [&tooDeep](int depth, nlohmann::json::parse_event_t, nlohmann::json&) {
    if (depth <= kMaxJsonDepth) return true;
    tooDeep = true;
    return false;
  };
  Json document;
  try {
    document = nlohmann::json::parse(text.begin(), text.end(), limitDepth);
  } catch (const nlohmann::json::exception& e) {
    return makeError(fmt::format("not valid JSON: {}", e.what()));
  }
  if (tooDeep) return makeError(fmt::format("JSON nested deeper than {} levels", kMaxJsonDepth));
  if (!document.is_object()) return makeError("the top-level JSON value is not an object");
  ENGINE_TRY(checkExtensions(document, warnings));
  // Before the plan and tinygltf read any number: both would take some broken values silently.
  ENGINE_TRY(checkGltfSchema(document));
  SanitizedJson out;
  ENGINE_TRY(planPrimitives(document, out.plan));
  ENGINE_TRY(planBuffers(document, out.plan));
  out.plan.images = imageSources(document);
  document.erase("images");
  try {
    out.text = document.dump();
  } catch (const nlohmann::json::exception& e) {
    return makeError(fmt::format("cannot re-serialise JSON: {}", e.what()));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// tinygltf with our own file access

// After resolving "." and "..": a URI such as "../../secret.bin" must not climb out of the folder.
// Lexically, so a symbolic link the user placed inside the folder is still followed.
bool insideDirectory(const std::filesystem::path& file, const std::filesystem::path& directory) {
  const std::filesystem::path relative = file.lexically_normal().lexically_relative(directory.lexically_normal());
  return !relative.empty() && *relative.begin() != "..";
}

bool externalFileExists(const std::string& path, void* user) {
  auto& access = *static_cast<ExternalFileAccess*>(user);
  if (access.baseDir.empty()) {
    access.problem = fmt::format("external file '{}' not allowed when loading from memory without a base directory", path);
    return false;
  }
  // tinygltf also tries the current directory as a fallback; only the base directory counts.
  if (path.rfind(access.baseDir, 0) != 0) return false;
  if (!insideDirectory(path, access.baseDir)) {
    access.problem = fmt::format("external file '{}' lies outside the folder of the glTF file ('{}')", path,
                                 access.baseDir);
    return false;
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    access.problem = fmt::format("external file '{}' not found", path);
    return false;
  }
  return true;
}

std::string expandNothing(const std::string& path, void*) { return path; }

bool readExternalFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  const auto& access = *static_cast<ExternalFileAccess*>(user);
  auto bytes = readBinaryFile(path, access.maxBytes);
  if (!bytes.ok()) {
    if (err) *err += bytes.error().message;
    return false;
  }
  *out = std::move(bytes.value());
  return true;
}

bool refuseWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "the importer never writes files";
  return false;
}

bool ignoreImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    if (end > start) lines.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return lines;
}

std::string joinLines(const std::vector<std::string>& lines) {
  std::string joined;
  for (const auto& line : lines) joined += (joined.empty() ? "" : "; ") + line;
  return joined;
}

}  // namespace

Expected<std::vector<std::uint8_t>> readFileBesideGltf(const ExternalFileAccess& access, const std::string& uri) {
  if (access.baseDir.empty())
    return makeError(fmt::format("external file '{}' not allowed when loading from memory without a base directory", uri));
  const std::filesystem::path path = std::filesystem::path(access.baseDir) / uri;
  if (!insideDirectory(path, access.baseDir))
    return makeError(fmt::format("external file '{}' lies outside the folder of the glTF file ('{}')", uri, access.baseDir));
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return makeError(fmt::format("external file '{}' not found", uri));
  return readBinaryFile(path, access.maxBytes);
}

// `document` is sanitised JSON text or a rebuilt GLB.
Expected<tinygltf::Model> parseWithTinygltf(std::span<const std::uint8_t> document, bool binary,
                                            ExternalFileAccess& access, std::vector<std::string>& warnings) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&ignoreImage, nullptr);
  loader.SetFsCallbacks({&externalFileExists, &expandNothing, &readExternalFile, &refuseWrite, &access});
  tinygltf::Model model;
  std::string err;
  std::string warn;
  const auto* data = reinterpret_cast<const unsigned char*>(document.data());
  const auto length = static_cast<unsigned int>(document.size());
  const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, data, length, access.baseDir)
                         : loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(data),
                                                      length, access.baseDir);
  for (auto& line : splitLines(warn)) warnings.push_back(std::move(line));
  if (!ok) {
    auto problems = splitLines(err);
    if (!access.problem.empty()) problems.push_back(access.problem);
    if (problems.empty()) problems.push_back("tinygltf failed without saying why");
    return makeError(joinLines(problems));
  }
  for (auto& line : splitLines(err)) warnings.push_back(std::move(line));  // non-fatal complaints
  return model;
}

// The document handed to tinygltf, and what the sanitiser read from it.
Expected<SanitizedDocument> sanitizedDocument(std::span<const std::uint8_t> bytes, std::vector<std::string>& warnings) {
  if (!isGlb(bytes)) {
    ENGINE_TRY_ASSIGN(SanitizedJson json, sanitizeJson(bytes, warnings));
    return SanitizedDocument{std::vector<std::uint8_t>(json.text.begin(), json.text.end()), std::move(json.plan)};
  }
  ENGINE_TRY_ASSIGN(const GlbChunks chunks, parseGlbChunks(bytes));
  ENGINE_TRY_ASSIGN(SanitizedJson json, sanitizeJson(chunks.json, warnings).withContext("GLB JSON chunk"));
  return SanitizedDocument{buildGlb(json.text, chunks.bin), std::move(json.plan)};
}

}  // namespace engine::scene::gltf
