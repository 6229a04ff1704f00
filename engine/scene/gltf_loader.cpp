// glTF import: GLB container check -> JSON sanitising and extension plan -> tinygltf parse ->
// compressed bufferViews decoded -> validated conversion.
//
// tinygltf 2.7 parses the JSON and fetches buffers, but it trusts most indices and offsets, and a few
// of its own reads are unchecked, so it only ever sees input that has passed the checks below:
//  - GLB: it accepts a BIN chunk whose length runs up to 8 bytes past the end of the file (it forgets
//    the chunk header) and then copies from there. The container is validated here and rebuilt.
//  - JSON: it converts `extras`/`extensions` recursively, so a deeply nested document overflows the
//    stack; nesting is limited while parsing here.
//  - images: it indexes buffer.data[bufferView.byteOffset] unchecked for images stored in buffer
//    views, and reads external image files. Images are not needed, so they are removed from the JSON
//    before tinygltf sees it, and a no-op image loader is installed as a second line of defence.
//  - extensions: tinygltf 2.7 (Debian's build, without Draco) refuses a primitive whose index
//    accessor has no bufferView (every Draco file) and copies the GLB BIN chunk into every buffer
//    without a uri (meshopt's fallback buffers, which hold no data). So the sanitiser lifts
//    `indices` out of the primitives and reads the KHR_draco_mesh_compression and
//    EXT_meshopt_compression objects itself (an ExtensionPlan), and gives fallback buffers a
//    4-byte data: URI; the conversion decodes them (gltf_compression.h).
// The JSON is checked against the glTF 2.0 schema's ranges first (gltf_validate.h: tinygltf drops
// or wraps some out-of-range numbers silently). Everything else tinygltf leaves unchecked (ranges
// against the buffers' real bytes, node graph, finiteness) is checked in the conversion below
// before any byte is read.
#include "engine/scene/gltf_loader.h"

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
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "engine/core/files.h"
#include "engine/core/log.h"
#include "engine/scene/gltf_compression.h"
#include "engine/scene/gltf_validate.h"

namespace engine::scene {
namespace {

constexpr std::uint32_t kGlbMagic = 0x46546C67;   // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kChunkBin = 0x004E4942;   // "BIN\0"
constexpr std::size_t kGlbHeaderBytes = 12;
constexpr std::size_t kChunkHeaderBytes = 8;

// glTF documents are shallow (the deepest standard path is about 6 levels); 64 leaves ample room
// for extras while keeping tinygltf's recursive conversion far from the stack limit.
constexpr int kMaxJsonDepth = 64;

// Decoded geometry may legitimately be larger than its encoding (uint8 indices become uint32,
// quantized positions become floats, normals are generated), but a small file must not be able
// to demand gigabytes by referencing one accessor from thousands of primitives.
constexpr std::uint64_t kDecodeBudgetFloorBytes = std::uint64_t(64) << 20;
constexpr std::uint64_t kDecodeBudgetPerInputByte = 16;

// Extensions that change how geometry is stored, all decoded here.
constexpr std::array<std::string_view, 3> kGeometryExtensions = {
    "KHR_mesh_quantization",       // integer/normalized vertex attributes
    "KHR_draco_mesh_compression",  // Draco-compressed primitives
    "EXT_meshopt_compression",     // meshopt-compressed bufferViews
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

bool isGlb(std::span<const std::uint8_t> bytes) {
  return bytes.size() >= 4 && readLittleEndianU32(bytes, 0) == kGlbMagic;
}

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

// What the sanitiser read from the JSON for the conversion, indexed like tinygltf's arrays.
struct ExtensionPlan {
  std::vector<std::vector<int>> primitiveIndices;                       // [mesh][primitive]: accessor, -1 none
  std::vector<std::vector<std::optional<DracoExtension>>> draco;        // [mesh][primitive]
  std::vector<std::optional<MeshoptExtension>> meshopt;                 // [bufferView]
  std::vector<bool> fallbackBuffer;                                     // [buffer]: meshopt fallback, no data
};

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
                                   "KHR_draco_mesh_compression, EXT_meshopt_compression and KHR_mesh_quantization, "
                                   "and ignores material, texture and light extensions)",
                                   name));
  }
  ENGINE_TRY_ASSIGN(const auto used, extensionNames(document, "extensionsUsed"));
  for (const auto& name : used) {
    if (isGeometryExtension(name)) continue;
    if (isNonGeometryExtension(name))
      warnings.push_back(fmt::format("extension {} ignored: it does not affect geometry", name));
    else
      warnings.push_back(fmt::format("extension {} is not supported and was ignored (the file does not require it)", name));
  }
  return {};
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

// External files may only come from the base directory the caller named, and not be too large.
struct ExternalFileAccess {
  std::string baseDir;  // empty: no external files at all
  std::uint64_t maxBytes = 0;
  std::string problem;  // why the last lookup failed, for the error message
};

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

// ---------------------------------------------------------------------------------------------
// Conversion context, numbers

struct ImportContext {
  const tinygltf::Model& model;
  const ExtensionPlan& plan;
  std::vector<std::string>& warnings;
  std::uint64_t decodeBudgetBytes = 0;  // what decoded geometry may still take
  int scene = -1;                       // GltfLoadOptions::scene
  std::vector<std::vector<std::uint8_t>> meshoptViews;  // [bufferView]: decoded bytes (empty: not compressed)
};

Status chargeDecode(ImportContext& context, std::uint64_t bytes) {
  if (bytes > context.decodeBudgetBytes)
    return makeError(fmt::format("decoded geometry would exceed the limit for this file ({} more bytes requested, {} left)",
                                 bytes, context.decodeBudgetBytes));
  context.decodeBudgetBytes -= bytes;
  return {};
}

std::string describeIndexRange(const char* kind, int index, std::size_t available) {
  return fmt::format("{} {} out of range (file has {})", kind, index, available);
}

template <class T>
bool inRange(int index, const std::vector<T>& items) {
  return index >= 0 && std::size_t(index) < items.size();
}

Expected<float> toFiniteFloat(double value, std::string_view what) {
  if (!std::isfinite(value) || std::abs(value) > double(std::numeric_limits<float>::max()))
    return makeError(fmt::format("{} {} is not a finite 32-bit float", what, value));
  return static_cast<float>(value);
}

// ---------------------------------------------------------------------------------------------
// Accessors

std::uint64_t componentBytes(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;  // INT and DOUBLE are not glTF 2.0 component types
  }
}

const char* typeName(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    default: return "a matrix type";
  }
}

// A checked window onto an accessor's elements: element i starts at element(i) and its
// `components` components of `componentType` all lie inside the buffer, or inside `assembled`
// when the elements were put together here (sparse accessors, accessors without a bufferView).
struct AccessorSpan {
  const std::uint8_t* first = nullptr;
  std::vector<std::uint8_t> assembled;  // when not empty, the elements (tightly packed)
  std::uint64_t count = 0;
  std::uint64_t stride = 0;
  int componentType = 0;
  int components = 0;
  bool normalized = false;
  const std::uint8_t* element(std::size_t i) const { return (assembled.empty() ? first : assembled.data()) + i * stride; }
};

// A buffer range of the file, checked to lie inside the buffer.
Expected<std::span<const std::uint8_t>> bufferRange(const tinygltf::Model& model, int bufferIndex, std::uint64_t offset,
                                                    std::uint64_t length) {
  if (!inRange(bufferIndex, model.buffers)) return makeError(describeIndexRange("buffer", bufferIndex, model.buffers.size()));
  const auto& data = model.buffers[std::size_t(bufferIndex)].data;
  if (offset > data.size() || length > data.size() - offset)
    return makeError(fmt::format("bytes [{}, {}+{}) lie beyond buffer {} ({} bytes)", offset, offset, length, bufferIndex,
                                 data.size()));
  return std::span<const std::uint8_t>(data.data() + offset, length);
}

// The bytes of a bufferView: decoded ones for a meshopt-compressed view, else its buffer range.
Expected<std::span<const std::uint8_t>> bufferViewBytes(const ImportContext& context, int viewIndex) {
  const auto& model = context.model;
  if (!inRange(viewIndex, model.bufferViews))
    return makeError(describeIndexRange("bufferView", viewIndex, model.bufferViews.size()));
  if (std::size_t(viewIndex) < context.plan.meshopt.size() && context.plan.meshopt[std::size_t(viewIndex)])
    return std::span<const std::uint8_t>(context.meshoptViews[std::size_t(viewIndex)]);
  const auto& view = model.bufferViews[std::size_t(viewIndex)];
  if (!inRange(view.buffer, model.buffers))
    return makeError(fmt::format("bufferView {}: {}", viewIndex, describeIndexRange("buffer", view.buffer, model.buffers.size())));
  if (std::size_t(view.buffer) < context.plan.fallbackBuffer.size() && context.plan.fallbackBuffer[std::size_t(view.buffer)])
    return makeError(fmt::format("bufferView {} is not meshopt-compressed but lies in buffer {}, a meshopt fallback "
                                 "buffer without data",
                                 viewIndex, view.buffer));
  const auto& data = model.buffers[std::size_t(view.buffer)].data;
  if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
    return makeError(fmt::format("bufferView {}: bytes [{}, {}+{}) lie beyond buffer {} ({} bytes)", viewIndex,
                                 view.byteOffset, view.byteOffset, view.byteLength, view.buffer, data.size()));
  return std::span<const std::uint8_t>(data.data() + view.byteOffset, view.byteLength);
}

Status checkAccessorFormat(const tinygltf::Accessor& accessor, int expectedType) {
  if (accessor.type != expectedType)
    return makeError(fmt::format("type is {}, expected {}", typeName(accessor.type), typeName(expectedType)));
  if (componentBytes(accessor.componentType) == 0)
    return makeError(fmt::format("componentType {} is not a glTF 2.0 component type", accessor.componentType));
  if (accessor.count == 0) return makeError("count is 0 (glTF requires at least 1)");
  return {};
}

// Every element must fit: byteOffset + stride * (count - 1) + elementBytes <= view length, checked
// without forming a product that could overflow.
Status checkAccessorFits(const tinygltf::Accessor& accessor, std::uint64_t elementBytes, std::uint64_t stride,
                         std::uint64_t viewBytes) {
  const std::uint64_t offset = accessor.byteOffset;
  if (offset > viewBytes || elementBytes > viewBytes - offset)
    return makeError(fmt::format("byteOffset {} leaves no room for one {}-byte element in bufferView {} ({} bytes)",
                                 offset, elementBytes, accessor.bufferView, viewBytes));
  const std::uint64_t lastStartMax = viewBytes - offset - elementBytes;
  if (std::uint64_t(accessor.count) - 1 > lastStartMax / stride)
    return makeError(fmt::format("count {} with stride {} runs past the end of bufferView {} ({} bytes from offset {})",
                                 accessor.count, stride, accessor.bufferView, viewBytes, offset));
  return {};
}

template <class T>
T loadUnaligned(const std::uint8_t* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

// One component as a float, applying the glTF rules for normalized integers.
float readComponent(const std::uint8_t* bytes, int componentType, bool normalized) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const float v = float(loadUnaligned<std::int8_t>(bytes));
      return normalized ? std::max(v / 127.0f, -1.0f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      const float v = float(loadUnaligned<std::uint8_t>(bytes));
      return normalized ? v / 255.0f : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      const float v = float(loadUnaligned<std::int16_t>(bytes));
      return normalized ? std::max(v / 32767.0f, -1.0f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      const float v = float(loadUnaligned<std::uint16_t>(bytes));
      return normalized ? v / 65535.0f : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      const auto v = loadUnaligned<std::uint32_t>(bytes);
      return normalized ? float(double(v) / 4294967295.0) : float(v);
    }
    default: return loadUnaligned<float>(bytes);
  }
}

// An index (primitive indices, sparse indices) exactly: through float, 32-bit values above 2^24
// would be rounded.
std::uint32_t readIndexValue(const std::uint8_t* bytes, int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return loadUnaligned<std::uint8_t>(bytes);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return loadUnaligned<std::uint16_t>(bytes);
    default: return loadUnaligned<std::uint32_t>(bytes);
  }
}

// The elements an accessor's bufferView holds (checked to fit).
Expected<AccessorSpan> viewElements(const ImportContext& context, const tinygltf::Accessor& accessor,
                                    std::uint64_t elementBytes) {
  ENGINE_TRY_ASSIGN(const auto viewBytes, bufferViewBytes(context, accessor.bufferView));
  const std::uint64_t declaredStride = context.model.bufferViews[std::size_t(accessor.bufferView)].byteStride;
  if (declaredStride != 0 && declaredStride < elementBytes)
    return makeError(fmt::format("bufferView {} byteStride {} is smaller than one element ({} bytes)",
                                 accessor.bufferView, declaredStride, elementBytes));
  const std::uint64_t stride = declaredStride != 0 ? declaredStride : elementBytes;
  ENGINE_TRY(checkAccessorFits(accessor, elementBytes, stride, viewBytes.size()));
  AccessorSpan span;
  span.first = viewBytes.data() + accessor.byteOffset;
  span.stride = stride;
  return span;
}

// `count` tightly packed items of `itemBytes` at `offset` in a bufferView (sparse indices, values).
Expected<std::span<const std::uint8_t>> packedItems(const ImportContext& context, int viewIndex, int offset,
                                                    std::uint64_t count, std::uint64_t itemBytes, const char* what) {
  ENGINE_TRY_ASSIGN(const auto viewBytes, bufferViewBytes(context, viewIndex).withContext(what));
  if (offset < 0) return makeError(fmt::format("{}: byteOffset {} is negative", what, offset));
  const std::uint64_t start = std::uint64_t(offset);
  if (start > viewBytes.size() || count > (viewBytes.size() - start) / itemBytes)
    return makeError(fmt::format("{}: {} items of {} bytes from byteOffset {} run past the end of bufferView {} ({} bytes)",
                                 what, count, itemBytes, offset, viewIndex, viewBytes.size()));
  return viewBytes.subspan(std::size_t(start), std::size_t(count * itemBytes));
}

// Sparse substitution (glTF 2.0, 3.6.2.3): `count` strictly increasing element indices, each
// below the accessor's count, and as many tightly packed replacement elements.
Status applySparse(const ImportContext& context, const tinygltf::Accessor& accessor, std::uint64_t elementBytes,
                   std::vector<std::uint8_t>& elements) {
  const auto& sparse = accessor.sparse;
  if (sparse.count < 1 || std::uint64_t(sparse.count) > std::uint64_t(accessor.count))
    return makeError(fmt::format("sparse count {} is outside 1..{} (the accessor's count)", sparse.count, accessor.count));
  const int indexType = sparse.indices.componentType;
  if (indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    return makeError(fmt::format("sparse indices componentType {} is not an unsigned integer type", indexType));
  const std::uint64_t count = std::uint64_t(sparse.count);
  ENGINE_TRY_ASSIGN(const auto indices, packedItems(context, sparse.indices.bufferView, sparse.indices.byteOffset, count,
                                                    componentBytes(indexType), "sparse indices"));
  ENGINE_TRY_ASSIGN(const auto values, packedItems(context, sparse.values.bufferView, sparse.values.byteOffset, count,
                                                   elementBytes, "sparse values"));
  std::uint64_t previous = 0;
  for (std::uint64_t k = 0; k < count; ++k) {
    const std::uint64_t target = readIndexValue(indices.data() + k * componentBytes(indexType), indexType);
    if (target >= std::uint64_t(accessor.count))
      return makeError(fmt::format("sparse index {} (entry {}) is not below the accessor's count {}", target, k, accessor.count));
    if (k > 0 && target <= previous)
      return makeError(fmt::format("sparse indices must increase strictly, but entry {} is {} after {}", k, target, previous));
    previous = target;
    std::memcpy(elements.data() + target * elementBytes, values.data() + k * elementBytes, std::size_t(elementBytes));
  }
  return {};
}

// The accessor's elements as stored, or assembled (charged to the decode budget) when the
// accessor is sparse or has no bufferView, which glTF defines as all zeros.
Expected<AccessorSpan> accessorElements(ImportContext& context, const tinygltf::Accessor& accessor, int expectedType) {
  ENGINE_TRY(checkAccessorFormat(accessor, expectedType));
  const int components = tinygltf::GetNumComponentsInType(std::uint32_t(accessor.type));
  const std::uint64_t elementBytes = componentBytes(accessor.componentType) * std::uint64_t(components);
  AccessorSpan span;
  if (accessor.bufferView >= 0 || accessor.bufferView < -1) {
    ENGINE_TRY_ASSIGN(span, viewElements(context, accessor, elementBytes));
  }
  if (accessor.bufferView == -1 || accessor.sparse.isSparse) {
    const std::uint64_t count = std::uint64_t(accessor.count);
    ENGINE_TRY(chargeDecode(context, count * elementBytes));
    std::vector<std::uint8_t> elements(std::size_t(count * elementBytes), 0);
    if (span.first)
      for (std::uint64_t i = 0; i < count; ++i)
        std::memcpy(elements.data() + i * elementBytes, span.element(std::size_t(i)), std::size_t(elementBytes));
    if (accessor.sparse.isSparse) ENGINE_TRY(applySparse(context, accessor, elementBytes, elements));
    span.assembled = std::move(elements);
    span.stride = elementBytes;
  }
  span.count = std::uint64_t(accessor.count);
  span.componentType = accessor.componentType;
  span.components = components;
  span.normalized = accessor.normalized;
  return span;
}

Expected<AccessorSpan> accessorSpan(ImportContext& context, int accessorIndex, int expectedType) {
  if (!inRange(accessorIndex, context.model.accessors))
    return makeError(describeIndexRange("accessor", accessorIndex, context.model.accessors.size()));
  return accessorElements(context, context.model.accessors[std::size_t(accessorIndex)], expectedType)
      .withContext(fmt::format("accessor {}", accessorIndex));
}

// VEC3 attribute (POSITION, NORMAL) as floats; every component must be finite.
Expected<std::vector<glm::vec3>> readVec3(ImportContext& context, int accessorIndex) {
  ENGINE_TRY_ASSIGN(const AccessorSpan span, accessorSpan(context, accessorIndex, TINYGLTF_TYPE_VEC3));
  ENGINE_TRY(chargeDecode(context, span.count * sizeof(glm::vec3)));
  const std::uint64_t componentSize = componentBytes(span.componentType);
  std::vector<glm::vec3> values(static_cast<std::size_t>(span.count));
  for (std::size_t i = 0; i < values.size(); ++i) {
    const std::uint8_t* element = span.element(i);
    for (int c = 0; c < 3; ++c) {
      const float component = readComponent(element + std::uint64_t(c) * componentSize, span.componentType, span.normalized);
      if (!std::isfinite(component))
        return makeError(fmt::format("accessor {}: element {} component {} is {} (must be finite)", accessorIndex,
                                     i, c, component));
      values[i][c] = component;
    }
  }
  return values;
}

Expected<std::vector<std::uint32_t>> readIndices(ImportContext& context, int accessorIndex) {
  ENGINE_TRY_ASSIGN(const AccessorSpan span, accessorSpan(context, accessorIndex, TINYGLTF_TYPE_SCALAR));
  const bool indexType = span.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                         span.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
                         span.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  if (!indexType || span.normalized)
    return makeError(fmt::format("accessor {}: componentType {}{} cannot hold indices", accessorIndex,
                                 span.componentType, span.normalized ? " (normalized)" : ""));
  ENGINE_TRY(chargeDecode(context, span.count * sizeof(std::uint32_t)));
  std::vector<std::uint32_t> indices(static_cast<std::size_t>(span.count));
  for (std::size_t i = 0; i < indices.size(); ++i)
    indices[i] = readIndexValue(span.element(i), span.componentType);
  return indices;
}

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
Status checkDracoCounts(const ImportContext& context, std::span<const std::uint8_t> compressed, bool withNormals) {
  ENGINE_TRY_ASSIGN(const DracoCounts declared, readDracoCounts(compressed));
  const std::uint64_t bytes = declared.decodedBytes(withNormals);
  if (bytes > context.decodeBudgetBytes)
    return makeError(fmt::format("the Draco stream declares {} faces and {} vertices ({} bytes decoded), over the limit for "
                                 "this file ({} bytes left)",
                                 declared.faces, declared.vertices, bytes, context.decodeBudgetBytes));
  return {};
}

// Positions, indices and (when compressed too) normals from the primitive's Draco stream, checked
// against the counts its accessors declare.
Expected<MeshPrimitiveData> decodeDracoGeometry(ImportContext& context, const PrimitiveRef& ref) {
  const DracoExtension& draco = *ref.draco;
  if (ref.primitive.mode != TINYGLTF_MODE_TRIANGLES)
    return makeError(fmt::format("KHR_draco_mesh_compression on mode {} (only TRIANGLES is supported)", ref.primitive.mode));
  const auto position = draco.attributes.find("POSITION");
  if (position == draco.attributes.end()) return makeError("KHR_draco_mesh_compression has no POSITION attribute");
  const auto normal = draco.attributes.find("NORMAL");
  ENGINE_TRY_ASSIGN(const auto compressed, bufferViewBytes(context, draco.bufferView).withContext("KHR_draco_mesh_compression"));
  ENGINE_TRY(checkDracoCounts(context, compressed, normal != draco.attributes.end()).withContext("KHR_draco_mesh_compression"));
  ENGINE_TRY_ASSIGN(const DracoPrimitive decoded,
                    decodeDracoPrimitive(compressed, position->second,
                                         normal == draco.attributes.end() ? std::nullopt : std::optional(normal->second))
                        .withContext("KHR_draco_mesh_compression"));
  ENGINE_TRY(chargeDecode(context, (decoded.positions.size() + decoded.normals.size()) * sizeof(glm::vec3) +
                                       decoded.indices.size() * sizeof(std::uint32_t)));
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

Expected<MeshPrimitiveData> convertTrianglePrimitive(ImportContext& context, const PrimitiveRef& ref) {
  const auto& primitive = ref.primitive;
  if (findAttribute(primitive, "POSITION") == -2) return makeError("has no POSITION attribute");
  MeshPrimitiveData out;
  if (ref.draco) {
    ENGINE_TRY_ASSIGN(out, decodeDracoGeometry(context, ref));
  } else {
    ENGINE_TRY_ASSIGN(out, readUncompressedGeometry(context, ref));
  }

  if (out.normals.empty()) {  // not decoded from Draco with the positions
    ENGINE_TRY_ASSIGN(out.normals, readOrGenerateNormals(context, primitive, out));
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
  return PrimitiveRef{context.model.meshes[m].primitives[p], plan.primitiveIndices[m][p], draco ? &*draco : nullptr};
}

bool isTriangleMode(int mode) {
  return mode == TINYGLTF_MODE_TRIANGLES || mode == TINYGLTF_MODE_TRIANGLE_STRIP || mode == TINYGLTF_MODE_TRIANGLE_FAN;
}

bool isPointOrLineMode(int mode) { return mode >= TINYGLTF_MODE_POINTS && mode <= TINYGLTF_MODE_LINE_STRIP; }

Expected<MeshData> convertMesh(ImportContext& context, int meshIndex) {
  const auto& mesh = context.model.meshes[std::size_t(meshIndex)];
  MeshData out;
  out.name = mesh.name;
  for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
    const auto& primitive = mesh.primitives[p];
    const std::string where = fmt::format("mesh {} '{}' primitive {}", meshIndex, mesh.name, p);
    if (isPointOrLineMode(primitive.mode)) {
      context.warnings.push_back(fmt::format("{}: mode {} is points or lines, skipped", where, primitive.mode));
      continue;
    }
    if (!isTriangleMode(primitive.mode)) return makeError(fmt::format("{}: unknown mode {}", where, primitive.mode));
    ENGINE_TRY_ASSIGN(const PrimitiveRef ref, primitiveRef(context, meshIndex, p).withContext(where));
    ENGINE_TRY_ASSIGN(auto converted, convertTrianglePrimitive(context, ref).withContext(where));
    if (converted.indices.empty()) {  // a strip or fan of fewer than 3 vertices: nothing to draw
      context.warnings.push_back(fmt::format("{}: mode {} with fewer than 3 vertices has no triangles, skipped", where,
                                             primitive.mode));
      continue;
    }
    out.primitives.push_back(std::move(converted));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Materials and cameras

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

// Fills scene.cameras with the perspective cameras; returns, for each file camera, its index in
// scene.cameras or -1 when it was skipped.
Expected<std::vector<int>> convertCameras(ImportContext& context, SceneData& scene) {
  std::vector<int> remap;
  for (std::size_t i = 0; i < context.model.cameras.size(); ++i) {
    const auto& camera = context.model.cameras[i];
    if (camera.type == "perspective") {
      ENGINE_TRY_ASSIGN(auto converted, convertPerspectiveCamera(camera).withContext(fmt::format("camera {}", i)));
      remap.push_back(int(scene.cameras.size()));
      scene.cameras.push_back(std::move(converted));
    } else {
      context.warnings.push_back(fmt::format("camera {} '{}': {} cameras are not supported, skipped", i, camera.name, camera.type));
      remap.push_back(-1);
    }
  }
  return remap;
}

// ---------------------------------------------------------------------------------------------
// Nodes

Expected<glm::mat4> localMatrix(const tinygltf::Node& node) {
  if (!node.matrix.empty()) {  // glTF allows matrix or TRS; with both, tinygltf keeps only the matrix
    if (node.matrix.size() != 16) return makeError(fmt::format("matrix has {} elements, expected 16", node.matrix.size()));
    glm::mat4 m(1.0f);
    for (std::size_t i = 0; i < 16; ++i) {  // glTF and GLM are both column-major
      ENGINE_TRY_ASSIGN(glm::value_ptr(m)[i], toFiniteFloat(node.matrix[i], "matrix element"));
    }
    return m;
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
  const float rotationLength = glm::length(r);
  if (!(rotationLength > 0.0f) || !std::isfinite(rotationLength))
    return makeError("rotation quaternion has zero (or non-finite) length");
  const glm::quat q = glm::quat(r.w, r.x, r.y, r.z) / rotationLength;  // glTF stores x, y, z, w
  return glm::translate(glm::mat4(1.0f), glm::vec3(t)) * glm::mat4_cast(q) * glm::scale(glm::mat4(1.0f), glm::vec3(s));
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

// Scene nodes in depth-first pre-order (parents before children), with world matrices.
Expected<std::vector<NodeData>> convertNodes(ImportContext& context, const std::vector<int>& cameraRemap) {
  const auto& model = context.model;
  ENGINE_TRY_ASSIGN(const auto parent, nodeParents(model));
  ENGINE_TRY(checkAcyclic(model, parent));
  ENGINE_TRY_ASSIGN(const auto roots, sceneRoots(context, parent));

  std::vector<NodeData> out;
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
    ENGINE_TRY_ASSIGN(data.local, localMatrix(node).withContext(where));
    data.world = outParent == -1 ? data.local : out[std::size_t(outParent)].world * data.local;
    if (!isFinite(data.world)) return makeError(fmt::format("{}: world matrix is not finite", where));
    data.mesh = node.mesh;
    if (node.extras.Type() != tinygltf::NULL_TYPE) data.extras = toJson(node.extras).dump();
    data.camera = node.camera == -1 ? -1 : cameraRemap[std::size_t(node.camera)];
    out.push_back(std::move(data));
    const int self = int(out.size() - 1);
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

Expected<SceneData> convertModel(ImportContext& context) {
  const auto& model = context.model;
  ENGINE_TRY(decodeMeshoptViews(context));
  SceneData scene;
  for (std::size_t m = 0; m < model.materials.size(); ++m) {
    ENGINE_TRY_ASSIGN(auto material, convertMaterial(model.materials[m]).withContext(fmt::format("material {}", m)));
    scene.materials.push_back(std::move(material));
  }
  ENGINE_TRY_ASSIGN(const auto cameraRemap, convertCameras(context, scene));
  for (std::size_t m = 0; m < model.meshes.size(); ++m) {
    ENGINE_TRY_ASSIGN(auto mesh, convertMesh(context, int(m)));
    scene.meshes.push_back(std::move(mesh));
  }
  ENGINE_TRY_ASSIGN(scene.nodes, convertNodes(context, cameraRemap));
  ENGINE_TRY(checkInstancesFinite(scene));
  return scene;
}

std::uint64_t decodeBudget(std::uint64_t fileBytes, const tinygltf::Model& model) {
  std::uint64_t inputBytes = fileBytes;
  for (const auto& buffer : model.buffers) inputBytes += buffer.data.size();
  return kDecodeBudgetFloorBytes + kDecodeBudgetPerInputByte * inputBytes;
}

struct SanitizedDocument {
  std::vector<std::uint8_t> bytes;  // sanitised JSON, or a GLB rebuilt around the sanitised JSON
  ExtensionPlan plan;
};

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

Expected<SceneData> loadChecked(std::span<const std::uint8_t> bytes, const std::filesystem::path& baseDir,
                                const GltfLoadOptions& options, std::vector<std::string>& warnings) {
  if (bytes.size() > options.maxFileBytes)
    return makeError(fmt::format("{} bytes is over the {}-byte limit for glTF files", bytes.size(), options.maxFileBytes));
  if (bytes.empty()) return makeError("file is empty");
  ENGINE_TRY_ASSIGN(const SanitizedDocument document, sanitizedDocument(bytes, warnings));
  ExternalFileAccess access{baseDir.empty() ? std::string() : baseDir.string(), options.maxFileBytes, {}};
  ENGINE_TRY_ASSIGN(const tinygltf::Model model, parseWithTinygltf(document.bytes, isGlb(bytes), access, warnings));
  ImportContext context{model, document.plan, warnings, decodeBudget(bytes.size(), model), options.scene, {}};
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

TriangleSoup flattenTriangles(const SceneData& scene) {
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
      for (const auto& p : primitive.positions) soup.positions.push_back(glm::vec3(node.world * glm::vec4(p, 1.0f)));
      for (std::size_t t = 0; t + 2 < primitive.indices.size(); t += 3) {
        const std::uint32_t a = primitive.indices[t], b = primitive.indices[t + 1], c = primitive.indices[t + 2];
        const auto offset = static_cast<std::uint32_t>(base);
        soup.indices.insert(soup.indices.end(), {offset + a, offset + (mirrored ? c : b), offset + (mirrored ? b : c)});
        soup.triangleNodes.push_back(std::uint32_t(n));
      }
    }
  }
  return soup;
}

}  // namespace engine::scene
