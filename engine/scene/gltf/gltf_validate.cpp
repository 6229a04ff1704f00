// glTF 2.0 schema ranges on the raw JSON (see gltf_validate.h for why not on tinygltf's Model).
// Field paths in messages are JSON paths as the file spells them: accessors[3].sparse.count.
#include "engine/scene/gltf/gltf_validate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace engine::scene {
namespace {

using Json = nlohmann::json;

struct ComponentType {
  std::int64_t code;
  std::int64_t bytes;
  std::string_view name;
};
// accessor.componentType (schema enum); 5124 (INT) and 5130 (DOUBLE) are OpenGL codes glTF 2.0
// does not allow, though tinygltf accepts them.
constexpr std::array<ComponentType, 6> kComponentTypes = {{{5120, 1, "BYTE"},
                                                           {5121, 1, "UNSIGNED_BYTE"},
                                                           {5122, 2, "SHORT"},
                                                           {5123, 2, "UNSIGNED_SHORT"},
                                                           {5125, 4, "UNSIGNED_INT"},
                                                           {5126, 4, "FLOAT"}}};
constexpr std::int64_t kUnsignedByte = 5121;
constexpr std::int64_t kUnsignedShort = 5123;
constexpr std::int64_t kUnsignedInt = 5125;
constexpr std::int64_t kFloat = 5126;

struct AccessorType {
  std::string_view name;
  std::size_t components;
};
constexpr std::array<AccessorType, 7> kAccessorTypes = {
    {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4}, {"MAT2", 4}, {"MAT3", 9}, {"MAT4", 16}}};

constexpr std::int64_t kTargetArrayBuffer = 34962;
constexpr std::int64_t kTargetElementArrayBuffer = 34963;
constexpr std::int64_t kMaxMode = 6;  // POINTS 0 ... TRIANGLE_FAN 6
constexpr std::int64_t kMinStride = 4;
constexpr std::int64_t kMaxStride = 252;

// tinygltf stores sparse counts and offsets in an int (cast from 64 bits): a larger value would
// wrap to a small, plausible one after this check passed it.
constexpr std::int64_t kMaxTinygltfInt = std::numeric_limits<int>::max();

std::string member(std::string_view path, std::string_view key) {
  return path.empty() ? std::string(key) : fmt::format("{}.{}", path, key);
}
std::string element(std::string_view path, std::size_t index) { return fmt::format("{}[{}]", path, index); }

// ---------------------------------------------------------------------------------------------
// Values

// A JSON integer (schema "integer"). A float such as 4.0 is refused too: tinygltf reads unsigned
// fields only from JSON integers, so it would take 4.0 as absent (0) after this check passed 4.
Expected<std::int64_t> integerValue(const Json& value, const std::string& path) {
  if (value.is_number_unsigned()) {
    const auto v = value.get<std::uint64_t>();
    if (v > std::uint64_t(std::numeric_limits<std::int64_t>::max()))
      return makeError(fmt::format("{}: {} is too large (no glTF file holds 2^63 of anything)", path, v));
    return std::int64_t(v);
  }
  if (value.is_number_integer()) return value.get<std::int64_t>();
  if (value.is_number_float())
    return makeError(fmt::format("{}: {} is not an integer (schema: integer)", path, value.dump()));
  return makeError(fmt::format("{}: is a JSON {}, not an integer (schema: integer)", path, value.type_name()));
}

Expected<double> numberValue(const Json& value, const std::string& path) {
  if (!value.is_number())
    return makeError(fmt::format("{}: is a JSON {}, not a number (schema: number)", path, value.type_name()));
  const double v = value.get<double>();
  if (!std::isfinite(v)) return makeError(fmt::format("{}: {} is not a finite number", path, value.dump()));
  return v;
}

const Json* find(const Json& object, const char* key) {
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

Expected<std::optional<std::int64_t>> optionalInteger(const Json& object, const char* key, const std::string& path) {
  const Json* value = find(object, key);
  if (!value) return std::optional<std::int64_t>();
  ENGINE_TRY_ASSIGN(const std::int64_t v, integerValue(*value, member(path, key)));
  return std::optional<std::int64_t>(v);
}

Expected<std::int64_t> requiredInteger(const Json& object, const char* key, const std::string& path) {
  const Json* value = find(object, key);
  if (!value) return makeError(fmt::format("{}: is missing (schema: required)", member(path, key)));
  return integerValue(*value, member(path, key));
}

Status checkMinimum(std::int64_t value, std::int64_t minimum, const std::string& path) {
  if (value >= minimum) return {};
  if (minimum == 0) return makeError(fmt::format("{}: {} is negative (schema: minimum 0)", path, value));
  return makeError(fmt::format("{}: {} is below the minimum (schema: minimum {})", path, value, minimum));
}

// "meshes" -> "mesh", "nodes" -> "node": for "the file has 1 node".
std::string_view singular(std::string_view arrayName) {
  if (arrayName == "meshes") return "mesh";
  return arrayName.substr(0, arrayName.size() - 1);
}

// A glTF id (schema: integer, minimum 0) that must also name an element of the array it points
// into; `arrayName` is that array's key.
Status checkIndex(std::int64_t value, std::size_t available, std::string_view arrayName, const std::string& path) {
  ENGINE_TRY(checkMinimum(value, 0, path));
  if (std::uint64_t(value) >= available)
    return makeError(fmt::format("{}: {} is out of range (the file has {} {})", path, value, available,
                                 available == 1 ? singular(arrayName) : arrayName));
  return {};
}

Status optionalIndex(const Json& object, const char* key, const std::string& path, std::size_t available,
                     std::string_view arrayName) {
  ENGINE_TRY_ASSIGN(const auto value, optionalInteger(object, key, path));
  if (!value) return {};
  return checkIndex(*value, available, arrayName, member(path, key));
}

Status requiredIndex(const Json& object, const char* key, const std::string& path, std::size_t available,
                     std::string_view arrayName) {
  ENGINE_TRY_ASSIGN(const std::int64_t value, requiredInteger(object, key, path));
  return checkIndex(value, available, arrayName, member(path, key));
}

Expected<const Json*> optionalObject(const Json& object, const char* key, const std::string& path) {
  const Json* value = find(object, key);
  if (value && !value->is_object())
    return makeError(fmt::format("{}: is a JSON {}, not an object (schema: object)", member(path, key), value->type_name()));
  return value;
}

Expected<const Json*> optionalArray(const Json& object, const char* key, const std::string& path,
                                    std::size_t minItems = 0) {
  const Json* value = find(object, key);
  if (!value) return value;
  if (!value->is_array())
    return makeError(fmt::format("{}: is a JSON {}, not an array (schema: array)", member(path, key), value->type_name()));
  if (value->size() < minItems)
    return makeError(fmt::format("{}: has {} elements (schema: minItems {})", member(path, key), value->size(), minItems));
  return value;
}

// An array of numbers of exactly `length` elements (0: any length of at least 1), each within
// [lo, hi] when given.
Status optionalNumberArray(const Json& object, const char* key, const std::string& path, std::size_t length,
                           std::optional<double> lo = {}, std::optional<double> hi = {}) {
  ENGINE_TRY_ASSIGN(const Json* array, optionalArray(object, key, path, 1));
  if (!array) return {};
  const std::string arrayPath = member(path, key);
  if (length != 0 && array->size() != length)
    return makeError(fmt::format("{}: has {} elements, expected {}", arrayPath, array->size(), length));
  for (std::size_t i = 0; i < array->size(); ++i) {
    const std::string itemPath = element(arrayPath, i);
    ENGINE_TRY_ASSIGN(const double v, numberValue((*array)[i], itemPath));
    if (lo && v < *lo) return makeError(fmt::format("{}: {} is below the minimum (schema: minimum {})", itemPath, v, *lo));
    if (hi && v > *hi) return makeError(fmt::format("{}: {} is above the maximum (schema: maximum {})", itemPath, v, *hi));
  }
  return {};
}

Status optionalNumberInRange(const Json& object, const char* key, const std::string& path, double lo, double hi) {
  const Json* value = find(object, key);
  if (!value) return {};
  const std::string itemPath = member(path, key);
  ENGINE_TRY_ASSIGN(const double v, numberValue(*value, itemPath));
  if (v < lo || v > hi)
    return makeError(fmt::format("{}: {} is outside [{}, {}] (schema: minimum {}, maximum {})", itemPath, v, lo, hi, lo, hi));
  return {};
}

// A number of at least `lo` when present (a schema with a minimum and no maximum).
Status optionalNumberAtLeast(const Json& object, const char* key, const std::string& path, double lo) {
  const Json* value = find(object, key);
  if (!value) return {};
  const std::string itemPath = member(path, key);
  ENGINE_TRY_ASSIGN(const double v, numberValue(*value, itemPath));
  if (v < lo) return makeError(fmt::format("{}: {} is below the minimum (schema: minimum {})", itemPath, v, lo));
  return {};
}

// A boolean when present (tinygltf reads a value of another type as absent: the default).
Status optionalBoolean(const Json& object, const char* key, const std::string& path) {
  const Json* value = find(object, key);
  if (value && !value->is_boolean())
    return makeError(fmt::format("{}: is a JSON {}, not a boolean (schema: boolean)", member(path, key), value->type_name()));
  return {};
}

// A list of ids (node.children, scene.nodes): at least one, unique, each in range. Duplicates are
// found by sorting the list, not with a table as long as the array it points into: a file of many
// nodes with a child each would otherwise cost nodes^2.
Status optionalIndexList(const Json& object, const char* key, const std::string& path, std::size_t available,
                         std::string_view arrayName) {
  ENGINE_TRY_ASSIGN(const Json* array, optionalArray(object, key, path, 1));
  if (!array) return {};
  const std::string arrayPath = member(path, key);
  std::vector<std::pair<std::int64_t, std::size_t>> sorted;  // (id, position in the list)
  sorted.reserve(array->size());
  for (std::size_t i = 0; i < array->size(); ++i) {
    const std::string itemPath = element(arrayPath, i);
    ENGINE_TRY_ASSIGN(const std::int64_t value, integerValue((*array)[i], itemPath));
    ENGINE_TRY(checkIndex(value, available, arrayName, itemPath));
    sorted.emplace_back(value, i);
  }
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t k = 1; k < sorted.size(); ++k)
    if (sorted[k].first == sorted[k - 1].first)
      return makeError(fmt::format("{}: {} is listed twice (schema: uniqueItems)", element(arrayPath, sorted[k].second),
                                   sorted[k].first));
  return {};
}

// ---------------------------------------------------------------------------------------------
// The document

// The top-level arrays the loader reads or points into, each checked to be an array of objects.
struct Arrays {
  const Json* accessors = nullptr;
  const Json* bufferViews = nullptr;
  const Json* buffers = nullptr;
  const Json* meshes = nullptr;
  const Json* nodes = nullptr;
  const Json* scenes = nullptr;
  const Json* materials = nullptr;
  const Json* cameras = nullptr;
  const Json* skins = nullptr;
};

std::size_t sizeOf(const Json* array) { return array ? array->size() : 0; }

Expected<const Json*> topLevelArray(const Json& document, const char* key) {
  ENGINE_TRY_ASSIGN(const Json* array, optionalArray(document, key, ""));
  if (!array) return array;
  for (std::size_t i = 0; i < array->size(); ++i)
    if (!(*array)[i].is_object())
      return makeError(fmt::format("{}: is a JSON {}, not an object (schema: object)", element(key, i),
                                   (*array)[i].type_name()));
  return array;
}

class SchemaCheck {
 public:
  explicit SchemaCheck(const Json& document) : document_(document) {}

  Status run() {
    ENGINE_TRY(readArrays());
    ENGINE_TRY(optionalIndex(document_, "scene", "", sizeOf(a_.scenes), "scenes"));
    // Buffers, then bufferViews, then accessors: each one's checks read the fields of the one
    // before, which have been checked by then.
    for (std::size_t i = 0; i < sizeOf(a_.buffers); ++i) ENGINE_TRY(checkBuffer(i));
    for (std::size_t i = 0; i < sizeOf(a_.bufferViews); ++i) ENGINE_TRY(checkBufferView(i));
    for (std::size_t i = 0; i < sizeOf(a_.accessors); ++i) ENGINE_TRY(checkAccessor(i));
    for (std::size_t i = 0; i < sizeOf(a_.meshes); ++i) ENGINE_TRY(checkMesh(i));
    for (std::size_t i = 0; i < sizeOf(a_.nodes); ++i) ENGINE_TRY(checkNode(i));
    for (std::size_t i = 0; i < sizeOf(a_.scenes); ++i)
      ENGINE_TRY(optionalIndexList((*a_.scenes)[i], "nodes", element("scenes", i), sizeOf(a_.nodes), "nodes"));
    for (std::size_t i = 0; i < sizeOf(a_.materials); ++i) ENGINE_TRY(checkMaterial(i));
    return {};
  }

 private:
  Status readArrays() {
    ENGINE_TRY_ASSIGN(a_.accessors, topLevelArray(document_, "accessors"));
    ENGINE_TRY_ASSIGN(a_.bufferViews, topLevelArray(document_, "bufferViews"));
    ENGINE_TRY_ASSIGN(a_.buffers, topLevelArray(document_, "buffers"));
    ENGINE_TRY_ASSIGN(a_.meshes, topLevelArray(document_, "meshes"));
    ENGINE_TRY_ASSIGN(a_.nodes, topLevelArray(document_, "nodes"));
    ENGINE_TRY_ASSIGN(a_.scenes, topLevelArray(document_, "scenes"));
    ENGINE_TRY_ASSIGN(a_.materials, topLevelArray(document_, "materials"));
    ENGINE_TRY_ASSIGN(a_.cameras, topLevelArray(document_, "cameras"));
    ENGINE_TRY_ASSIGN(a_.skins, topLevelArray(document_, "skins"));
    return {};
  }

  Status checkBuffer(std::size_t b) {
    const std::string path = element("buffers", b);
    ENGINE_TRY_ASSIGN(const std::int64_t byteLength, requiredInteger((*a_.buffers)[b], "byteLength", path));
    return checkMinimum(byteLength, 1, member(path, "byteLength"));
  }

  Status checkBufferView(std::size_t v) {
    const Json& view = (*a_.bufferViews)[v];
    const std::string path = element("bufferViews", v);
    ENGINE_TRY(requiredIndex(view, "buffer", path, sizeOf(a_.buffers), "buffers"));
    ENGINE_TRY_ASSIGN(const auto byteOffset, optionalInteger(view, "byteOffset", path));
    if (byteOffset) ENGINE_TRY(checkMinimum(*byteOffset, 0, member(path, "byteOffset")));
    ENGINE_TRY_ASSIGN(const std::int64_t byteLength, requiredInteger(view, "byteLength", path));
    ENGINE_TRY(checkMinimum(byteLength, 1, member(path, "byteLength")));
    // Whether the view lies inside its buffer is checked where it is read, against the bytes the
    // buffer really has (bufferViewBytes in gltf_accessors.cpp); an unread one (say, an image's) may
    // be broken without harm.
    ENGINE_TRY_ASSIGN(const auto byteStride, optionalInteger(view, "byteStride", path));
    if (byteStride && (*byteStride < kMinStride || *byteStride > kMaxStride || *byteStride % 4 != 0))
      return makeError(fmt::format("{}: {} is not a multiple of 4 from 4 to 252 (schema: minimum 4, maximum 252, "
                                   "multipleOf 4)",
                                   member(path, "byteStride"), *byteStride));
    ENGINE_TRY_ASSIGN(const auto target, optionalInteger(view, "target", path));
    if (target && *target != kTargetArrayBuffer && *target != kTargetElementArrayBuffer)
      return makeError(fmt::format("{}: {} is not ARRAY_BUFFER or ELEMENT_ARRAY_BUFFER (schema: one of 34962, 34963)",
                                   member(path, "target"), *target));
    return {};
  }

  // The view's byteOffset, already checked (0 when absent).
  std::int64_t viewOffset(std::int64_t view) const {
    const Json& object = (*a_.bufferViews)[std::size_t(view)];
    return object.contains("byteOffset") ? object.at("byteOffset").get<std::int64_t>() : 0;
  }

  Expected<const ComponentType*> componentType(const Json& object, const std::string& path) {
    ENGINE_TRY_ASSIGN(const std::int64_t code, requiredInteger(object, "componentType", path));
    const auto it = std::find_if(kComponentTypes.begin(), kComponentTypes.end(),
                                 [code](const ComponentType& type) { return type.code == code; });
    if (it == kComponentTypes.end())
      return makeError(fmt::format("{}: {} is not a glTF 2.0 component type (schema: one of 5120, 5121, 5122, 5123, "
                                   "5125, 5126)",
                                   member(path, "componentType"), code));
    return &*it;
  }

  Expected<const AccessorType*> accessorType(const Json& accessor, const std::string& path) {
    const Json* value = find(accessor, "type");
    const std::string typePath = member(path, "type");
    if (!value) return makeError(fmt::format("{}: is missing (schema: required)", typePath));
    if (!value->is_string())
      return makeError(fmt::format("{}: is a JSON {}, not a string (schema: string)", typePath, value->type_name()));
    const auto name = value->get<std::string>();
    const auto it = std::find_if(kAccessorTypes.begin(), kAccessorTypes.end(),
                                 [&name](const AccessorType& type) { return type.name == name; });
    if (it == kAccessorTypes.end())
      return makeError(fmt::format("{}: \"{}\" is not an accessor type (schema: one of SCALAR, VEC2, VEC3, VEC4, MAT2, "
                                   "MAT3, MAT4)",
                                   typePath, name.substr(0, 32)));
    return &*it;
  }

  // Accessor offsets (3.6.2.4): accessor.byteOffset, and its sum with the view's byteOffset, are
  // multiples of the component size, so that every component is aligned in the buffer. The sum is
  // checked with or without an accessor byteOffset: a misaligned view misaligns its accessors too.
  Status checkAccessorOffset(const Json& accessor, const std::string& path, const ComponentType& type,
                             std::optional<std::int64_t> view) {
    ENGINE_TRY_ASSIGN(const auto byteOffset, optionalInteger(accessor, "byteOffset", path));
    const std::string offsetPath = member(path, "byteOffset");
    if (byteOffset) {
      ENGINE_TRY(checkMinimum(*byteOffset, 0, offsetPath));
      if (!view)
        return makeError(fmt::format("{}: given without a bufferView (schema: byteOffset requires bufferView)", offsetPath));
      if (*byteOffset % type.bytes != 0)
        return makeError(fmt::format("{}: {} is not a multiple of the component size {} ({})", offsetPath, *byteOffset,
                                     type.bytes, type.name));
    }
    if (!view) return {};
    // Both offsets are below 2^63 and non-negative; their sum fits an unsigned 64-bit integer.
    const std::uint64_t inBuffer = std::uint64_t(viewOffset(*view)) + std::uint64_t(byteOffset.value_or(0));
    if (inBuffer % std::uint64_t(type.bytes) != 0)
      return makeError(fmt::format("{}: bufferViews[{}].byteOffset {} + byteOffset {} = {} is not a multiple of the "
                                   "component size {} ({})",
                                   path, *view, viewOffset(*view), byteOffset.value_or(0), inBuffer, type.bytes,
                                   type.name));
    return {};
  }

  // Sparse storage (3.6.2.3): at least one and at most `count` substituted elements, unsigned
  // integer indices, both parts in existing bufferViews.
  Status checkSparse(const Json& sparse, const std::string& path, std::int64_t accessorCount) {
    ENGINE_TRY_ASSIGN(const std::int64_t count, requiredInteger(sparse, "count", path));
    ENGINE_TRY(checkMinimum(count, 1, member(path, "count")));
    if (count > accessorCount)
      return makeError(fmt::format("{}: {} is more than the accessor's count {}", member(path, "count"), count, accessorCount));
    if (count > kMaxTinygltfInt)
      return makeError(fmt::format("{}: {} is too large for this loader (at most {})", member(path, "count"), count,
                                   kMaxTinygltfInt));
    for (const char* part : {"indices", "values"}) {
      ENGINE_TRY_ASSIGN(const Json* object, optionalObject(sparse, part, path));
      const std::string partPath = member(path, part);
      if (!object) return makeError(fmt::format("{}: is missing (schema: required)", partPath));
      ENGINE_TRY(requiredIndex(*object, "bufferView", partPath, sizeOf(a_.bufferViews), "bufferViews"));
      ENGINE_TRY_ASSIGN(const auto byteOffset, optionalInteger(*object, "byteOffset", partPath));
      if (byteOffset) {
        ENGINE_TRY(checkMinimum(*byteOffset, 0, member(partPath, "byteOffset")));
        if (*byteOffset > kMaxTinygltfInt)
          return makeError(fmt::format("{}: {} is too large for this loader (at most {})", member(partPath, "byteOffset"),
                                       *byteOffset, kMaxTinygltfInt));
      }
      if (std::string_view(part) == "indices") {
        ENGINE_TRY_ASSIGN(const std::int64_t type, requiredInteger(*object, "componentType", partPath));
        if (type != kUnsignedByte && type != kUnsignedShort && type != kUnsignedInt)
          return makeError(fmt::format("{}: {} is not an unsigned integer type (schema: one of 5121, 5123, 5125)",
                                       member(partPath, "componentType"), type));
      }
    }
    return {};
  }

  Status checkAccessor(std::size_t a) {
    const Json& accessor = (*a_.accessors)[a];
    const std::string path = element("accessors", a);
    ENGINE_TRY_ASSIGN(const auto view, optionalInteger(accessor, "bufferView", path));
    if (view) ENGINE_TRY(checkIndex(*view, sizeOf(a_.bufferViews), "bufferViews", member(path, "bufferView")));
    ENGINE_TRY_ASSIGN(const ComponentType* component, componentType(accessor, path));
    ENGINE_TRY(checkAccessorOffset(accessor, path, *component, view));
    ENGINE_TRY(optionalBoolean(accessor, "normalized", path));
    if (const Json* normalized = find(accessor, "normalized")) {
      // 3.6.2.1: normalized MUST NOT be true for FLOAT or UNSIGNED_INT.
      if (normalized->get<bool>() && (component->code == kFloat || component->code == kUnsignedInt))
        return makeError(fmt::format("{}: true with componentType {} ({}); only 8- and 16-bit integers are normalized",
                                     member(path, "normalized"), component->code, component->name));
    }
    ENGINE_TRY_ASSIGN(const std::int64_t count, requiredInteger(accessor, "count", path));
    ENGINE_TRY(checkMinimum(count, 1, member(path, "count")));
    ENGINE_TRY_ASSIGN(const AccessorType* type, accessorType(accessor, path));
    // min and max (schema: 1 to 16 numbers) hold one value per component of the type (3.6.2.5).
    for (const char* bound : {"min", "max"})
      ENGINE_TRY(optionalNumberArray(accessor, bound, path, type->components));
    ENGINE_TRY_ASSIGN(const Json* sparse, optionalObject(accessor, "sparse", path));
    if (sparse) ENGINE_TRY(checkSparse(*sparse, member(path, "sparse"), count));
    return {};
  }

  // Every value of an attributes (or morph target) object is an accessor id.
  Status checkAttributeMap(const Json& attributes, const std::string& path) {
    for (const auto& [semantic, value] : attributes.items()) {
      const std::string itemPath = member(path, semantic);
      ENGINE_TRY_ASSIGN(const std::int64_t index, integerValue(value, itemPath));
      ENGINE_TRY(checkIndex(index, sizeOf(a_.accessors), "accessors", itemPath));
    }
    return {};
  }

  Status checkPrimitive(const Json& primitive, const std::string& path) {
    if (!primitive.is_object())
      return makeError(fmt::format("{}: is a JSON {}, not an object (schema: object)", path, primitive.type_name()));
    ENGINE_TRY_ASSIGN(const Json* attributes, optionalObject(primitive, "attributes", path));
    if (!attributes) return makeError(fmt::format("{}: is missing (schema: required)", member(path, "attributes")));
    ENGINE_TRY(checkAttributeMap(*attributes, member(path, "attributes")));
    ENGINE_TRY(optionalIndex(primitive, "indices", path, sizeOf(a_.accessors), "accessors"));
    ENGINE_TRY(optionalIndex(primitive, "material", path, sizeOf(a_.materials), "materials"));
    ENGINE_TRY_ASSIGN(const auto mode, optionalInteger(primitive, "mode", path));
    if (mode && (*mode < 0 || *mode > kMaxMode))
      return makeError(fmt::format("{}: {} is not a primitive mode (schema: 0 POINTS to 6 TRIANGLE_FAN)",
                                   member(path, "mode"), *mode));
    ENGINE_TRY_ASSIGN(const Json* targets, optionalArray(primitive, "targets", path, 1));
    for (std::size_t t = 0; targets && t < targets->size(); ++t) {
      const std::string targetPath = element(member(path, "targets"), t);
      if (!(*targets)[t].is_object())
        return makeError(fmt::format("{}: is a JSON {}, not an object (schema: object)", targetPath, (*targets)[t].type_name()));
      ENGINE_TRY(checkAttributeMap((*targets)[t], targetPath));
    }
    return {};
  }

  Status checkMesh(std::size_t m) {
    const Json& mesh = (*a_.meshes)[m];
    const std::string path = element("meshes", m);
    ENGINE_TRY_ASSIGN(const Json* primitives, optionalArray(mesh, "primitives", path, 1));
    if (!primitives) return makeError(fmt::format("{}: is missing (schema: required)", member(path, "primitives")));
    for (std::size_t p = 0; p < primitives->size(); ++p)
      ENGINE_TRY(checkPrimitive((*primitives)[p], element(member(path, "primitives"), p)));
    return optionalNumberArray(mesh, "weights", path, 0);
  }

  Status checkNode(std::size_t n) {
    const Json& node = (*a_.nodes)[n];
    const std::string path = element("nodes", n);
    ENGINE_TRY(optionalIndex(node, "camera", path, sizeOf(a_.cameras), "cameras"));
    ENGINE_TRY(optionalIndex(node, "skin", path, sizeOf(a_.skins), "skins"));
    ENGINE_TRY(optionalIndex(node, "mesh", path, sizeOf(a_.meshes), "meshes"));
    ENGINE_TRY(optionalIndexList(node, "children", path, sizeOf(a_.nodes), "nodes"));
    ENGINE_TRY(optionalNumberArray(node, "matrix", path, 16));
    // A unit quaternion's components lie in [-1, 1]; the loader normalises the rest of the way.
    ENGINE_TRY(optionalNumberArray(node, "rotation", path, 4, -1.0, 1.0));
    ENGINE_TRY(optionalNumberArray(node, "scale", path, 3));
    ENGINE_TRY(optionalNumberArray(node, "translation", path, 3));
    return optionalNumberArray(node, "weights", path, 0);
  }

  // The fields the loader reads: doubleSided (tinygltf took a string or a number for false, and the
  // surface lost its back faces unsaid), alphaCutoff (>= 0, as glTF says: a negative one cuts
  // nothing, a string read as 0 neither), emission and the three factors (it clamps them into
  // [0, 1], which would hide the error).
  Status checkMaterial(std::size_t m) {
    const std::string path = element("materials", m);
    const Json& material = (*a_.materials)[m];
    ENGINE_TRY(optionalBoolean(material, "doubleSided", path));
    ENGINE_TRY(optionalNumberAtLeast(material, "alphaCutoff", path, 0.0));
    ENGINE_TRY(checkEmission(material, path));
    ENGINE_TRY_ASSIGN(const Json* pbr, optionalObject(material, "pbrMetallicRoughness", path));
    if (!pbr) return {};
    const std::string pbrPath = member(path, "pbrMetallicRoughness");
    ENGINE_TRY(optionalNumberArray(*pbr, "baseColorFactor", pbrPath, 4, 0.0, 1.0));
    ENGINE_TRY(optionalNumberInRange(*pbr, "metallicFactor", pbrPath, 0.0, 1.0));
    return optionalNumberInRange(*pbr, "roughnessFactor", pbrPath, 0.0, 1.0);
  }

  // emissiveFactor (3 numbers in [0, 1]) and KHR_materials_emissive_strength's emissiveStrength
  // (a number >= 0, which tinygltf would hand over negative or as a string read as 0).
  static Status checkEmission(const Json& material, const std::string& path) {
    ENGINE_TRY(optionalNumberArray(material, "emissiveFactor", path, 3, 0.0, 1.0));
    ENGINE_TRY_ASSIGN(const Json* extensions, optionalObject(material, "extensions", path));
    if (!extensions) return {};
    const std::string extensionsPath = member(path, "extensions");
    ENGINE_TRY_ASSIGN(const Json* strength, optionalObject(*extensions, "KHR_materials_emissive_strength", extensionsPath));
    if (!strength) return {};
    return optionalNumberAtLeast(*strength, "emissiveStrength", member(extensionsPath, "KHR_materials_emissive_strength"),
                                 0.0);
  }

  const Json& document_;
  Arrays a_;
};

}  // namespace

Status checkGltfSchema(const nlohmann::json& document) {
  if (!document.is_object()) return makeError("the top-level JSON value is not an object");
  return SchemaCheck(document).run();
}

}  // namespace engine::scene
