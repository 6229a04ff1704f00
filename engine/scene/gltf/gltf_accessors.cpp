// Checked reads of a parsed glTF model (gltf_accessors.h).
#include "engine/scene/gltf/gltf_accessors.h"

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

namespace engine::scene::gltf {

// ---------------------------------------------------------------------------------------------
// Conversion context, numbers

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

Expected<float> toFiniteFloat(double value, std::string_view what) {
  if (!std::isfinite(value) || std::abs(value) > double(std::numeric_limits<float>::max()))
    return makeError(fmt::format("{} {} is not a finite 32-bit float", what, value));
  return static_cast<float>(value);
}

namespace {

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

}  // namespace

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

namespace {

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

}  // namespace

namespace {

// VEC2, VEC3 or VEC4 elements as floats (glTF's rules for normalized integers); every component finite.
template <int N>
Expected<std::vector<glm::vec<N, float>>> readFloatVectors(ImportContext& context, int accessorIndex) {
  ENGINE_TRY_ASSIGN(const AccessorSpan span,
                    accessorSpan(context, accessorIndex,
                                 N == 2 ? TINYGLTF_TYPE_VEC2 : N == 3 ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC4));
  ENGINE_TRY(chargeDecode(context, span.count * sizeof(glm::vec<N, float>)));
  const std::uint64_t componentSize = componentBytes(span.componentType);
  std::vector<glm::vec<N, float>> values(static_cast<std::size_t>(span.count));
  for (std::size_t i = 0; i < values.size(); ++i) {
    const std::uint8_t* element = span.element(i);
    for (int c = 0; c < N; ++c) {
      const float component = readComponent(element + std::uint64_t(c) * componentSize, span.componentType, span.normalized);
      if (!std::isfinite(component))
        return makeError(fmt::format("accessor {}: element {} component {} is {} (must be finite)", accessorIndex,
                                     i, c, component));
      values[i][c] = component;
    }
  }
  return values;
}

}  // namespace

Expected<std::vector<glm::vec2>> readVec2(ImportContext& context, int accessorIndex) {
  return readFloatVectors<2>(context, accessorIndex);
}

Expected<std::vector<glm::vec3>> readVec3(ImportContext& context, int accessorIndex) {
  return readFloatVectors<3>(context, accessorIndex);
}

Expected<std::vector<glm::vec4>> readVec4(ImportContext& context, int accessorIndex) {
  return readFloatVectors<4>(context, accessorIndex);
}

Expected<std::vector<float>> readFloats(ImportContext& context, int accessorIndex) {
  ENGINE_TRY_ASSIGN(const AccessorSpan span, accessorSpan(context, accessorIndex, TINYGLTF_TYPE_SCALAR));
  if (span.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || span.normalized)
    return makeError(fmt::format("accessor {}: componentType {} is not FLOAT (5126)", accessorIndex, span.componentType));
  ENGINE_TRY(chargeDecode(context, span.count * sizeof(float)));
  std::vector<float> values(static_cast<std::size_t>(span.count));
  for (std::size_t i = 0; i < values.size(); ++i) {
    values[i] = readComponent(span.element(i), span.componentType, false);
    if (!std::isfinite(values[i]))
      return makeError(fmt::format("accessor {}: element {} is {} (must be finite)", accessorIndex, i, values[i]));
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

}  // namespace engine::scene::gltf
