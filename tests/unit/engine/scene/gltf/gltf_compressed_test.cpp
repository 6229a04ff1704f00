// glTF as users have it: the small bunny of tests/data/gltf/ compressed with Draco (gltf-pipeline),
// meshopt and quantized (glTF-Transform) must load as the same mesh as its plain original, and broken
// compressed streams must give errors naming the file and the problem.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "engine/core/files.h"
#include "engine/scene/gltf/gltf_compression.h"
#include "engine/scene/gltf/gltf_loader.h"

namespace engine::scene {
namespace {

using nlohmann::json;

const std::filesystem::path kDataDir = std::filesystem::path(HSDF_TEST_DATA_DIR) / "gltf";

// World-space geometry of the file's single mesh instance (positions through the node matrix,
// normals through its inverse transpose): the meshopt and quantized files store positions in
// normalized integers and undo that with a node scale + translation.
struct WorldMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<std::uint32_t> indices;
};

WorldMesh loadWorldMesh(const std::string& file) {
  WorldMesh out;
  const auto scene = loadGltf(kDataDir / file);
  EXPECT_TRUE(scene.ok()) << scene.error().message;
  if (!scene.ok()) return out;
  for (const auto& node : scene->nodes) {
    if (node.mesh < 0) continue;
    const auto& primitive = scene->meshes.at(std::size_t(node.mesh)).primitives.at(0);
    const glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(node.world)));
    for (const auto& p : primitive.positions) out.positions.push_back(glm::vec3(node.world * glm::vec4(p, 1.0f)));
    for (const auto& n : primitive.normals) out.normals.push_back(glm::normalize(normalMatrix * n));
    out.indices = primitive.indices;
  }
  return out;
}

// Per-axis tolerance: 2^-10 of the plain mesh's largest extent, above one quantization step of the
// coarsest encoding here (Draco's 11-bit positions: extent / 2047) and far below what a decoding
// mistake does (a wrong scale, offset, axis order or index moves vertices by a good part of the
// extent).
float positionTolerance(const WorldMesh& plain) {
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const auto& p : plain.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::vec3 extent = hi - lo;
  return std::max({extent.x, extent.y, extent.z}) / 1024.0f;
}

std::size_t nearest(const std::vector<glm::vec3>& points, const glm::vec3& q) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < points.size(); ++i)
    if (glm::distance(points[i], q) < glm::distance(points[best], q)) best = i;
  return best;
}

// Triangles as index triples rotated to start at their smallest index (winding kept), sorted.
std::vector<std::array<std::uint32_t, 3>> canonicalTriangles(const std::vector<std::uint32_t>& indices,
                                                             const std::vector<std::size_t>& remap) {
  std::vector<std::array<std::uint32_t, 3>> triangles;
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    std::array<std::uint32_t, 3> tri{std::uint32_t(remap[indices[t]]), std::uint32_t(remap[indices[t + 1]]),
                                     std::uint32_t(remap[indices[t + 2]])};
    std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
    triangles.push_back(tri);
  }
  std::sort(triangles.begin(), triangles.end());
  return triangles;
}

class CompressedBunny : public ::testing::TestWithParam<const char*> {};

// Tricky because the encoders reorder vertices and triangles (meshopt optimises for its codec), so
// nothing can be compared index by index: each decoded vertex is matched to its nearest plain
// vertex (the match must be one to one, within the quantization tolerance), and the triangles,
// renamed through that match, must be exactly the plain triangles with the same winding. That
// catches a wrong index decoding, a flipped winding, a lost or repeated triangle and any position
// error above the quantization step; normals must agree within the normal encodings' error.
TEST_P(CompressedBunny, LoadsAsThePlainMeshWithinQuantization) {
  const WorldMesh plain = loadWorldMesh("bunny_small.glb");
  const WorldMesh packed = loadWorldMesh(GetParam());
  ASSERT_EQ(plain.positions.size(), 148u);
  ASSERT_EQ(plain.indices.size(), 3u * 292u);
  ASSERT_EQ(packed.positions.size(), plain.positions.size());
  ASSERT_EQ(packed.indices.size(), plain.indices.size());
  ASSERT_EQ(packed.normals.size(), packed.positions.size());

  const float tolerance = positionTolerance(plain);
  const float radius = tolerance * std::sqrt(3.0f);  // per-axis tolerance on all three axes
  // The matching is only unambiguous if plain vertices are further apart than twice the radius.
  float closestPair = std::numeric_limits<float>::max();
  for (std::size_t i = 0; i < plain.positions.size(); ++i)
    for (std::size_t j = i + 1; j < plain.positions.size(); ++j)
      closestPair = std::min(closestPair, glm::distance(plain.positions[i], plain.positions[j]));
  ASSERT_GT(closestPair, 2.0f * radius);

  std::vector<std::size_t> remap(packed.positions.size());
  std::vector<bool> used(plain.positions.size(), false);
  float worstDistance = 0.0f, worstNormalDegrees = 0.0f;
  for (std::size_t v = 0; v < packed.positions.size(); ++v) {
    remap[v] = nearest(plain.positions, packed.positions[v]);
    const float distance = glm::distance(plain.positions[remap[v]], packed.positions[v]);
    worstDistance = std::max(worstDistance, distance);
    EXPECT_LE(distance, radius) << "vertex " << v;
    EXPECT_FALSE(used[remap[v]]) << "two decoded vertices match plain vertex " << remap[v];
    used[remap[v]] = true;
    const float cosine = std::clamp(glm::dot(plain.normals[remap[v]], packed.normals[v]), -1.0f, 1.0f);
    worstNormalDegrees = std::max(worstNormalDegrees, glm::degrees(std::acos(cosine)));
  }
  std::vector<std::size_t> identity(plain.positions.size());
  for (std::size_t i = 0; i < identity.size(); ++i) identity[i] = i;
  EXPECT_EQ(canonicalTriangles(packed.indices, remap), canonicalTriangles(plain.indices, identity));
  // 8-bit octahedral normals (Draco's default, meshopt's OCTAHEDRAL filter at stride 4) are within
  // about 1 degree; 3 degrees leaves room, while a wrong filter or axis gives tens of degrees.
  EXPECT_LT(worstNormalDegrees, 3.0f);
  std::printf("%s: worst vertex distance %.3g (tolerance %.3g), worst normal %.2f degrees\n", GetParam(),
              double(worstDistance), double(radius), double(worstNormalDegrees));
}

INSTANTIATE_TEST_SUITE_P(GltfLoader, CompressedBunny,
                         ::testing::Values("bunny_small_draco.glb", "bunny_small_meshopt.glb", "bunny_small_quantized.glb"));

// ------------------------------------------------------------------------------------------------
// Broken compressed streams

struct Glb {
  json document;
  std::vector<std::uint8_t> bin;
};

std::uint32_t u32(const std::vector<std::uint8_t>& bytes, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, bytes.data() + at, 4);
  return v;
}

// The committed GLBs have a JSON chunk then a BIN chunk.
Glb readGlb(const std::string& file) {
  auto bytes = readBinaryFile(kDataDir / file);
  EXPECT_TRUE(bytes.ok());
  if (!bytes.ok()) return {};
  const std::uint32_t jsonLength = u32(*bytes, 12);
  Glb glb;
  glb.document = json::parse(bytes->begin() + 20, bytes->begin() + 20 + jsonLength);
  const std::size_t binAt = 20 + jsonLength;
  const std::uint32_t binLength = u32(*bytes, binAt);
  glb.bin.assign(bytes->begin() + std::ptrdiff_t(binAt + 8), bytes->begin() + std::ptrdiff_t(binAt + 8 + binLength));
  return glb;
}

std::vector<std::uint8_t> writeGlb(const Glb& glb) {
  std::string text = glb.document.dump();
  while (text.size() % 4 != 0) text += ' ';
  std::vector<std::uint8_t> out;
  auto put = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(std::uint8_t(v >> (8 * i)));
  };
  put(0x46546C67);
  put(2);
  put(std::uint32_t(12 + 8 + text.size() + 8 + glb.bin.size()));
  put(std::uint32_t(text.size()));
  put(0x4E4F534A);
  out.insert(out.end(), text.begin(), text.end());
  put(std::uint32_t(glb.bin.size()));
  put(0x004E4942);
  out.insert(out.end(), glb.bin.begin(), glb.bin.end());
  return out;
}

std::string loadError(const Glb& glb, std::string_view name) {
  const auto bytes = writeGlb(glb);
  const auto scene = loadGltfFromMemory(bytes, name, {});
  return scene.ok() ? "(loaded)" : scene.error().message;
}

void expectContains(const std::string& message, std::initializer_list<std::string_view> parts) {
  for (const auto part : parts) EXPECT_NE(message.find(part), std::string::npos) << "missing '" << part << "' in: " << message;
}

// `packed` (a compressed or quantized copy of tests/data/gltf/textured_grid.gltf) loads with its
// texture and, for each of its vertices, the texture coordinates of the plain vertex at the same
// world position (matched one to one) within `texcoordTolerance`. Its worst error is printed.
void expectTheGridsTexcoords(const std::string& packed, float texcoordTolerance) {
  const auto plain = loadGltf(kDataDir / "textured_grid.gltf");
  const auto scene = loadGltf(kDataDir / packed);
  ASSERT_TRUE(plain.ok()) << plain.error().message;
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  for (const auto& w : scene->warnings) ADD_FAILURE() << "unexpected warning: " << w;
  ASSERT_EQ(scene->textures.size(), 1u);
  EXPECT_EQ(scene->textures[0].rgba, plain->textures.at(0).rgba);
  EXPECT_EQ(scene->materials.at(0).baseColorTexture, 0);
  const auto& expected = plain->meshes.at(0).primitives.at(0);
  const auto& decoded = scene->meshes.at(0).primitives.at(0);
  ASSERT_EQ(expected.positions.size(), 16u);
  ASSERT_EQ(decoded.positions.size(), expected.positions.size());
  ASSERT_EQ(decoded.texcoords.size(), decoded.positions.size());
  const glm::mat4 world = scene->nodes.at(0).world;  // gltfpack stores integer positions and a node scale
  const float positionTolerance = 1.0f / 1024.0f;    // 11 bits or more over a unit square
  std::vector<bool> used(expected.positions.size(), false);
  float worst = 0.0f;
  for (std::size_t v = 0; v < decoded.positions.size(); ++v) {
    const glm::vec3 position = glm::vec3(world * glm::vec4(decoded.positions[v], 1.0f));
    const std::size_t match = nearest(expected.positions, position);
    EXPECT_LE(glm::distance(expected.positions[match], position), positionTolerance) << "vertex " << v;
    EXPECT_FALSE(used[match]) << "two decoded vertices match plain vertex " << match;
    used[match] = true;
    const glm::vec2 error = glm::abs(decoded.texcoords[v] - expected.texcoords[match]);
    worst = std::max({worst, error.x, error.y});
  }
  EXPECT_LE(worst, texcoordTolerance);
  std::printf("%s: worst texture coordinate error %.3g (tolerance %.3g)\n", packed.c_str(), double(worst),
              double(texcoordTolerance));
}

// Why: web pipelines compress textured models with Draco (gltf-pipeline -d), TEXCOORD_0 with the
// positions; read from the accessors only, the texture was not drawn, and the note said the
// primitive had no TEXCOORD_0. Tricky because Draco reorders the points and quantizes the
// coordinates (10 bits by default: over about 0.94, a step of 0.001): each decoded vertex is
// matched to its plain vertex by position, one to one; the grid's coordinates are no function of
// its positions, so a wrong attribute or order is seen.
TEST(GltfLoaderCompressed, ADracoTexturedMeshKeepsItsTextureCoordinates) {
  expectTheGridsTexcoords("textured_grid_draco.glb", 1.0f / 512.0f);

  // A TEXCOORD_0 id that names the normals (3 components) is a warning: the mesh is drawn in its factor.
  Glb wrong = readGlb("textured_grid_draco.glb");
  auto& ids = wrong.document["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"];
  ids["TEXCOORD_0"] = ids["NORMAL"];
  const auto bytes = writeGlb(wrong);
  const auto untextured = loadGltfFromMemory(bytes, "wrong.glb", {});
  ASSERT_TRUE(untextured.ok()) << untextured.error().message;
  EXPECT_TRUE(untextured->meshes.at(0).primitives.at(0).texcoords.empty());
  std::string notes;
  for (const auto& w : untextured->warnings) notes += w + "\n";
  EXPECT_NE(notes.find("mesh 0 'grid' primitive 0: TEXCOORD_0 not read: TEXCOORD_0: Draco attribute 1 has 3 components, "
                       "expected 2"),
            std::string::npos)
      << notes;
}

// Why: KHR_draco_mesh_compression has a primitive's attributes that its extension's `attributes` do
// not name read from their accessors as usual (an encoder may compress the positions only); an
// uncompressed TEXCOORD_0 beside a Draco stream was skipped, and the texture not drawn. The file:
// the Draco grid with TEXCOORD_0 taken out of the extension's map (the stream still holds it) and
// given as a float accessor of coordinates made here from each decoded vertex's position, unlike
// the stream's (the grid's coordinates are no function of its positions): reading the stream's,
// or none, is seen.
TEST(GltfLoaderCompressed, AnUncompressedTexcoordBesideADracoStreamIsRead) {
  const auto draco = loadGltf(kDataDir / "textured_grid_draco.glb");
  ASSERT_TRUE(draco.ok()) << draco.error().message;
  std::vector<float> own;
  for (const glm::vec3& p : draco->meshes.at(0).primitives.at(0).positions) {
    own.push_back(0.25f + 0.5f * p.x);
    own.push_back(0.75f - 0.25f * p.y + 0.125f * p.z);
  }
  Glb glb = readGlb("textured_grid_draco.glb");
  json& primitive = glb.document["meshes"][0]["primitives"][0];
  ASSERT_EQ(primitive["extensions"]["KHR_draco_mesh_compression"]["attributes"].erase("TEXCOORD_0"), 1u);
  while (glb.bin.size() % 4 != 0) glb.bin.push_back(0);
  const std::size_t offset = glb.bin.size(), length = own.size() * sizeof(float);
  glb.bin.resize(offset + length);
  std::memcpy(glb.bin.data() + offset, own.data(), length);
  glb.document["buffers"][0]["byteLength"] = glb.bin.size();
  glb.document["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}});
  glb.document["accessors"].push_back({{"bufferView", glb.document["bufferViews"].size() - 1},
                                       {"componentType", 5126},
                                       {"count", own.size() / 2},
                                       {"type", "VEC2"}});
  primitive["attributes"]["TEXCOORD_0"] = glb.document["accessors"].size() - 1;
  const auto bytes = writeGlb(glb);
  const auto scene = loadGltfFromMemory(bytes, "texcoord_beside_draco.glb", {});
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  for (const auto& w : scene->warnings) ADD_FAILURE() << "unexpected warning: " << w;
  const auto& read = scene->meshes.at(0).primitives.at(0).texcoords;
  ASSERT_EQ(read.size() * 2, own.size()) << "TEXCOORD_0 read from its accessor";
  for (std::size_t v = 0; v < read.size(); ++v)
    EXPECT_EQ(read[v], glm::vec2(own[2 * v], own[2 * v + 1])) << "vertex " << v;
}

// Why: gltfpack quantizes texture coordinates to normalized 16-bit integers and undoes that with a
// KHR_texture_transform (offset and scale, KHR_mesh_quantization's way); read without it, every
// textured file out of gltfpack drew the corner of its texture. Tricky because positions are
// quantized too (integers under a node scale), so vertices are matched in world space.
TEST(GltfLoaderCompressed, AGltfpackTexturedMeshReadsItsTextureThroughItsTransform) {
  expectTheGridsTexcoords("textured_grid_gltfpack.glb", 1.0f / 2048.0f);
}

// Tricky because the writer round trip itself must be lossless, or every case below would pass for
// the wrong reason: the untouched file must load.
TEST(GltfLoaderCompressedMalformed, UntouchedRoundTripLoads) {
  EXPECT_EQ(loadError(readGlb("bunny_small_draco.glb"), "draco.glb"), "(loaded)");
  EXPECT_EQ(loadError(readGlb("bunny_small_meshopt.glb"), "meshopt.glb"), "(loaded)");
}

// Tricky because Draco streams carry no checksum: a cut stream, an attribute id that is not in it,
// or a stream whose point count contradicts the accessor must each be caught (by the decoder or by
// the counts), never read as a smaller or different mesh.
TEST(GltfLoaderCompressedMalformed, BrokenDracoPrimitivesAreNamed) {
  const Glb original = readGlb("bunny_small_draco.glb");
  auto draco = [](json& doc) -> json& {
    return doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"];
  };

  Glb cut = original;
  cut.document["bufferViews"][0]["byteLength"] = 64;
  expectContains(loadError(cut, "cut.glb"), {"cut.glb", "mesh 0 'bunny' primitive 0", "KHR_draco_mesh_compression", "Draco"});

  Glb badId = original;
  draco(badId.document)["attributes"]["POSITION"] = 7;
  expectContains(loadError(badId, "id.glb"), {"id.glb", "POSITION: the Draco stream has no attribute with id 7"});

  Glb badCount = original;
  const int positionAccessor = badCount.document["meshes"][0]["primitives"][0]["attributes"]["POSITION"];
  badCount.document["accessors"][std::size_t(positionAccessor)]["count"] = 147;
  expectContains(loadError(badCount, "count.glb"), {"the Draco stream has 148 points but the POSITION accessor says 147"});

  Glb noView = original;
  draco(noView.document)["bufferView"] = 9;
  expectContains(loadError(noView, "view.glb"), {"bufferView 9 out of range (file has 1)"});

  Glb negative = original;
  draco(negative.document)["bufferView"] = -1;
  expectContains(loadError(negative, "neg.glb"), {"bufferView is a JSON number, not a non-negative integer"});
}

// Tricky because libdraco may reorder a primitive's points, so morph targets stored beside a Draco
// stream (uncompressed, in the file's order) cannot be added point by point: applying them would
// move the wrong vertices. With the mesh's default weights set they are left out, and said so
// naming the primitive; the mesh loads as its compressed stream, exactly.
TEST(GltfLoaderCompressedMalformed, MorphTargetsOfADracoPrimitiveAreNamedAndNotApplied) {
  const Glb original = readGlb("bunny_small_draco.glb");
  Glb morphed = original;
  json& doc = morphed.document;
  const int positionAccessor = doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"];
  const std::size_t points = doc["accessors"][std::size_t(positionAccessor)]["count"];
  const std::size_t at = morphed.bin.size();  // a 4-byte multiple: the BIN chunk is padded
  for (std::size_t i = 0; i < points; ++i)
    for (const float d : {1.0f, 0.0f, 0.0f}) {
      std::array<std::uint8_t, 4> b{};
      std::memcpy(b.data(), &d, 4);
      morphed.bin.insert(morphed.bin.end(), b.begin(), b.end());
    }
  doc["buffers"][0]["byteLength"] = morphed.bin.size();
  doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", at}, {"byteLength", points * 12}});
  doc["accessors"].push_back({{"bufferView", doc["bufferViews"].size() - 1}, {"componentType", 5126},
                              {"count", points}, {"type", "VEC3"}, {"min", {1, 0, 0}}, {"max", {1, 0, 0}}});
  doc["meshes"][0]["primitives"][0]["targets"] = json::array({{{"POSITION", doc["accessors"].size() - 1}}});
  doc["meshes"][0]["weights"] = {1.0};
  const auto loaded = [](const Glb& glb, std::string_view name) {
    const auto bytes = writeGlb(glb);
    return loadGltfFromMemory(bytes, name, {});
  };
  const auto scene = loaded(morphed, "morphed.glb");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const auto named = std::find_if(scene->warnings.begin(), scene->warnings.end(), [](const std::string& w) {
    return w.find("mesh 0 'bunny' primitive 0: morph targets of a Draco-compressed primitive are not applied") !=
           std::string::npos;
  });
  EXPECT_NE(named, scene->warnings.end());
  const auto plain = loaded(original, "plain.glb");
  ASSERT_TRUE(plain.ok()) << plain.error().message;
  EXPECT_EQ(scene->meshes[0].primitives[0].positions, plain->meshes[0].primitives[0].positions);
}

// The committed Draco stream is bitstream 2.2, edgebreaker, no metadata (gltf-pipeline's default):
// an 11-byte header ("DRACO", version, encoder type, method, flags), the traversal type, then the
// varint counts of encoded vertices and faces. The tests below edit it by that layout, written down
// here from the Draco bitstream specification rather than taken from the reader under test.
constexpr std::size_t kDracoFlagsAt = 9, kDracoCountsAt = 12;

std::vector<std::uint8_t> dracoStream(const Glb& glb) {
  const std::size_t length = glb.document["bufferViews"][0]["byteLength"];
  return {glb.bin.begin(), glb.bin.begin() + std::ptrdiff_t(length)};
}

// Puts `stream` back as the file's only bufferView (the Draco one) and its only buffer.
Glb withDracoStream(Glb glb, std::vector<std::uint8_t> stream) {
  glb.document["bufferViews"][0]["byteLength"] = stream.size();
  while (stream.size() % 4 != 0) stream.push_back(0);
  glb.document["buffers"][0]["byteLength"] = stream.size();
  glb.bin = std::move(stream);
  return glb;
}

std::vector<std::uint8_t> varint(std::uint32_t value) {
  std::vector<std::uint8_t> out;
  do {
    out.push_back(std::uint8_t((value & 0x7f) | (value >= 0x80 ? 0x80 : 0)));
    value >>= 7;
  } while (value != 0);
  return out;
}

std::size_t varintLength(const std::vector<std::uint8_t>& bytes, std::size_t at) {
  std::size_t n = 1;
  while (bytes[at + n - 1] & 0x80) ++n;
  return n;
}

std::size_t replaceVarint(std::vector<std::uint8_t>& bytes, std::size_t at, std::uint32_t value) {
  const auto encoded = varint(value);
  bytes.erase(bytes.begin() + std::ptrdiff_t(at), bytes.begin() + std::ptrdiff_t(at + varintLength(bytes, at)));
  bytes.insert(bytes.begin() + std::ptrdiff_t(at), encoded.begin(), encoded.end());
  return at + encoded.size();
}

// The committed stream with its vertex and face counts, and its symbol count (one per face but the
// first, which libdraco checks against the faces), replaced.
std::vector<std::uint8_t> withDeclaredCounts(std::vector<std::uint8_t> stream, std::uint32_t vertices, std::uint32_t faces) {
  const std::size_t facesAt = replaceVarint(stream, kDracoCountsAt, vertices);
  const std::size_t attributeDataAt = replaceVarint(stream, facesAt, faces);
  replaceVarint(stream, attributeDataAt + 1, faces - 1);
  return stream;
}

// Tricky because libdraco trusts the face count in the stream's header: it sizes its corner table
// from it before reading one symbol, so a 1 KB stream declaring 2^30 faces made it allocate ~12 GB
// (found by scripts/fuzz.sh in CI). The loader must read the counts first and refuse the file by
// name; the same stream with its true count must still load.
TEST(GltfLoaderCompressedMalformed, DracoStreamDeclaringAHugeMeshIsRefusedBeforeDecoding) {
  const Glb original = readGlb("bunny_small_draco.glb");
  const auto stream = dracoStream(original);
  const std::uint32_t faces = original.document["accessors"][0]["count"].get<std::uint32_t>() / 3;
  const std::uint32_t vertices = original.document["accessors"][1]["count"];
  EXPECT_EQ(loadError(withDracoStream(original, withDeclaredCounts(stream, vertices, faces)), "same.glb"), "(loaded)");
  // 2^16 vertices: enough edges for 2^30 faces, which libdraco checks before it allocates.
  expectContains(loadError(withDracoStream(original, withDeclaredCounts(stream, 1u << 16, 1u << 30)), "huge.glb"),
                 {"huge.glb", "mesh 0 'bunny' primitive 0", "KHR_draco_mesh_compression",
                  "the Draco stream declares 1073741824 faces and 65536 vertices", "over the limit for this file"});
}

// Tricky because the counts sit after the header's optional metadata (a tree of named entries and
// named sub-trees of any depth): skipping it wrongly would read the counts from the wrong bytes. A
// stream given metadata must report the counts its accessors declare and still decode in libdraco
// (which reads the metadata itself), and a cut header or metadata must be an error.
TEST(GltfDracoCounts, CountsAreReadPastTheHeadersMetadata) {
  const Glb original = readGlb("bunny_small_draco.glb");
  const auto stream = dracoStream(original);
  const std::uint64_t faces = original.document["accessors"][0]["count"].get<std::uint64_t>() / 3;
  const std::uint64_t vertices = original.document["accessors"][1]["count"].get<std::uint64_t>();
  const auto plain = readDracoCounts(stream);
  ASSERT_TRUE(plain.ok()) << plain.error().message;
  EXPECT_EQ(plain->faces, faces);
  EXPECT_EQ(plain->vertices, vertices);

  // One attribute tree (id 0: entry "q" = 2 bytes, one sub-tree "s" with one entry and none below),
  // then the file's tree (no entries, two empty sub-trees).
  const std::vector<std::uint8_t> metadata = {1, 0,                          // 1 attribute tree, for id 0
                                              1, 1, 'q', 2, 7, 7,            //   entry q: 2 bytes
                                              1,                             //   1 sub-tree
                                              1, 's', 1, 1, 'r', 1, 9, 0,    //     "s": entry r: 1 byte; no sub-trees
                                              0, 2,                          // file: no entries, 2 sub-trees
                                              1, 'a', 0, 0, 1, 'b', 0, 0};   //   "a", "b": empty
  auto withMetadata = stream;
  withMetadata[kDracoFlagsAt + 1] |= 0x80;  // flags are little-endian; 0x8000 = metadata present
  withMetadata.insert(withMetadata.begin() + 11, metadata.begin(), metadata.end());
  const auto counted = readDracoCounts(withMetadata);
  ASSERT_TRUE(counted.ok()) << counted.error().message;
  EXPECT_EQ(counted->faces, faces);
  EXPECT_EQ(counted->vertices, vertices);
  EXPECT_EQ(loadError(withDracoStream(original, withMetadata), "metadata.glb"), "(loaded)");

  for (std::size_t length : {4ul, 11ul, 13ul, 11ul + metadata.size() - 1}) {
    const std::vector<std::uint8_t> cut(withMetadata.begin(), withMetadata.begin() + std::ptrdiff_t(length));
    EXPECT_FALSE(readDracoCounts(cut).ok()) << "cut at " << length;
  }
  auto newer = stream;
  newer[6] = 3;  // bitstream 2.3: not one libdraco 1.5 decodes
  ASSERT_FALSE(readDracoCounts(newer).ok());
  EXPECT_NE(readDracoCounts(newer).error().message.find("version 2.3"), std::string::npos);
}

// Tricky because the meshopt decoders are handed lengths and strides from the file: a cut stream, a
// mode or filter that does not exist, a stride the codec cannot have, a count that disagrees with
// the view, and a plain view placed in the data-less fallback buffer must all be errors.
TEST(GltfLoaderCompressedMalformed, BrokenMeshoptViewsAreNamed) {
  const Glb original = readGlb("bunny_small_meshopt.glb");
  auto meshopt = [](json& doc, int view) -> json& { return doc["bufferViews"][std::size_t(view)]["extensions"]["EXT_meshopt_compression"]; };

  Glb cut = original;
  meshopt(cut.document, 0)["byteLength"] = 100;
  expectContains(loadError(cut, "cut.glb"), {"cut.glb", "bufferView 0: EXT_meshopt_compression", "meshopt TRIANGLES stream of 100 bytes is malformed"});

  Glb mode = original;
  meshopt(mode.document, 0)["mode"] = "QUADS";
  expectContains(loadError(mode, "mode.glb"), {"unknown mode 'QUADS'"});

  Glb filter = original;
  meshopt(filter.document, 1)["filter"] = "WAVELET";
  expectContains(loadError(filter, "filter.glb"), {"unknown filter 'WAVELET'"});

  Glb stride = original;
  meshopt(stride.document, 2)["byteStride"] = 6;
  expectContains(loadError(stride, "stride.glb"), {"ATTRIBUTES byteStride 6 is not a multiple of 4"});

  Glb count = original;
  meshopt(count.document, 2)["count"] = 147;
  expectContains(loadError(count, "count.glb"), {"count 147 x byteStride 8 is not the view's byteLength 1184"});

  Glb beyond = original;
  meshopt(beyond.document, 2)["byteOffset"] = 4000;
  expectContains(loadError(beyond, "beyond.glb"), {"lie beyond buffer 0"});

  Glb plainInFallback = original;
  plainInFallback.document["bufferViews"][2]["extensions"].erase("EXT_meshopt_compression");
  expectContains(loadError(plainInFallback, "fallback.glb"), {"bufferView 2 is not meshopt-compressed but lies in buffer 1, a meshopt fallback buffer"});
}

}  // namespace
}  // namespace engine::scene
