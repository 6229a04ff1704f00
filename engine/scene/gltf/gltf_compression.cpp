#include "engine/scene/gltf/gltf_compression.h"

#include <algorithm>
#include <cmath>
#include <iterator>
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

// Bounds-checked little-endian reads over the start of a Draco stream (libdraco's DecoderBuffer
// reads the same way: fixed fields as raw little-endian, counts as LEB128 varints from 2.0 on).
class DracoHeaderReader {
 public:
  explicit DracoHeaderReader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}

  std::uint64_t remaining() const { return bytes_.size() - at_; }
  bool skip(std::uint64_t n) {
    if (n > remaining()) return false;
    at_ += std::size_t(n);
    return true;
  }
  bool fixed(std::uint32_t& value, int byteCount) {
    if (std::uint64_t(byteCount) > remaining()) return false;
    value = 0;
    for (int i = 0; i < byteCount; ++i) value |= std::uint32_t(bytes_[at_++]) << (8 * i);
    return true;
  }
  bool varint(std::uint32_t& value) {  // at most 5 bytes for 32 bits, as libdraco's DecodeVarint
    value = 0;
    for (int i = 0; i < 5; ++i) {
      std::uint32_t byte = 0;
      if (!fixed(byte, 1)) return false;
      if (i == 4 && byte > 0x0f) return false;
      value |= (byte & 0x7f) << (7 * i);
      if ((byte & 0x80) == 0) return true;
    }
    return false;
  }
  // A count: a varint from bitstream 2.0 on, a raw uint32 before.
  bool count(std::uint32_t& value, bool varintCounts) { return varintCounts ? varint(value) : fixed(value, 4); }

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t at_ = 0;
};

// One metadata tree (entries, then named sub-trees), walked without recursion: the nesting depth is
// the file's to choose.
bool skipDracoMetadataTree(DracoHeaderReader& in) {
  std::uint64_t pendingNamedTrees = 0;
  bool root = true;
  do {
    std::uint32_t length = 0;
    if (!root && !(in.fixed(length, 1) && in.skip(length))) return false;
    root = false;
    std::uint32_t entries = 0;
    if (!in.varint(entries)) return false;
    for (std::uint32_t e = 0; e < entries; ++e) {  // each entry takes >= 3 bytes: ends with the stream
      std::uint32_t dataSize = 0;
      if (!(in.fixed(length, 1) && in.skip(length) && in.varint(dataSize) && dataSize > 0 && in.skip(dataSize))) return false;
    }
    std::uint32_t subTrees = 0;
    if (!in.varint(subTrees) || subTrees > in.remaining()) return false;
    pendingNamedTrees += subTrees;
  } while (pendingNamedTrees-- > 0);
  return true;
}

bool skipDracoMetadata(DracoHeaderReader& in) {
  std::uint32_t attributeTrees = 0;
  if (!in.varint(attributeTrees) || attributeTrees > in.remaining()) return false;
  for (std::uint32_t a = 0; a < attributeTrees; ++a) {
    std::uint32_t attributeId = 0;
    if (!(in.varint(attributeId) && skipDracoMetadataTree(in))) return false;
  }
  return skipDracoMetadataTree(in);  // the file's own
}

// Draco attribute `uniqueId` as N-component floats, one per point, every component finite.
template <int N>
Expected<std::vector<glm::vec<N, float>>> readDracoVectors(const draco::Mesh& mesh, std::uint32_t uniqueId,
                                                            const char* semantic) {
  const draco::PointAttribute* attribute = mesh.GetAttributeByUniqueId(uniqueId);
  if (attribute == nullptr) return makeError(fmt::format("{}: the Draco stream has no attribute with id {}", semantic, uniqueId));
  if (attribute->num_components() != N)
    return makeError(fmt::format("{}: Draco attribute {} has {} components, expected {}", semantic, uniqueId,
                                 int(attribute->num_components()), N));
  std::vector<glm::vec<N, float>> values(mesh.num_points());
  for (draco::PointIndex p(0); p < mesh.num_points(); ++p) {
    float value[N];
    if (!attribute->ConvertValue<float>(attribute->mapped_index(p), N, value))
      return makeError(fmt::format("{}: Draco attribute {} cannot be read as floats", semantic, uniqueId));
    for (int c = 0; c < N; ++c) {
      if (!std::isfinite(value[c]))
        return makeError(fmt::format("{}: point {} component {} is {} (must be finite)", semantic, p.value(), c, value[c]));
      values[p.value()][c] = value[c];
    }
  }
  return values;
}

}  // namespace

Expected<DracoCounts> readDracoCounts(std::span<const std::uint8_t> compressed) {
  constexpr std::uint8_t kMagic[] = {'D', 'R', 'A', 'C', 'O'};
  constexpr std::uint32_t kTriangularMesh = 1, kSequential = 0, kEdgebreaker = 1, kMetadataFlag = 0x8000;
  if (compressed.size() < 11 || !std::equal(std::begin(kMagic), std::end(kMagic), compressed.begin()))
    return makeError(fmt::format("not a Draco stream (no 'DRACO' header in {} bytes)", compressed.size()));
  DracoHeaderReader in(compressed.subspan(5));
  std::uint32_t major = 0, minor = 0, encoderType = 0, method = 0, flags = 0;
  if (!(in.fixed(major, 1) && in.fixed(minor, 1) && in.fixed(encoderType, 1) && in.fixed(method, 1) && in.fixed(flags, 2)))
    return makeError("the Draco stream is cut in its header");
  if (major < 1 || major > 2 || (major == 2 && minor > 2))
    return makeError(fmt::format("Draco bitstream version {}.{} (1.x and 2.0-2.2 are decoded)", major, minor));
  if (encoderType != kTriangularMesh) return makeError("the Draco stream holds a point cloud, not a triangle mesh");
  const auto version = major * 256 + minor;
  if (version >= 0x103 && (flags & kMetadataFlag) != 0 && !skipDracoMetadata(in))
    return makeError("the Draco stream's metadata is cut or malformed");
  const bool varintCounts = version >= 0x200;
  const auto cut = [&] { return makeError(fmt::format("the Draco stream of {} bytes is cut in its connectivity header", compressed.size())); };
  std::uint32_t faces = 0, vertices = 0;
  if (method == kSequential) {
    const bool varintHeader = version >= 0x202;
    if (!(varintHeader ? in.varint(faces) && in.varint(vertices) : in.fixed(faces, 4) && in.fixed(vertices, 4))) return cut();
  } else if (method == kEdgebreaker) {
    std::uint32_t traversal = 0, newVertices = 0;
    if (!in.fixed(traversal, 1)) return cut();
    if (version < 0x202 && !in.count(newVertices, varintCounts)) return cut();
    if (!(in.count(vertices, varintCounts) && in.count(faces, varintCounts))) return cut();
  } else {
    return makeError(fmt::format("unknown Draco encoding method {} (0 sequential, 1 edgebreaker)", method));
  }
  return DracoCounts{faces, vertices};
}

Expected<DracoPrimitive> decodeDracoPrimitive(std::span<const std::uint8_t> compressed, const DracoAttributeIds& ids) {
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
  ENGINE_TRY_ASSIGN(out.positions, readDracoVectors<3>(*mesh, ids.position, "POSITION"));
  if (ids.normal) {
    ENGINE_TRY_ASSIGN(out.normals, readDracoVectors<3>(*mesh, *ids.normal, "NORMAL"));
  }
  if (ids.texcoord) {
    auto texcoords = readDracoVectors<2>(*mesh, *ids.texcoord, "TEXCOORD_0");
    if (texcoords.ok())
      out.texcoords = std::move(*texcoords);
    else
      out.texcoordProblem = texcoords.error().message;
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
