#include "engine/scene/gltf_compression.h"

#include <cmath>
#include <limits>
#include <memory>

#include <draco/compression/decode.h>
#include <fmt/format.h>
#include <meshoptimizer.h>

namespace engine::scene {

// ---------------------------------------------------------------------------------------------
// EXT_meshopt_compression

Status checkMeshoptView(const MeshoptViewDesc& view) {
  const std::uint64_t stride = view.byteStride;
  if (view.count == 0) return makeError("count is 0");
  if (view.mode == "ATTRIBUTES") {
    if (stride == 0 || stride > 256 || stride % 4 != 0)
      return makeError(fmt::format("ATTRIBUTES byteStride {} is not a multiple of 4 in 4..256", stride));
  } else if (view.mode == "TRIANGLES" || view.mode == "INDICES") {
    if (stride != 2 && stride != 4) return makeError(fmt::format("{} byteStride {} is not 2 or 4", view.mode, stride));
    if (view.mode == "TRIANGLES" && view.count % 3 != 0)
      return makeError(fmt::format("TRIANGLES count {} is not a multiple of 3", view.count));
    if (view.filter != "NONE") return makeError(fmt::format("filter {} is only allowed with mode ATTRIBUTES", view.filter));
  } else {
    return makeError(fmt::format("unknown mode '{}' (ATTRIBUTES, TRIANGLES or INDICES)", view.mode));
  }
  if (view.filter == "OCTAHEDRAL" && stride != 4 && stride != 8)
    return makeError(fmt::format("OCTAHEDRAL filter needs byteStride 4 or 8, not {}", stride));
  if (view.filter == "QUATERNION" && stride != 8)
    return makeError(fmt::format("QUATERNION filter needs byteStride 8, not {}", stride));
  if (view.filter != "NONE" && view.filter != "OCTAHEDRAL" && view.filter != "QUATERNION" && view.filter != "EXPONENTIAL")
    return makeError(fmt::format("unknown filter '{}' (NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL)", view.filter));
  return {};
}

Expected<std::vector<std::uint8_t>> decodeMeshoptView(std::span<const std::uint8_t> compressed,
                                                      const MeshoptViewDesc& view) {
  ENGINE_TRY(checkMeshoptView(view));
  const auto count = static_cast<std::size_t>(view.count);
  const auto stride = static_cast<std::size_t>(view.byteStride);
  std::vector<std::uint8_t> out(count * stride);
  // The decoders check every read against `compressed` and fail (< 0) on malformed streams.
  int status = 0;
  if (view.mode == "ATTRIBUTES")
    status = meshopt_decodeVertexBuffer(out.data(), count, stride, compressed.data(), compressed.size());
  else if (view.mode == "TRIANGLES")
    status = meshopt_decodeIndexBuffer(out.data(), count, stride, compressed.data(), compressed.size());
  else
    status = meshopt_decodeIndexSequence(out.data(), count, stride, compressed.data(), compressed.size());
  if (status != 0)
    return makeError(fmt::format("meshopt {} stream of {} bytes is malformed (decoder status {})", view.mode,
                                 compressed.size(), status));
  if (view.filter == "OCTAHEDRAL") meshopt_decodeFilterOct(out.data(), count, stride);
  if (view.filter == "QUATERNION") meshopt_decodeFilterQuat(out.data(), count, stride);
  if (view.filter == "EXPONENTIAL") meshopt_decodeFilterExp(out.data(), count, stride);
  return out;
}

// ---------------------------------------------------------------------------------------------
// KHR_draco_mesh_compression

namespace {

Expected<std::vector<glm::vec3>> readDracoVec3(const draco::Mesh& mesh, std::uint32_t uniqueId, const char* semantic) {
  const draco::PointAttribute* attribute = mesh.GetAttributeByUniqueId(uniqueId);
  if (attribute == nullptr) return makeError(fmt::format("{}: the Draco stream has no attribute with id {}", semantic, uniqueId));
  if (attribute->num_components() != 3)
    return makeError(fmt::format("{}: Draco attribute {} has {} components, expected 3", semantic, uniqueId,
                                 int(attribute->num_components())));
  std::vector<glm::vec3> values(mesh.num_points());
  for (draco::PointIndex p(0); p < mesh.num_points(); ++p) {
    float value[3];
    if (!attribute->ConvertValue<float>(attribute->mapped_index(p), 3, value))
      return makeError(fmt::format("{}: Draco attribute {} cannot be read as floats", semantic, uniqueId));
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(value[c]))
        return makeError(fmt::format("{}: point {} component {} is {} (must be finite)", semantic, p.value(), c, value[c]));
      values[p.value()][c] = value[c];
    }
  }
  return values;
}

}  // namespace

Expected<DracoPrimitive> decodeDracoPrimitive(std::span<const std::uint8_t> compressed, std::uint32_t positionId,
                                              std::optional<std::uint32_t> normalId) {
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(compressed.data()), compressed.size());
  const auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
  if (!type.ok()) return makeError(fmt::format("not a Draco stream: {}", type.status().error_msg_string()));
  if (type.value() != draco::TRIANGULAR_MESH) return makeError("the Draco stream holds a point cloud, not a triangle mesh");
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) return makeError(fmt::format("Draco decoding failed: {}", decoded.status().error_msg_string()));
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  if (!mesh) return makeError("Draco decoding gave no mesh");
  if (mesh->num_points() == 0) return makeError("the Draco mesh has no points");

  DracoPrimitive out;
  ENGINE_TRY_ASSIGN(out.positions, readDracoVec3(*mesh, positionId, "POSITION"));
  if (normalId) {
    ENGINE_TRY_ASSIGN(out.normals, readDracoVec3(*mesh, *normalId, "NORMAL"));
  }
  out.indices.reserve(std::size_t(mesh->num_faces()) * 3);
  for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f) {
    const draco::Mesh::Face& face = mesh->face(f);
    for (int k = 0; k < 3; ++k) {
      if (face[k].value() >= mesh->num_points())  // the decoder checks this; a second look costs nothing
        return makeError(fmt::format("Draco face {} refers to point {} of {}", f.value(), face[k].value(), mesh->num_points()));
      out.indices.push_back(face[k].value());
    }
  }
  return out;
}

}  // namespace engine::scene
