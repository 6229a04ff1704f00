// glTF import: GLB container check -> JSON sanitising -> tinygltf parse -> validated conversion.
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
// Everything tinygltf leaves unchecked (accessor/bufferView/buffer ranges, node graph, counts,
// finiteness) is checked in the conversion below before any byte is read.
#include "engine/scene/gltf_loader.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
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

// Required extensions that change nothing in what this importer reads.
constexpr std::array<std::string_view, 4> kSupportedRequiredExtensions = {
    "KHR_mesh_quantization",  // integer/normalized vertex attributes: decoded below
    "KHR_texture_transform",  // textures are not imported
    "KHR_texture_basisu",     // images are not imported
    "EXT_texture_webp",       // images are not imported
};

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
// JSON sanitising

// Parses the document with a nesting limit and re-serialises it without `images`.
Expected<std::string> sanitizeJson(std::span<const std::uint8_t> text) {
  bool tooDeep = false;
  // Discarding every value deeper than the limit keeps the parsed document shallow; the parser
  // itself is iterative, so it walks the rest without recursing.
  auto limitDepth = [&tooDeep](int depth, nlohmann::json::parse_event_t, nlohmann::json&) {
    if (depth <= kMaxJsonDepth) return true;
    tooDeep = true;
    return false;
  };
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(text.begin(), text.end(), limitDepth);
  } catch (const nlohmann::json::exception& e) {
    return makeError(fmt::format("not valid JSON: {}", e.what()));
  }
  if (tooDeep) return makeError(fmt::format("JSON nested deeper than {} levels", kMaxJsonDepth));
  if (!document.is_object()) return makeError("the top-level JSON value is not an object");
  document.erase("images");
  try {
    return document.dump();
  } catch (const nlohmann::json::exception& e) {
    return makeError(fmt::format("cannot re-serialise JSON: {}", e.what()));
  }
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
  std::vector<std::string>& warnings;
  std::uint64_t decodeBudgetBytes = 0;  // what decoded geometry may still take
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

// A checked window onto an accessor's elements: element i starts at first + i * stride and its
// `components` components of `componentType` all lie inside the buffer.
struct AccessorSpan {
  const std::uint8_t* first = nullptr;
  std::uint64_t count = 0;
  std::uint64_t stride = 0;
  int componentType = 0;
  int components = 0;
  bool normalized = false;
};

Expected<std::span<const std::uint8_t>> bufferViewBytes(const tinygltf::Model& model, int viewIndex) {
  if (!inRange(viewIndex, model.bufferViews))
    return makeError(describeIndexRange("bufferView", viewIndex, model.bufferViews.size()));
  const auto& view = model.bufferViews[std::size_t(viewIndex)];
  if (!inRange(view.buffer, model.buffers))
    return makeError(fmt::format("bufferView {}: {}", viewIndex, describeIndexRange("buffer", view.buffer, model.buffers.size())));
  const auto& data = model.buffers[std::size_t(view.buffer)].data;
  if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
    return makeError(fmt::format("bufferView {}: bytes [{}, {}+{}) lie beyond buffer {} ({} bytes)", viewIndex,
                                 view.byteOffset, view.byteOffset, view.byteLength, view.buffer, data.size()));
  return std::span<const std::uint8_t>(data.data() + view.byteOffset, view.byteLength);
}

Status checkAccessorFormat(const tinygltf::Accessor& accessor, int expectedType) {
  if (accessor.sparse.isSparse) return makeError("sparse accessors are not supported");
  if (accessor.type != expectedType)
    return makeError(fmt::format("type is {}, expected {}", typeName(accessor.type), typeName(expectedType)));
  if (componentBytes(accessor.componentType) == 0)
    return makeError(fmt::format("componentType {} is not a glTF 2.0 component type", accessor.componentType));
  if (accessor.count == 0) return makeError("count is 0 (glTF requires at least 1)");
  if (accessor.bufferView < 0) return makeError("has no bufferView (all-zero accessors are not supported)");
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

Expected<AccessorSpan> accessorSpan(const tinygltf::Model& model, int accessorIndex, int expectedType) {
  if (!inRange(accessorIndex, model.accessors))
    return makeError(describeIndexRange("accessor", accessorIndex, model.accessors.size()));
  const auto& accessor = model.accessors[std::size_t(accessorIndex)];
  auto checked = [&]() -> Expected<AccessorSpan> {
    ENGINE_TRY(checkAccessorFormat(accessor, expectedType));
    ENGINE_TRY_ASSIGN(const auto viewBytes, bufferViewBytes(model, accessor.bufferView));
    const int components = tinygltf::GetNumComponentsInType(std::uint32_t(accessor.type));
    const std::uint64_t elementBytes = componentBytes(accessor.componentType) * std::uint64_t(components);
    const std::uint64_t declaredStride = model.bufferViews[std::size_t(accessor.bufferView)].byteStride;
    if (declaredStride != 0 && declaredStride < elementBytes)
      return makeError(fmt::format("bufferView {} byteStride {} is smaller than one element ({} bytes)",
                                   accessor.bufferView, declaredStride, elementBytes));
    const std::uint64_t stride = declaredStride != 0 ? declaredStride : elementBytes;
    ENGINE_TRY(checkAccessorFits(accessor, elementBytes, stride, viewBytes.size()));
    return AccessorSpan{viewBytes.data() + accessor.byteOffset, accessor.count, stride, accessor.componentType,
                        components, accessor.normalized};
  }();
  return std::move(checked).withContext(fmt::format("accessor {}", accessorIndex));
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

// VEC3 attribute (POSITION, NORMAL) as floats; every component must be finite.
Expected<std::vector<glm::vec3>> readVec3(ImportContext& context, int accessorIndex) {
  ENGINE_TRY_ASSIGN(const AccessorSpan span, accessorSpan(context.model, accessorIndex, TINYGLTF_TYPE_VEC3));
  ENGINE_TRY(chargeDecode(context, span.count * sizeof(glm::vec3)));
  const std::uint64_t componentSize = componentBytes(span.componentType);
  std::vector<glm::vec3> values(static_cast<std::size_t>(span.count));
  for (std::size_t i = 0; i < values.size(); ++i) {
    const std::uint8_t* element = span.first + i * span.stride;
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
  ENGINE_TRY_ASSIGN(const AccessorSpan span, accessorSpan(context.model, accessorIndex, TINYGLTF_TYPE_SCALAR));
  const bool indexType = span.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                         span.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
                         span.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  if (!indexType || span.normalized)
    return makeError(fmt::format("accessor {}: componentType {}{} cannot hold indices", accessorIndex,
                                 span.componentType, span.normalized ? " (normalized)" : ""));
  ENGINE_TRY(chargeDecode(context, span.count * sizeof(std::uint32_t)));
  std::vector<std::uint32_t> indices(static_cast<std::size_t>(span.count));
  for (std::size_t i = 0; i < indices.size(); ++i)
    indices[i] = static_cast<std::uint32_t>(readComponent(span.first + i * span.stride, span.componentType, false));
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

Expected<std::vector<std::uint32_t>> readPrimitiveTriangles(ImportContext& context, const tinygltf::Primitive& primitive,
                                                            std::size_t vertexCount) {
  std::vector<std::uint32_t> indices;
  if (primitive.indices >= 0) {
    ENGINE_TRY_ASSIGN(indices, readIndices(context, primitive.indices).withContext("indices"));
  } else if (primitive.indices != -1) {
    return makeError(describeIndexRange("indices accessor", primitive.indices, context.model.accessors.size()));
  } else {
    ENGINE_TRY_ASSIGN(indices, sequentialIndices(context, vertexCount));
  }
  ENGINE_TRY(checkIndicesInRange(indices, vertexCount));
  return toTriangleList(primitive.mode, std::move(indices));
}

Expected<MeshPrimitiveData> convertTrianglePrimitive(ImportContext& context, const tinygltf::Primitive& primitive) {
  MeshPrimitiveData out;
  const int positionAccessor = findAttribute(primitive, "POSITION");
  if (positionAccessor == -2) return makeError("has no POSITION attribute");
  ENGINE_TRY_ASSIGN(out.positions, readVec3(context, positionAccessor).withContext("POSITION"));
  if (out.positions.size() > std::numeric_limits<std::uint32_t>::max())
    return makeError(fmt::format("{} vertices do not fit 32-bit indices", out.positions.size()));
  ENGINE_TRY_ASSIGN(out.indices, readPrimitiveTriangles(context, primitive, out.positions.size()));

  if (const int normalAccessor = findAttribute(primitive, "NORMAL"); normalAccessor != -2) {
    ENGINE_TRY_ASSIGN(out.normals, readVec3(context, normalAccessor).withContext("NORMAL"));
    if (out.normals.size() != out.positions.size())
      return makeError(fmt::format("NORMAL has {} elements but POSITION has {}", out.normals.size(), out.positions.size()));
  } else {
    ENGINE_TRY(chargeDecode(context, out.positions.size() * sizeof(glm::vec3)));
    out.normals = smoothNormals(out.positions, out.indices);
  }

  if (primitive.material != -1 && !inRange(primitive.material, context.model.materials))
    return makeError(describeIndexRange("material", primitive.material, context.model.materials.size()));
  out.material = primitive.material;
  return out;
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
    ENGINE_TRY_ASSIGN(auto converted, convertTrianglePrimitive(context, primitive).withContext(where));
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

Expected<std::vector<int>> sceneRoots(const tinygltf::Model& model, const std::vector<int>& parent) {
  std::vector<int> roots;
  if (model.scenes.empty()) {
    if (model.defaultScene != -1) return makeError(fmt::format("default scene {} given but the file has no scenes", model.defaultScene));
    for (std::size_t n = 0; n < parent.size(); ++n)
      if (parent[n] == -1) roots.push_back(int(n));
    return roots;
  }
  const int sceneIndex = model.defaultScene == -1 ? 0 : model.defaultScene;
  if (!inRange(sceneIndex, model.scenes))
    return makeError(describeIndexRange("default scene", sceneIndex, model.scenes.size()));
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

// Scene nodes in depth-first pre-order (parents before children), with world matrices.
Expected<std::vector<NodeData>> convertNodes(const tinygltf::Model& model, const std::vector<int>& cameraRemap) {
  ENGINE_TRY_ASSIGN(const auto parent, nodeParents(model));
  ENGINE_TRY(checkAcyclic(model, parent));
  ENGINE_TRY_ASSIGN(const auto roots, sceneRoots(model, parent));

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

Status checkRequiredExtensions(const tinygltf::Model& model) {
  for (const auto& extension : model.extensionsRequired) {
    const bool supported = std::find(kSupportedRequiredExtensions.begin(), kSupportedRequiredExtensions.end(),
                                     extension) != kSupportedRequiredExtensions.end();
    if (!supported) return makeError(fmt::format("requires extension {}, which is not supported", extension));
  }
  return {};
}

Expected<SceneData> convertModel(ImportContext& context) {
  const auto& model = context.model;
  ENGINE_TRY(checkRequiredExtensions(model));
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
  ENGINE_TRY_ASSIGN(scene.nodes, convertNodes(model, cameraRemap));
  ENGINE_TRY(checkInstancesFinite(scene));
  return scene;
}

std::uint64_t decodeBudget(std::uint64_t fileBytes, const tinygltf::Model& model) {
  std::uint64_t inputBytes = fileBytes;
  for (const auto& buffer : model.buffers) inputBytes += buffer.data.size();
  return kDecodeBudgetFloorBytes + kDecodeBudgetPerInputByte * inputBytes;
}

// The document handed to tinygltf: sanitised JSON, or a GLB rebuilt around the sanitised JSON.
Expected<std::vector<std::uint8_t>> sanitizedDocument(std::span<const std::uint8_t> bytes) {
  if (!isGlb(bytes)) {
    ENGINE_TRY_ASSIGN(const std::string json, sanitizeJson(bytes));
    return std::vector<std::uint8_t>(json.begin(), json.end());
  }
  ENGINE_TRY_ASSIGN(const GlbChunks chunks, parseGlbChunks(bytes));
  ENGINE_TRY_ASSIGN(const std::string json, sanitizeJson(chunks.json).withContext("GLB JSON chunk"));
  return buildGlb(json, chunks.bin);
}

Expected<SceneData> loadChecked(std::span<const std::uint8_t> bytes, const std::filesystem::path& baseDir,
                                const GltfLoadOptions& options, std::vector<std::string>& warnings) {
  if (bytes.size() > options.maxFileBytes)
    return makeError(fmt::format("{} bytes is over the {}-byte limit for glTF files", bytes.size(), options.maxFileBytes));
  if (bytes.empty()) return makeError("file is empty");
  ENGINE_TRY_ASSIGN(const auto document, sanitizedDocument(bytes));
  ExternalFileAccess access{baseDir.empty() ? std::string() : baseDir.string(), options.maxFileBytes, {}};
  ENGINE_TRY_ASSIGN(const tinygltf::Model model, parseWithTinygltf(document, isGlb(bytes), access, warnings));
  ImportContext context{model, warnings, decodeBudget(bytes.size(), model)};
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
  for (const auto& node : scene.nodes) {
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
      }
    }
  }
  return soup;
}

}  // namespace engine::scene
