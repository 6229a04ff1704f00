// glTF import: the committed bunny, a hand-written hierarchy, feature cases built in memory, and
// malformed files that must give an error naming the file and the problem (never a crash or hang).
#include "test_files.h"
#include "engine/scene/gltf/gltf_loader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "engine/core/files.h"
#include "engine/core/image_io.h"
#include "engine/scene/transform.h"

namespace engine::scene {
namespace {

using nlohmann::json;

constexpr int kFloat = 5126;
constexpr int kUnsignedByte = 5121;
constexpr int kUnsignedShort = 5123;
constexpr int kUnsignedInt = 5125;
constexpr int kByte = 5120;

const std::filesystem::path kDataDir = std::filesystem::path(HSDF_TEST_DATA_DIR) / "gltf";
const std::filesystem::path kBunnyPath = std::filesystem::path(HSDF_ASSET_DIR) / "bunny.glb";

std::string base64(const std::vector<std::uint8_t>& bytes) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t n = std::uint32_t(bytes[i]) << 16 | (i + 1 < bytes.size() ? std::uint32_t(bytes[i + 1]) << 8 : 0u) |
                            (i + 2 < bytes.size() ? std::uint32_t(bytes[i + 2]) : 0u);
    out += alphabet[n >> 18 & 63];
    out += alphabet[n >> 12 & 63];
    out += i + 1 < bytes.size() ? alphabet[n >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? alphabet[n & 63] : '=';
  }
  return out;
}

// Builds a glTF document around one embedded (data: URI) buffer, so that each test can state the
// one thing it breaks or exercises.
class GltfBuilder {
 public:
  GltfBuilder() { doc_ = {{"asset", {{"version", "2.0"}}}}; }

  template <class T>
  std::size_t addData(const std::vector<T>& values) {
    while (bin_.size() % 4 != 0) bin_.push_back(0);
    const std::size_t offset = bin_.size();
    bin_.resize(offset + values.size() * sizeof(T));
    if (!values.empty()) std::memcpy(bin_.data() + offset, values.data(), values.size() * sizeof(T));
    return offset;
  }

  int addView(std::size_t offset, std::size_t length, int stride = 0) {
    json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}};
    if (stride != 0) view["byteStride"] = stride;
    return append("bufferViews", view);
  }

  int addAccessor(int view, int componentType, std::uint64_t count, const char* type, bool normalized = false) {
    json accessor = {{"bufferView", view}, {"componentType", componentType}, {"count", count}, {"type", type}};
    if (normalized) accessor["normalized"] = true;
    return append("accessors", accessor);
  }

  template <class T>
  int addTightAccessor(const std::vector<T>& values, int componentType, const char* type, std::uint64_t count,
                       bool normalized = false) {
    const std::size_t offset = addData(values);
    return addAccessor(addView(offset, values.size() * sizeof(T)), componentType, count, type, normalized);
  }

  int addPositions(const std::vector<glm::vec3>& positions) {
    std::vector<float> flat;
    for (const auto& p : positions) flat.insert(flat.end(), {p.x, p.y, p.z});
    return addTightAccessor(flat, kFloat, "VEC3", positions.size());
  }

  int addIndices(const std::vector<std::uint32_t>& indices) {
    return addTightAccessor(indices, kUnsignedInt, "SCALAR", indices.size());
  }

  // A mesh with one primitive; returns the mesh index.
  // Positions first, then indices (separate statements: argument evaluation order is unspecified).
  int addIndexedMesh(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& indices) {
    const int positionAccessor = addPositions(positions);
    return addMesh(positionAccessor, addIndices(indices));
  }

  int addMesh(int positions, int indices = -1, int mode = 4) {
    json primitive = {{"attributes", {{"POSITION", positions}}}, {"mode", mode}};
    if (indices >= 0) primitive["indices"] = indices;
    return append("meshes", json{{"primitives", json::array({primitive})}});
  }

  int addNode(json node) { return append("nodes", std::move(node)); }

  json& doc() { return doc_; }

  std::vector<std::uint8_t> bytes() {
    json doc = doc_;
    if (!bin_.empty())
      doc["buffers"] = json::array({{{"byteLength", bin_.size()},
                                     {"uri", "data:application/octet-stream;base64," + base64(bin_)}}});
    const std::string text = doc.dump();
    return {text.begin(), text.end()};
  }

 private:
  int append(const char* key, json value) {
    if (!doc_.contains(key)) doc_[key] = json::array();
    doc_[key].push_back(std::move(value));
    return int(doc_[key].size() - 1);
  }

  json doc_;
  std::vector<std::uint8_t> bin_;
};

const std::vector<glm::vec3> kTriangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

// One triangle mesh instanced by one node: the smallest scene with geometry.
GltfBuilder triangleScene() {
  GltfBuilder b;
  b.addNode({{"mesh", b.addIndexedMesh(kTriangle, {0, 1, 2})}});
  return b;
}

Expected<SceneData> load(GltfBuilder& builder, std::string_view name = "case.gltf") {
  const auto bytes = builder.bytes();
  return loadGltfFromMemory(bytes, name, {});
}

// The error must exist, name the file and contain each expected fragment of the problem.
void expectError(const Expected<SceneData>& result, std::string_view fileName, std::initializer_list<std::string_view> fragments) {
  ASSERT_FALSE(result.ok()) << "expected an error mentioning " << *fragments.begin();
  const std::string& message = result.error().message;
  EXPECT_NE(message.find(fileName), std::string::npos) << message;
  for (const auto fragment : fragments) EXPECT_NE(message.find(fragment), std::string::npos) << "missing '" << fragment << "' in: " << message;
}

void expectNear(const glm::vec2& actual, const glm::vec2& expected, float tolerance) {
  EXPECT_NEAR(actual.x, expected.x, tolerance);
  EXPECT_NEAR(actual.y, expected.y, tolerance);
}

void expectNear(const glm::vec3& actual, const glm::vec3& expected, float tolerance = 1e-5f) {
  EXPECT_NEAR(actual.x, expected.x, tolerance);
  EXPECT_NEAR(actual.y, expected.y, tolerance);
  EXPECT_NEAR(actual.z, expected.z, tolerance);
}

void expectMatrixNear(const glm::mat4& actual, const glm::mat4& expected) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) EXPECT_NEAR(actual[c][r], expected[c][r], 1e-5f) << "column " << c << " row " << r;
}

bool anyWarningContains(const SceneData& scene, std::string_view fragment) {
  for (const auto& w : scene.warnings)
    if (w.find(fragment) != std::string::npos) return true;
  return false;
}

// The warnings one a line, for a failure message.
std::string warningLines(const SceneData& scene) {
  std::string lines;
  for (const auto& w : scene.warnings) lines += w + "\n";
  return lines;
}

std::vector<std::uint8_t> bunnyBytes() {
  auto bytes = readBinaryFile(kBunnyPath);
  EXPECT_TRUE(bytes.ok()) << bytes.error().message;
  return bytes.ok() ? bytes.value() : std::vector<std::uint8_t>{};
}

void writeU32(std::vector<std::uint8_t>& bytes, std::size_t offset, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) bytes[offset + std::size_t(i)] = std::uint8_t(value >> (8 * i));
}

std::uint32_t readU32(const std::vector<std::uint8_t>& bytes, std::size_t offset) {
  std::uint32_t value = 0;
  for (int i = 0; i < 4; ++i) value |= std::uint32_t(bytes[offset + std::size_t(i)]) << (8 * i);
  return value;
}

// ------------------------------------------------------------------------------------------------
// The committed asset

// Tricky because it checks the converter and the loader together: counts from the npm package,
// a closed surface after index decoding (a scrambled index buffer would leave unpaired edges), CCW
// winding (positive signed volume), outward unit normals, and no tinygltf warnings at all.
TEST(GltfLoaderBunny, LoadsWatertightCounterClockwiseWithOutwardNormals) {
  const auto scene = loadGltf(kBunnyPath);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_TRUE(scene->warnings.empty()) << scene->warnings.front();
  ASSERT_EQ(scene->meshes.size(), 1u);
  ASSERT_EQ(scene->meshes[0].primitives.size(), 1u);
  const auto& primitive = scene->meshes[0].primitives[0];
  EXPECT_EQ(primitive.positions.size(), 1839u);
  EXPECT_EQ(primitive.indices.size(), 3u * 3674u);
  ASSERT_EQ(primitive.normals.size(), primitive.positions.size());
  EXPECT_EQ(primitive.material, 0);
  ASSERT_EQ(scene->materials.size(), 1u);
  ASSERT_EQ(scene->nodes.size(), 1u);

  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edgeUses;
  const auto soup = flattenTriangles(*scene);
  ASSERT_EQ(soup.indices.size(), primitive.indices.size());
  double sixVolume = 0.0;
  for (std::size_t t = 0; t < soup.indices.size(); t += 3) {
    const glm::dvec3 a = soup.positions[soup.indices[t]], b = soup.positions[soup.indices[t + 1]], c = soup.positions[soup.indices[t + 2]];
    sixVolume += glm::dot(a, glm::cross(b, c));
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t u = soup.indices[t + std::size_t(k)], v = soup.indices[t + std::size_t((k + 1) % 3)];
      ++edgeUses[{std::min(u, v), std::max(u, v)}];
    }
  }
  EXPECT_GT(sixVolume, 0.0);
  for (const auto& [edge, uses] : edgeUses) ASSERT_EQ(uses, 2) << "edge " << edge.first << "-" << edge.second;

  glm::dvec3 centroid(0.0);
  for (const auto& p : primitive.positions) centroid += glm::dvec3(p);
  centroid /= double(primitive.positions.size());
  double outwardness = 0.0;
  for (std::size_t v = 0; v < primitive.normals.size(); ++v) {
    EXPECT_NEAR(glm::length(primitive.normals[v]), 1.0f, 1e-4f);
    outwardness += glm::dot(glm::dvec3(primitive.normals[v]), glm::dvec3(primitive.positions[v]) - centroid);
  }
  EXPECT_GT(outwardness, 0.0);
}

// Tricky because the size limit must be enforced before reading the file or parsing the bytes.
TEST(GltfLoaderBunny, RefusesFilesOverTheSizeLimit) {
  expectError(loadGltf(kBunnyPath, GltfLoadOptions{1000}), "bunny.glb", {"over the 1000-byte limit"});
  const auto bytes = bunnyBytes();
  expectError(loadGltfFromMemory(bytes, "mem.glb", {}, GltfLoadOptions{1000}), "mem.glb", {"over the 1000-byte limit"});
}

// ------------------------------------------------------------------------------------------------
// Hand-written hierarchy (tests/data/gltf/hierarchy.gltf, external buffer triangle.bin)

// Tricky because it needs TRS composition in the order T*R*S with glTF's x,y,z,w quaternion, a
// column-major `matrix`, parent-before-child world products, a buffer resolved relative to the file
// (ctest runs elsewhere), and nodes outside the default scene dropped. The expected matrices are
// worked out by hand: parent = T(1,0,0) Rz(90) S(2); child adds T(0,1,0); grandchild adds T(0,0,3).
TEST(GltfLoaderHierarchy, WorldMatricesMatchHandComputedOnes) {
  const auto scene = loadGltf(kDataDir / "hierarchy.gltf");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->nodes.size(), 4u);  // not_in_scene is dropped
  const glm::mat4 parentWorld(glm::vec4(0, 2, 0, 0), glm::vec4(-2, 0, 0, 0), glm::vec4(0, 0, 2, 0), glm::vec4(1, 0, 0, 1));
  glm::mat4 childWorld = parentWorld;
  childWorld[3] = glm::vec4(-1, 0, 0, 1);
  glm::mat4 grandchildWorld = parentWorld;
  grandchildWorld[3] = glm::vec4(-1, 0, 6, 1);

  const auto& nodes = scene->nodes;
  EXPECT_EQ(nodes[0].name, "parent");
  EXPECT_EQ(nodes[0].parent, -1);
  expectMatrixNear(nodes[0].world, parentWorld);
  EXPECT_EQ(nodes[1].name, "child");
  EXPECT_EQ(nodes[1].parent, 0);
  expectMatrixNear(nodes[1].local, glm::mat4(glm::vec4(1, 0, 0, 0), glm::vec4(0, 1, 0, 0), glm::vec4(0, 0, 1, 0), glm::vec4(0, 1, 0, 1)));
  expectMatrixNear(nodes[1].world, childWorld);
  EXPECT_EQ(nodes[2].name, "grandchild");
  EXPECT_EQ(nodes[2].parent, 1);
  expectMatrixNear(nodes[2].world, grandchildWorld);
  EXPECT_EQ(nodes[3].name, "ortho_holder");
  EXPECT_EQ(nodes[3].parent, -1);
}

// The world matrix the entities compose (instantiateScene gives each node the Transform
// fromMatrix(local) and the hierarchy multiplies them): what the mesh method draws.
glm::mat4 entityWorld(const SceneData& scene, std::size_t n) {
  const NodeData& node = scene.nodes[n];
  const glm::mat4 local = toMatrix(fromMatrix(node.local));
  return node.parent < 0 ? local : entityWorld(scene, std::size_t(node.parent)) * local;
}

void expectMatrixRelativelyNear(const glm::mat4& actual, const glm::mat4& expected, float scale) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) EXPECT_NEAR(actual[c][r], expected[c][r], 1e-5f * scale) << "column " << c << " row " << r;
}

// Tricky because glTF forbids a `matrix` that shears or projects, yet exporters write them, and an
// entity's Transform can only hold translation, rotation and scale: the triangles were drawn by
// the matrix's TRS part while the SDF was baked from node.world with the shear (a box drawn upright
// by the mesh method, leaning by the SDF methods). Every node's world must be what the entities
// compose, under a sheared parent too; a valid matrix that mirrors and scales by 1e-3 on one axis
// (a decomposition with an absolute epsilon would lose it) is kept as written, without a warning.
TEST(GltfLoaderHierarchy, ANodeMatrixThatShearsOrProjectsIsDrawnAsItsTrsPart) {
  GltfBuilder b;
  const int mesh = b.addIndexedMesh(kTriangle, {0, 1, 2});
  const int child = b.addNode({{"name", "child"}, {"mesh", mesh}, {"translation", {0.0, 1.0, 0.0}}});
  const json shear = {1, 0, 0, 0, 0.8, 1, 0, 0, 0, 0, 1, 0, 2, 0, 0, 1};  // column-major: x += 0.8 y
  b.addNode({{"name", "sheared"}, {"mesh", mesh}, {"matrix", shear}, {"children", {child}}});
  const json projective = {1, 0, 0, 0.2, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  b.addNode({{"name", "projective"}, {"mesh", mesh}, {"matrix", projective}});
  // Rotated 90 degrees about z, scaled (-2, 3, 1e-3): columns (0, -2, 0), (-3, 0, 0), (0, 0, 1e-3).
  const json mirrored = {0, -2, 0, 0, -3, 0, 0, 0, 0, 0, 1e-3, 0, 5, 6, 7, 1};
  b.addNode({{"name", "mirrored"}, {"mesh", mesh}, {"matrix", mirrored}});
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->nodes.size(), 4u);

  for (std::size_t n = 0; n < scene->nodes.size(); ++n) {
    SCOPED_TRACE(scene->nodes[n].name);
    expectMatrixRelativelyNear(scene->nodes[n].world, entityWorld(*scene, n), 3.0f);
  }
  EXPECT_TRUE(anyWarningContains(*scene, "'sheared': its matrix shears or projects"));
  EXPECT_TRUE(anyWarningContains(*scene, "'projective': its matrix shears or projects"));
  EXPECT_FALSE(anyWarningContains(*scene, "'mirrored'"));
  EXPECT_FALSE(anyWarningContains(*scene, "'child'"));
  const NodeData& kept = scene->nodes[3];
  ASSERT_EQ(kept.name, "mirrored");
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) EXPECT_EQ(kept.local[c][r], float(mirrored[std::size_t(c * 4 + r)].get<double>()));
}

// Tricky because the file lists the orthographic camera first: both cameras must be kept in file
// order with the nodes' references intact, and each keeps only its own projection's fields (the
// orthographic one its magnifications and finite far plane, the perspective one its field of view).
TEST(GltfLoaderHierarchy, PerspectiveAndOrthographicCamerasKept) {
  const auto scene = loadGltf(kDataDir / "hierarchy.gltf");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->cameras.size(), 2u);
  const auto& ortho = scene->cameras[0];
  EXPECT_EQ(ortho.name, "ortho");
  EXPECT_TRUE(ortho.orthographic);
  EXPECT_FLOAT_EQ(ortho.xmag, 1.0f);
  EXPECT_FLOAT_EQ(ortho.ymag, 1.0f);
  EXPECT_FLOAT_EQ(ortho.znear, 0.1f);
  ASSERT_TRUE(ortho.zfar.has_value());
  EXPECT_FLOAT_EQ(*ortho.zfar, 10.0f);
  const auto& camera = scene->cameras[1];
  EXPECT_EQ(camera.name, "eye");
  EXPECT_FALSE(camera.orthographic);
  EXPECT_FLOAT_EQ(camera.yfov, 0.7f);
  EXPECT_FLOAT_EQ(camera.znear, 0.1f);
  ASSERT_TRUE(camera.zfar.has_value());
  EXPECT_FLOAT_EQ(*camera.zfar, 100.0f);
  ASSERT_TRUE(camera.aspectRatio.has_value());
  EXPECT_FLOAT_EQ(*camera.aspectRatio, 1.5f);
  EXPECT_EQ(scene->nodes[2].camera, 1);  // grandchild: file camera 1
  EXPECT_EQ(scene->nodes[3].camera, 0);  // ortho_holder: file camera 0
  EXPECT_FALSE(anyWarningContains(*scene, "camera")) << "a supported camera was warned about";
}

// Tricky because uint16 indices from an external file must be widened, the missing NORMAL must
// be generated (+Z for this CCW triangle), the material must be read, and flattening must apply
// each instance's world matrix (the mesh is used twice).
TEST(GltfLoaderHierarchy, MeshMaterialAndFlattenedInstances) {
  const auto scene = loadGltf(kDataDir / "hierarchy.gltf");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->materials.size(), 1u);
  EXPECT_FLOAT_EQ(scene->materials[0].baseColor.b, 0.6f);
  EXPECT_FLOAT_EQ(scene->materials[0].metallic, 0.25f);
  EXPECT_FLOAT_EQ(scene->materials[0].roughness, 0.75f);
  const auto& primitive = scene->meshes.at(0).primitives.at(0);
  EXPECT_EQ(primitive.indices, (std::vector<std::uint32_t>{0, 1, 2}));
  for (const auto& n : primitive.normals) expectNear(n, {0, 0, 1});

  const auto soup = flattenTriangles(*scene);
  ASSERT_EQ(soup.positions.size(), 6u);
  EXPECT_EQ(soup.indices, (std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5}));
  expectNear(soup.positions[0], {-1, 0, 0});
  expectNear(soup.positions[1], {-1, 2, 0});
  expectNear(soup.positions[2], {-3, 0, 0});
  expectNear(soup.positions[5], {-3, 0, 6});
  // Each triangle names the node whose instance it is (the capture's per-object quality reads it).
  ASSERT_EQ(soup.triangleNodes.size(), 2u);
  EXPECT_NE(soup.triangleNodes[0], soup.triangleNodes[1]);
  for (const std::uint32_t n : soup.triangleNodes) EXPECT_EQ(scene->nodes.at(n).mesh, 0);
  expectNear(glm::vec3(scene->nodes[soup.triangleNodes[1]].world * glm::vec4(primitive.positions[2], 1.0f)),
             soup.positions[5]);
}

// One primitive of the triangle at `positions` per material of the document, in order, in one
// mesh placed by one node.
void addPrimitivePerMaterial(GltfBuilder& b, int positions) {
  json primitives = json::array();
  for (std::size_t m = 0; m < b.doc()["materials"].size(); ++m)
    primitives.push_back({{"attributes", {{"POSITION", positions}}}, {"material", m}});
  b.doc()["meshes"] = json::array({json{{"primitives", primitives}}});
  b.addNode({{"mesh", 0}});
}

// Tricky because glTF's doubleSided defaults to false when absent (glTF 2.0, material.doubleSided)
// and is read per material: three materials, true, false and absent, on three primitives of one
// mesh, must come out in their own order; a reader that took the first material's flag for every
// one, or defaulted an absent one to true (Blender's export default), fails here.
TEST(GltfLoaderFeatures, DoubleSidedIsReadPerMaterialAndDefaultsToFalse) {
  GltfBuilder b;
  const int positions = b.addPositions(kTriangle);
  const int indices = b.addIndices({0, 1, 2});
  b.doc()["materials"] = json::array({json{{"doubleSided", true}, {"name", "leaf"}},
                                      json{{"doubleSided", false}, {"name", "bark"}},
                                      json{{"name", "stone"}}});
  json primitives = json::array();
  for (int m = 0; m < 3; ++m)
    primitives.push_back({{"attributes", {{"POSITION", positions}}}, {"indices", indices}, {"material", m}});
  b.doc()["meshes"] = json::array({json{{"primitives", primitives}}});
  b.addNode({{"mesh", 0}});
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->materials.size(), 3u);
  EXPECT_TRUE(scene->materials[0].doubleSided) << scene->materials[0].name;
  EXPECT_FALSE(scene->materials[1].doubleSided) << scene->materials[1].name;
  EXPECT_FALSE(scene->materials[2].doubleSided) << scene->materials[2].name << " (absent: the default)";
  EXPECT_FALSE(MaterialData{}.doubleSided) << "a primitive without a material is single-sided";
  ASSERT_EQ(scene->meshes.at(0).primitives.size(), 3u);
  for (int m = 0; m < 3; ++m) EXPECT_EQ(scene->meshes[0].primitives[std::size_t(m)].material, m);
}

// Tricky because these fields are core glTF, not extensions (whose notes the loader already
// gives), and each changes what a mesh looks like: a normal-mapped wall drawn flat. Each material
// that uses one gets a note naming its fields; a plain opaque material, and an OPAQUE one whose
// emissiveFactor is zero (what exporters write), get none. Emission, the base colour texture and
// MASK are drawn (since session 39), BLEND since session 40, the metallic-roughness, occlusion,
// emissive and normal textures since session 41: only an alphaMode glTF does not define is noted
// now, and a MASK or BLEND material, or one with those textures, gets no note.
TEST(GltfLoaderFeatures, MaterialFieldsTheRendererDoesNotDrawAreNamedInANote) {
  GltfBuilder b;
  const int positions = b.addPositions(kTriangle);
  b.doc()["textures"] = json::array({json{{"source", 0}}});
  b.doc()["images"] = json::array({json{{"uri", "data:image/png;base64,AAAA"}}});
  b.doc()["materials"] = json::array(
      {json{{"name", "glass"}, {"alphaMode", "BLEND"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 0.3}}}}},
       json{{"name", "leaf"}, {"alphaMode", "MASK"}, {"alphaCutoff", 0.25}, {"doubleSided", true}},
       json{{"name", "sign"}, {"emissiveFactor", {1.0, 0.5, 0.0}}, {"emissiveTexture", {{"index", 0}}}},
       json{{"name", "brick"},
            {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"metallicRoughnessTexture", {{"index", 0}}}}},
            {"normalTexture", {{"index", 0}}},
            {"occlusionTexture", {{"index", 0}}}},
       json{{"name", "stone"}, {"alphaMode", "OPAQUE"}, {"emissiveFactor", {0, 0, 0}}}});
  addPrimitivePerMaterial(b, positions);
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const std::string notes = warningLines(*scene);
  EXPECT_FALSE(anyWarningContains(*scene, "'glass'")) << notes;
  EXPECT_FALSE(anyWarningContains(*scene, "'leaf'")) << notes;
  EXPECT_FALSE(anyWarningContains(*scene, "'sign': emissiveTexture (drawn in emissiveFactor) ignored")) << notes;
  // Its textures' image does not decode: warnings name them, but no note calls them ignored.
  EXPECT_FALSE(anyWarningContains(*scene, "normalTexture ignored")) << notes;
  EXPECT_FALSE(anyWarningContains(*scene, "occlusionTexture ignored")) << notes;
  EXPECT_FALSE(anyWarningContains(*scene, "'stone'")) << notes;
  // What is read stays read: the glass's factor (its alpha too), the leaf's two sides.
  ASSERT_EQ(scene->materials.size(), 5u);
  EXPECT_FLOAT_EQ(scene->materials[0].baseColor.a, 0.3f);
  EXPECT_TRUE(scene->materials[1].doubleSided);
}

// Why: a glass pane, a tinted visor (alphaMode BLEND) is blended over what lies behind it by its
// alpha, the factor's times the base colour texture's (the renderer multiplies the texture's in:
// MeshMaterialTest.ABlendedCheckerQuadIsBlendedOverWhatLiesBehindIt). Tricky because only BLEND
// blends: OPAQUE (the default) ignores an alpha below 1, MASK cuts out instead, and an alphaMode
// glTF does not define is drawn opaque with a note; a BLEND material keeps its factor's alpha, no
// cutoff and gets no note.
TEST(GltfLoaderFeatures, ABlendMaterialIsBlendedWithItsAlpha) {
  GltfBuilder b;
  const int positions = b.addPositions(kTriangle);
  const json halfAlpha = {{"baseColorFactor", {0.2, 0.4, 0.6, 0.5}}};
  b.doc()["materials"] = json::array({json{{"name", "glass"}, {"alphaMode", "BLEND"}, {"pbrMetallicRoughness", halfAlpha}},
                                      json{{"name", "stone"}, {"pbrMetallicRoughness", halfAlpha}},
                                      json{{"name", "leaf"}, {"alphaMode", "MASK"}, {"pbrMetallicRoughness", halfAlpha}},
                                      json{{"name", "odd"}, {"alphaMode", "GLASS"}, {"pbrMetallicRoughness", halfAlpha}}});
  addPrimitivePerMaterial(b, positions);
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->materials.size(), 4u);
  const MaterialData& glass = scene->materials[0];
  EXPECT_TRUE(glass.alphaBlend);
  EXPECT_FLOAT_EQ(glass.baseColor.a, 0.5f);
  EXPECT_FALSE(glass.alphaCutoff.has_value()) << "BLEND is not cut out";
  EXPECT_FALSE(scene->materials[1].alphaBlend) << "OPAQUE (absent) ignores the alpha";
  EXPECT_FALSE(scene->materials[2].alphaBlend) << "MASK cuts out, it does not blend";
  EXPECT_FALSE(scene->materials[3].alphaBlend) << "an alphaMode glTF does not define is drawn opaque";
  EXPECT_FALSE(MaterialData{}.alphaBlend) << "a primitive without a material is opaque";
  std::string notes;
  for (const auto& w : scene->warnings) notes += w + "\n";
  EXPECT_FALSE(anyWarningContains(*scene, "'glass'")) << notes;
  EXPECT_TRUE(anyWarningContains(*scene, "material 3 'odd': alphaMode 'GLASS', which glTF does not define (drawn opaque) "
                                         "ignored"))
      << notes;
}

// Why: a leaf card or a fence (alphaMode MASK) is cut out where its alpha is below alphaCutoff.
// Tricky because the cutoff is read only for MASK (glTF: "ignored for other modes", so a BLEND or
// OPAQUE material with a cutoff stays uncut), defaults to 0.5 when absent, and a negative one or
// one of another JSON type is refused naming the field (tinygltf would read a string as 0: nothing
// cut out, unsaid).
TEST(GltfLoaderFeatures, AMaskMaterialKeepsItsCutoffAndOnlyIt) {
  GltfBuilder b;
  const int positions = b.addPositions(kTriangle);
  b.doc()["materials"] = json::array({json{{"name", "leaf"}, {"alphaMode", "MASK"}, {"alphaCutoff", 0.25}},
                                      json{{"name", "fence"}, {"alphaMode", "MASK"}},
                                      json{{"name", "glass"}, {"alphaMode", "BLEND"}, {"alphaCutoff", 0.7}},
                                      json{{"name", "stone"}, {"alphaCutoff", 0.7}}});
  addPrimitivePerMaterial(b, positions);
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->materials.size(), 4u);
  ASSERT_TRUE(scene->materials[0].alphaCutoff.has_value());
  EXPECT_FLOAT_EQ(*scene->materials[0].alphaCutoff, 0.25f);
  ASSERT_TRUE(scene->materials[1].alphaCutoff.has_value());
  EXPECT_FLOAT_EQ(*scene->materials[1].alphaCutoff, 0.5f);
  EXPECT_FALSE(scene->materials[2].alphaCutoff.has_value()) << "BLEND is not cut out";
  EXPECT_FALSE(scene->materials[3].alphaCutoff.has_value()) << "OPAQUE is not cut out";

  for (const json& bad : {json(-0.1), json("0.5")}) {
    b.doc()["materials"][0]["alphaCutoff"] = bad;
    const auto refused = load(b);
    ASSERT_FALSE(refused.ok()) << bad.dump();
    EXPECT_NE(refused.error().message.find("alphaCutoff"), std::string::npos) << refused.error().message;
  }
}

// Why: an emissive sign, a lamp. Tricky because the brightness comes from two places: the core
// emissiveFactor (at most 1) and KHR_materials_emissive_strength, which multiplies it (a lamp's 40);
// the product is what is drawn, the extension is read (no 'ignored' note for it) and a material
// without either gives no light.
TEST(GltfLoaderFeatures, EmissionIsTheFactorTimesTheStrength) {
  GltfBuilder b;
  const int positions = b.addPositions(kTriangle);
  b.doc()["extensionsUsed"] = json::array({"KHR_materials_emissive_strength"});
  b.doc()["materials"] = json::array(
      {json{{"name", "sign"}, {"emissiveFactor", {1.0, 0.5, 0.0}}},
       json{{"name", "lamp"},
            {"emissiveFactor", {0.5, 0.25, 1.0}},
            {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 40.0}}}}}},
       json{{"name", "stone"}}});
  addPrimitivePerMaterial(b, positions);
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->materials.size(), 3u);
  EXPECT_EQ(scene->materials[0].emissive, glm::vec3(1.0f, 0.5f, 0.0f));
  EXPECT_EQ(scene->materials[1].emissive, glm::vec3(20.0f, 10.0f, 40.0f));
  EXPECT_EQ(scene->materials[2].emissive, glm::vec3(0.0f));
  for (const auto& w : scene->warnings) {
    EXPECT_EQ(w.find("KHR_materials_emissive_strength"), std::string::npos) << w;
    EXPECT_EQ(w.find("emission"), std::string::npos) << w;
  }
}

// ------------------------------------------------------------------------------------------------
// Base colour textures

// A PNG of `rgba` (width x height), as a file would hold it.
std::vector<std::uint8_t> pngOf(const std::vector<std::uint8_t>& rgba, std::uint32_t width, std::uint32_t height) {
  const hsdftest::ScopedTempPath file("texture.png");
  EXPECT_TRUE(writePng(file.path(), rgba, width, height, 4).ok());
  auto bytes = readBinaryFile(file.path());
  EXPECT_TRUE(bytes.ok());
  return bytes.ok() ? *bytes : std::vector<std::uint8_t>{};
}

// 3 x 2 texels, each its own colour and alpha (not a power of two: glTF allows any size).
const std::vector<std::uint8_t> kTexels = {255, 0,   0,   255, 0,  255, 0,  200, 0,   0,   255, 100,
                                           255, 255, 255, 255, 10, 20,  30, 40,  200, 150, 100, 0};

// A triangle with TEXCOORD_0 and `materials`, one primitive each, all placed by one node.
void addTexturedPrimitives(GltfBuilder& b, int materials, const std::vector<float>& texcoords) {
  const int positions = b.addPositions(kTriangle);
  const int uv = b.addTightAccessor(texcoords, kFloat, "VEC2", 3);
  json primitives = json::array();
  for (int m = 0; m < materials; ++m)
    primitives.push_back({{"attributes", {{"POSITION", positions}, {"TEXCOORD_0", uv}}}, {"material", m}});
  b.doc()["meshes"] = json::array({json{{"primitives", primitives}}});
  b.addNode({{"mesh", 0}});
}

json texturedMaterial(const std::string& name, int texture, int texCoord = 0) {
  return {{"name", name}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", texture}, {"texCoord", texCoord}}}}}};
}

// Why: most normal-mapped files carry no TANGENT (DamagedHelmet among them); glTF asks clients to
// make them. Only where a normal texture reads them, only with the file's normals (flat normals
// keep each face's exact frame), and in the texture's frame after KHR_texture_transform: a
// texture scaled by -1 in u mirrors the tangent.
TEST(GltfLoaderTextures, ANormalTextureWithoutTangentsGetsGeneratedOnes) {
  const auto loadWith = [](bool normals, const json& normalTexture) {
    GltfBuilder b;
    addTexturedPrimitives(b, 2, {0, 0, 1, 0, 0, 1});
    if (normals)
      for (auto& primitive : b.doc()["meshes"][0]["primitives"])
        primitive["attributes"]["NORMAL"] = b.addTightAccessor(std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1}, kFloat, "VEC3", 3);
    b.doc()["extensionsUsed"] = json::array({"KHR_texture_transform"});
    b.doc()["images"] = json::array({json{{"uri", "data:image/png;base64," + base64(pngOf(kTexels, 3, 2))}}});
    b.doc()["textures"] = json::array({json{{"source", 0}}});
    b.doc()["materials"] = json::array({json{{"name", "bumpy"}, {"normalTexture", normalTexture}}, texturedMaterial("plain", 0)});
    return load(b);
  };
  const auto scene = loadWith(true, {{"index", 0}});
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const auto& bumpy = scene->meshes[0].primitives[0];
  ASSERT_EQ(bumpy.tangents.size(), 3u) << warningLines(*scene);
  for (const glm::vec4& t : bumpy.tangents) EXPECT_EQ(t, glm::vec4(1, 0, 0, -1)) << "+u along +x, -v along -y";
  EXPECT_TRUE(scene->meshes[0].primitives[1].tangents.empty()) << "no normal texture reads them";

  const json mirrored = {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"scale", {-1.0, 1.0}}}}}}};
  const auto flipped = loadWith(true, mirrored);
  ASSERT_TRUE(flipped.ok()) << flipped.error().message;
  ASSERT_EQ(flipped->meshes[0].primitives[0].tangents.size(), 3u) << warningLines(*flipped);
  EXPECT_EQ(flipped->meshes[0].primitives[0].tangents[0], glm::vec4(-1, 0, 0, 1));

  const auto flat = loadWith(false, {{"index", 0}});
  ASSERT_TRUE(flat.ok()) << flat.error().message;
  EXPECT_TRUE(flat->meshes[0].primitives[0].tangents.empty()) << "flat normals keep the derivative frame";
}

// Why: a textured mesh (most glTF scenes) must reach the renderer with its texels, its sampler and
// its texture coordinates. Tricky because glTF stores an image three ways -- in a bufferView (every
// .glb), as a data: URI, as a file beside the .gltf -- which tinygltf is never shown (the sanitiser
// removes images), and the sampler's enums map to filters, mipmaps and wraps. Each way must give
// the same texels as the PNG written; one glTF texture used by two materials is decoded once.
TEST(GltfLoaderTextures, BaseColorTexturesAreDecodedFromEveryImageSourceWithTheirSampler) {
  const std::vector<std::uint8_t> png = pngOf(kTexels, 3, 2);
  const hsdftest::ScopedTempPath folder("gltf_textures");
  std::filesystem::create_directories(folder.path());
  ASSERT_TRUE(writeBinaryFile(folder.path() / "checker.png", png).ok());
  GltfBuilder b;
  const std::vector<float> uv = {0.0f, 1.0f, 1.0f, 1.0f, 0.0f, 0.0f};
  addTexturedPrimitives(b, 4, uv);
  const int view = b.addView(b.addData(png), png.size());
  b.doc()["images"] = json::array({json{{"bufferView", view}, {"mimeType", "image/png"}, {"name", "in the buffer"}},
                                   json{{"uri", "data:image/png;base64," + base64(png)}},
                                   json{{"uri", "checker.png"}}});
  b.doc()["samplers"] = json::array({json{{"magFilter", 9728}, {"minFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33648}},
                                     json{{"minFilter", 9985}}});
  b.doc()["textures"] = json::array({json{{"source", 0}, {"sampler", 0}}, json{{"source", 1}, {"sampler", 1}},
                                     json{{"source", 2}}});
  b.doc()["materials"] = json::array({texturedMaterial("buffer", 0), texturedMaterial("data", 1),
                                      texturedMaterial("file", 2), texturedMaterial("file again", 2)});
  ASSERT_TRUE(writeBinaryFile(folder.path() / "scene.gltf", b.bytes()).ok());
  const auto scene = loadGltf(folder.path() / "scene.gltf");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  for (const auto& w : scene->warnings) ADD_FAILURE() << "unexpected warning: " << w;
  ASSERT_EQ(scene->textures.size(), 3u) << "texture 2 decoded once for its two materials";
  for (std::size_t t = 0; t < 3; ++t) {
    SCOPED_TRACE(t);
    EXPECT_EQ(scene->textures[t].width, 3u);
    EXPECT_EQ(scene->textures[t].height, 2u);
    EXPECT_EQ(scene->textures[t].rgba, kTexels);
  }
  EXPECT_EQ(scene->textures[0].name, "in the buffer");
  EXPECT_EQ(scene->textures[1].name, "image 1");
  const TextureData& nearest = scene->textures[0];
  EXPECT_EQ(nearest.magFilter, TextureFilter::Nearest);
  EXPECT_EQ(nearest.minFilter, TextureFilter::Nearest);
  EXPECT_FALSE(nearest.mipmaps);
  EXPECT_EQ(nearest.wrapS, TextureWrap::ClampToEdge);
  EXPECT_EQ(nearest.wrapT, TextureWrap::MirroredRepeat);
  const TextureData& mipmapped = scene->textures[1];  // LINEAR_MIPMAP_NEAREST, no magFilter
  EXPECT_EQ(mipmapped.magFilter, TextureFilter::Linear);
  EXPECT_EQ(mipmapped.minFilter, TextureFilter::Linear);
  EXPECT_TRUE(mipmapped.mipmaps);
  EXPECT_EQ(mipmapped.mipmapFilter, TextureFilter::Nearest);
  EXPECT_EQ(mipmapped.wrapS, TextureWrap::Repeat);
  ASSERT_EQ(scene->materials.size(), 4u);
  EXPECT_EQ(scene->materials[0].baseColorTexture, 0);
  EXPECT_EQ(scene->materials[1].baseColorTexture, 1);
  EXPECT_EQ(scene->materials[2].baseColorTexture, 2);
  EXPECT_EQ(scene->materials[3].baseColorTexture, 2);
  const auto& texcoords = scene->meshes.at(0).primitives.at(0).texcoords;
  ASSERT_EQ(texcoords.size(), 3u);
  EXPECT_EQ(texcoords[1], glm::vec2(1.0f, 1.0f));
  EXPECT_EQ(texcoords[2], glm::vec2(0.0f, 0.0f));
}

// Why: KHR_texture_transform places a texture on a mesh by offset, rotation and scale (an atlas
// region, a tiled floor; gltfpack writes one to undo its quantization of texture coordinates);
// ignored, the texture is drawn stretched or shifted. Tricky because
// the README's GLSL rotates the wrong way for glTF's downward v (KhronosGroup/glTF#1563): the
// README's own example, "only the lower left quadrant of the source image, rotated clockwise 90
// degrees" (offset (0, 1), rotation pi/2, scale 0.5), is the reference here, computed by hand; and
// the extension's texCoord overrides the textureInfo's, as the exporters' fallback layout relies on.
TEST(GltfLoaderTextures, KhrTextureTransformMovesTheTexcoordsWhereTheTextureIsRead) {
  GltfBuilder b;
  addTexturedPrimitives(b, 6, {0, 0, 1, 0, 0, 1});
  b.doc()["extensionsUsed"] = json::array({"KHR_texture_transform"});
  b.doc()["images"] = json::array({json{{"uri", "data:image/png;base64," + base64(pngOf(kTexels, 3, 2))}}});
  b.doc()["textures"] = json::array({json{{"source", 0}}});
  const auto transformed = [](const std::string& name, const json& extension, int texCoord = 0) {
    json material = texturedMaterial(name, 0, texCoord);
    material["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {{"KHR_texture_transform", extension}};
    return material;
  };
  b.doc()["materials"] = json::array(
      {transformed("quadrant", {{"offset", {0, 1}}, {"rotation", 1.57079632679}, {"scale", {0.5, 0.5}}}),
       transformed("fallback layout", {{"offset", {0.25, -0.5}}, {"scale", {2, 3}}, {"texCoord", 0}}, 1),
       texturedMaterial("plain", 0), transformed("second set", {{"texCoord", 1}}),
       transformed("bad rotation", {{"rotation", "half"}}), transformed("bad scale", {{"scale", {1}}})});
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const std::string notes = warningLines(*scene);
  for (const auto& unsaid : {"extension KHR_texture_transform", "'quadrant'", "'fallback layout'"})
    EXPECT_FALSE(anyWarningContains(*scene, unsaid)) << unsaid << "\nin:\n" << notes;
  for (const auto& fragment :
       {"material 3 'second set': baseColorTexture: texCoord 1 is not read (only TEXCOORD_0)",
        "material 4 'bad rotation': baseColorTexture: KHR_texture_transform rotation is not a finite number",
        "material 5 'bad scale': baseColorTexture: KHR_texture_transform scale is not two finite numbers"})
    EXPECT_TRUE(anyWarningContains(*scene, fragment)) << fragment << "\nin:\n" << notes;

  const auto& primitives = scene->meshes.at(0).primitives;
  ASSERT_EQ(primitives.size(), 6u);
  const auto expectTexcoords = [&](std::size_t p, const std::vector<glm::vec2>& expected) {
    SCOPED_TRACE(scene->materials.at(std::size_t(primitives[p].material)).name);
    ASSERT_EQ(primitives[p].texcoords.size(), expected.size());
    for (std::size_t v = 0; v < expected.size(); ++v) expectNear(primitives[p].texcoords[v], expected[v], 1e-6f);
  };
  // (0, 0) -> the image's bottom-left corner; u runs up the quadrant's left edge, v along its bottom.
  expectTexcoords(0, {{0.0f, 1.0f}, {0.0f, 0.5f}, {0.5f, 1.0f}});
  expectTexcoords(1, {{0.25f, -0.5f}, {2.25f, -0.5f}, {0.25f, 2.5f}});
  expectTexcoords(2, {{0.0f, 0.0f}, {1.0f, 0.0f}, {0.0f, 1.0f}});
  for (std::size_t m = 0; m < 3; ++m) EXPECT_EQ(scene->materials[m].baseColorTexture, 0) << m;
  for (std::size_t m = 3; m < 6; ++m) EXPECT_EQ(scene->materials[m].baseColorTexture, -1) << m;
}

// Why: a broken texture must not cost the scene: the material is drawn in its factor, with a
// warning that names the material and what is wrong, never a crash. Tricky because each fault sits
// at a different step (the texture, sampler and image indices, an image only in an extension such
// as KTX2, the bytes, the decoder, the size limit, the texture coordinates), and a file beside a
// .gltf loaded from memory must stay refused.
TEST(GltfLoaderTextures, BrokenTexturesAreNamedAndTheMaterialDrawnInItsFactor) {
  GltfBuilder b;
  addTexturedPrimitives(b, 8, {0, 0, 1, 0, 0, 1});
  const std::vector<std::uint8_t> huge = pngOf(std::vector<std::uint8_t>(std::size_t(8193) * 4, 255), 8193, 1);
  b.doc()["images"] = json::array({json{{"uri", "data:image/png;base64," + base64({1, 2, 3, 4, 5, 6, 7, 8})}},
                                   json{{"uri", "beside.png"}}, json{{"uri", "data:image/png;base64," + base64(huge)}},
                                   json{{"uri", "data:image/png;base64," + base64(pngOf(kTexels, 3, 2))}}});
  b.doc()["textures"] = json::array({json{{"source", 0}}, json{{"source", 1}}, json{{"source", 2}},
                                     json{{"source", 3}, {"sampler", 5}}, json{{"source", 9}}, json{{"source", 3}},
                                     json{{"extensions", {{"KHR_texture_basisu", {{"source", 1}}}}}}});
  b.doc()["materials"] = json::array({texturedMaterial("garbage", 0), texturedMaterial("missing file", 1),
                                      texturedMaterial("huge", 2), texturedMaterial("bad sampler", 3),
                                      texturedMaterial("bad image", 4), texturedMaterial("bad texture", 12),
                                      texturedMaterial("second uv set", 5, 1), texturedMaterial("ktx2", 6)});
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const std::string notes = warningLines(*scene);
  const std::vector<std::string> expected = {
      "material 0 'garbage': baseColorTexture: texture 0: image 0 'image 0': cannot decode image",
      "material 1 'missing file': baseColorTexture: texture 1: image 1 'image 1': external file 'beside.png' not allowed",
      "material 2 'huge': baseColorTexture: texture 2: image 2 'image 2': image is 8193x1, over the limit of 8192 texels a side",
      "material 3 'bad sampler': baseColorTexture: texture 3: sampler 5 out of range (file has 0)",
      "material 4 'bad image': baseColorTexture: texture 4: image 9 out of range (file has 4)",
      "material 5 'bad texture': baseColorTexture: texture 12 out of range (file has 7)",
      "material 6 'second uv set': baseColorTexture: texCoord 1 is not read (only TEXCOORD_0); drawn in baseColorFactor",
      "material 7 'ktx2': baseColorTexture: texture 6: its image is only in KHR_texture_basisu, which is not decoded",
  };
  for (const auto& fragment : expected) EXPECT_TRUE(anyWarningContains(*scene, fragment)) << fragment << "\nin:\n" << notes;
  for (const auto& material : scene->materials) EXPECT_EQ(material.baseColorTexture, -1) << material.name;
  EXPECT_TRUE(scene->textures.empty());

  // A textured material on a primitive without TEXCOORD_0: said, drawn in the factor.
  GltfBuilder noUv;
  noUv.doc()["images"] = json::array({json{{"uri", "data:image/png;base64," + base64(pngOf(kTexels, 3, 2))}}});
  noUv.doc()["textures"] = json::array({json{{"source", 0}}});
  noUv.doc()["materials"] = json::array({texturedMaterial("leaf", 0)});
  const int positions = noUv.addPositions(kTriangle);
  noUv.doc()["meshes"] = json::array({json{{"name", "card"}, {"primitives", json::array({json{{"attributes", {{"POSITION", positions}}}, {"material", 0}}})}}});
  noUv.addNode({{"mesh", 0}});
  const auto untextured = load(noUv);
  ASSERT_TRUE(untextured.ok()) << untextured.error().message;
  EXPECT_TRUE(anyWarningContains(*untextured, "mesh 0 'card' primitive 0: material 0 'leaf' has a baseColorTexture but "
                                              "the primitive no TEXCOORD_0; drawn in its factors"));
}

// Why: almost every real glTF material (DamagedHelmet, Sponza, ...) has a metallic-roughness, an
// occlusion, an emissive and a normal texture beside its base colour; each must reach the renderer
// with its index, the occlusion its strength and the normal its scale. Tricky because tinygltf keeps each kind in a type of its
// own (the occlusion's strength, the emissive one outside pbrMetallicRoughness), one glTF texture
// may serve two kinds (decoded once), only TEXCOORD_0 is read (another set is a warning naming the
// material and the kind), and the material's texture coordinates go through one
// KHR_texture_transform: a texture with another one is refused with a warning, not drawn shifted.
TEST(GltfLoaderTextures, MaterialTexturesKeepTheirIndicesStrengthAndCoordinates) {
  GltfBuilder b;
  addTexturedPrimitives(b, 3, {0, 0, 1, 0, 0, 1});
  b.doc()["extensionsUsed"] = json::array({"KHR_texture_transform"});
  b.doc()["images"] = json::array({json{{"uri", "data:image/png;base64," + base64(pngOf(kTexels, 3, 2))}}});
  b.doc()["textures"] = json::array({json{{"source", 0}}, json{{"source", 0}}});
  const json half = {{"KHR_texture_transform", {{"scale", {0.5, 0.5}}}}};
  const json shifted = {{"KHR_texture_transform", {{"offset", {0.5, 0.0}}}}};
  b.doc()["materials"] = json::array(
      {json{{"name", "all"},
            {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"metallicRoughnessTexture", {{"index", 1}}},
                                      {"metallicFactor", 0.3}, {"roughnessFactor", 0.7}}},
            {"occlusionTexture", {{"index", 1}, {"strength", 0.25}}},
            {"emissiveTexture", {{"index", 0}}},
            {"emissiveFactor", {1.0, 0.5, 0.25}},
            {"normalTexture", {{"index", 0}, {"scale", 0.5}}}},
       json{{"name", "second set"},
            {"pbrMetallicRoughness", {{"metallicRoughnessTexture", {{"index", 0}, {"texCoord", 2}}}}},
            {"occlusionTexture", {{"index", 0}, {"texCoord", 1}}},
            {"emissiveTexture", {{"index", 1}, {"texCoord", 1}}},
            {"normalTexture", {{"index", 0}, {"texCoord", 1}}}},
       json{{"name", "transforms"},
            {"pbrMetallicRoughness", {{"metallicRoughnessTexture", {{"index", 0}, {"extensions", half}}}}},
            {"emissiveTexture", {{"index", 0}, {"extensions", half}}},
            {"occlusionTexture", {{"index", 1}, {"extensions", shifted}}}}});
  // "transforms": its first texture (metallic-roughness) sets the transform of its TEXCOORD_0; the
  // emissive one has the same, the occlusion one another.
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const std::string notes = warningLines(*scene);
  ASSERT_EQ(scene->textures.size(), 2u) << "each glTF texture decoded once, whatever kinds use it";
  ASSERT_EQ(scene->materials.size(), 3u);
  const MaterialData& all = scene->materials[0];
  EXPECT_EQ(all.baseColorTexture, 0);
  EXPECT_EQ(all.metallicRoughnessTexture, 1);
  EXPECT_EQ(all.occlusionTexture, 1);
  EXPECT_EQ(all.emissiveTexture, 0);
  EXPECT_FLOAT_EQ(all.occlusionStrength, 0.25f);
  EXPECT_EQ(all.normalTexture, 0);
  EXPECT_FLOAT_EQ(all.normalScale, 0.5f);
  EXPECT_FLOAT_EQ(all.roughness, 0.7f);
  EXPECT_FLOAT_EQ(all.metallic, 0.3f);
  EXPECT_EQ(all.emissive, glm::vec3(1.0f, 0.5f, 0.25f));
  EXPECT_FLOAT_EQ(scene->materials[1].occlusionStrength, 1.0f) << "glTF's default strength";
  EXPECT_FLOAT_EQ(scene->materials[1].normalScale, 1.0f) << "glTF's default scale";
  EXPECT_EQ(scene->materials[1].normalTexture, -1);
  for (const auto& kind : {"metallicRoughnessTexture", "occlusionTexture", "emissiveTexture", "normalTexture"}) {
    EXPECT_FALSE(anyWarningContains(*scene, std::string("'all': ") + kind)) << kind << "\nin:\n" << notes;
  }
  EXPECT_EQ(scene->materials[1].metallicRoughnessTexture, -1);
  EXPECT_EQ(scene->materials[1].occlusionTexture, -1);
  EXPECT_EQ(scene->materials[1].emissiveTexture, -1);
  const MaterialData& transforms = scene->materials[2];
  EXPECT_EQ(transforms.metallicRoughnessTexture, 0);
  EXPECT_EQ(transforms.emissiveTexture, 0);
  EXPECT_EQ(transforms.occlusionTexture, -1);
  for (const auto& fragment :
       {"material 1 'second set': normalTexture: texCoord 1 is not read (only TEXCOORD_0); drawn with its vertex normals",
        "material 1 'second set': metallicRoughnessTexture: texCoord 2 is not read (only TEXCOORD_0); drawn in "
        "metallicFactor and roughnessFactor",
        "material 1 'second set': occlusionTexture: texCoord 1 is not read (only TEXCOORD_0); drawn without occlusion",
        "material 1 'second set': emissiveTexture: texCoord 1 is not read (only TEXCOORD_0); drawn in emissiveFactor",
        "material 2 'transforms': occlusionTexture: its KHR_texture_transform differs from the material's first texture's"})
    EXPECT_TRUE(anyWarningContains(*scene, fragment)) << fragment << "\nin:\n" << notes;
  const auto& texcoords = scene->meshes.at(0).primitives.at(2).texcoords;
  ASSERT_EQ(texcoords.size(), 3u);
  EXPECT_EQ(texcoords[1], glm::vec2(0.5f, 0.0f)) << "the first texture's transform, once";
}

// Tricky because a mesh placed a million units from the origin, where float holds only 0.0625,
// loses its shape when its world positions are rounded to float; flattened about an origin near
// it (the scene runner bakes far scenes about their centre), each position is computed in double
// and rounded only once it is small again.
TEST(GltfLoaderHierarchy, FlattenedAboutAnOriginKeepsAFarMeshExact) {
  SceneData scene;
  MeshPrimitiveData primitive;
  primitive.positions = {{0.1f, 0.2f, 0.3f}, {0.7f, 0.2f, 0.3f}, {0.1f, 0.9f, 0.35f}};
  primitive.indices = {0, 1, 2};
  scene.meshes.push_back({"tri", {primitive}});
  NodeData node;
  node.mesh = 0;
  node.world = glm::translate(glm::mat4(1.0f), glm::vec3(1048576.0f, -1048576.0f, 524288.0f));
  scene.nodes.push_back(node);
  const auto about = flattenTriangles(scene, glm::dvec3(1048576.0, -1048576.0, 524288.0));
  const auto plain = flattenTriangles(scene);
  ASSERT_EQ(about.positions.size(), 3u);
  float plainError = 0.0f;
  for (std::size_t i = 0; i < 3; ++i) {
    expectNear(about.positions[i], primitive.positions[i], 1e-7f);
    plainError = std::max(plainError, glm::length(plain.positions[i] - glm::vec3(1048576.0f, -1048576.0f, 524288.0f) -
                                                  primitive.positions[i]));
  }
  EXPECT_GT(plainError, 0.01f) << "the case does not need the origin";
}

// ------------------------------------------------------------------------------------------------
// Features, built in memory

// Tricky because tinygltf parses extras into its own value type: the node's extras must come back as
// the same JSON (nested objects, strings, numbers, booleans), and a node without extras as none.
TEST(GltfLoaderFeatures, NodeExtrasKeptAsJson) {
  GltfBuilder b = triangleScene();
  const json extras = {{"hermite_sdf", {{"draw", "triangles"}}}, {"count", 3}, {"flag", true}, {"list", {1.5, "x"}}};
  b.doc()["nodes"][0]["extras"] = extras;
  b.addNode({{"mesh", 0}});
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->nodes.size(), 2u);
  EXPECT_EQ(json::parse(scene->nodes[0].extras), extras);
  EXPECT_TRUE(scene->nodes[1].extras.empty());
}

// A triangle with +Z normals and two morph targets: target 0 lifts every vertex by (0, 0, 1) and
// tilts the normals by (1, 0, 0); target 1 is sparse without a bufferView (zeros plus (2, 0, 0) at
// vertex 1), as exporters write a shape key that moves few vertices.
GltfBuilder morphScene(const json& meshWeights) {
  GltfBuilder b;
  const int positions = b.addPositions(kTriangle);
  const int normals = b.addPositions({{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
  const int lift = b.addPositions({{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
  const int tilt = b.addPositions({{1, 0, 0}, {1, 0, 0}, {1, 0, 0}});
  const std::vector<std::uint32_t> sparseIndex = {1};
  const int indexView = b.addView(b.addData(sparseIndex), 4);
  const std::vector<float> sparseValue = {2, 0, 0};
  const int valueView = b.addView(b.addData(sparseValue), 12);
  const int moved = int(b.doc()["accessors"].size());
  b.doc()["accessors"].push_back({{"componentType", kFloat}, {"count", 3}, {"type", "VEC3"},
                                  {"sparse", {{"count", 1},
                                              {"indices", {{"bufferView", indexView}, {"componentType", kUnsignedInt}}},
                                              {"values", {{"bufferView", valueView}}}}}});
  const json primitive = {{"attributes", {{"POSITION", positions}, {"NORMAL", normals}}},
                          {"targets", json::array({json{{"POSITION", lift}, {"NORMAL", tilt}}, json{{"POSITION", moved}}})}};
  json mesh = {{"primitives", json::array({primitive})}};
  if (!meshWeights.is_null()) mesh["weights"] = meshWeights;
  b.doc()["meshes"] = json::array({mesh});
  b.addNode({{"name", "shape"}, {"mesh", 0}});
  return b;
}

// Tricky because glTF defines a morphed mesh's shape without animation as the base plus the
// targets weighted by the mesh's default `weights`: a shape key an artist left at 0.5 was dropped,
// so the mesh method and the SDF drew the base shape. Each weight must scale its own target (a
// swapped weight moves vertex 1 by 1.0 in x instead of 0.5), a sparse target must add only its
// vertex, normals must take the NORMAL offsets and be normalized again, and targets without weights
// are the base shape. A weight count that is not the target count is an error naming both.
TEST(GltfLoaderFeatures, MorphTargetsTakeTheMeshsDefaultWeights) {
  GltfBuilder weighted = morphScene({0.5, 0.25});
  const auto scene = load(weighted);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const auto& primitive = scene->meshes.at(0).primitives.at(0);
  expectNear(primitive.positions[0], {0, 0, 0.5f});
  expectNear(primitive.positions[1], {1.5f, 0, 0.5f});
  expectNear(primitive.positions[2], {0, 1, 0.5f});
  for (const auto& n : primitive.normals) expectNear(n, glm::normalize(glm::vec3(0.5f, 0, 1)));
  const auto soup = flattenTriangles(*scene);
  ASSERT_EQ(soup.positions.size(), 3u);
  expectNear(soup.positions[1], {1.5f, 0, 0.5f});

  GltfBuilder unweighted = morphScene(nullptr);
  const auto base = load(unweighted);
  ASSERT_TRUE(base.ok()) << base.error().message;
  for (std::size_t v = 0; v < 3; ++v) expectNear(base->meshes[0].primitives[0].positions[v], kTriangle[v], 0.0f);

  GltfBuilder miscounted = morphScene({0.5, 0.25, 1.0});
  expectError(load(miscounted), "case.gltf", {"mesh 0", "the mesh has 3 morph weights for 2 morph targets"});
}

// Tricky because what the importer does not apply must be said, naming the node: a node's own
// morph weights (the mesh's are applied to every node that places it) and a skin (the mesh stays in
// the pose its vertices are written in). A node repeating its mesh's weights is not warned about.
TEST(GltfLoaderFeatures, NodeMorphWeightsAndSkinsAreNamedWhenIgnored) {
  GltfBuilder b = morphScene({0.5, 0.25});
  b.addNode({{"name", "own_weights"}, {"mesh", 0}, {"weights", {1.0, 0.0}}});
  b.addNode({{"name", "same_weights"}, {"mesh", 0}, {"weights", {0.5, 0.25}}});
  const int joint = b.addNode({{"name", "joint"}});
  b.addNode({{"name", "skinned"}, {"mesh", 0}, {"skin", 0}});
  b.doc()["skins"] = json::array({{{"joints", {joint}}}});
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_TRUE(anyWarningContains(*scene, "'own_weights': its own morph weights are not applied"));
  EXPECT_FALSE(anyWarningContains(*scene, "'same_weights'"));
  EXPECT_FALSE(anyWarningContains(*scene, "'shape'"));
  EXPECT_TRUE(anyWarningContains(*scene, "'skinned': skin 0 ignored"));
}

std::string allWarnings(const SceneData& scene) {
  std::string all;
  for (const std::string& warning : scene.warnings) all += warning + " | ";
  return all;
}

// A file with a root, and a child "spinner" whose one animation (two channels, rotation and
// translation) the tests below read or break one field at a time.
struct AnimatedFile {
  GltfBuilder b;
  int spinner = -1;
  int times = -1;
  int turns = -1;
  json& sampler(std::size_t s) { return b.doc()["animations"][0]["samplers"][s]; }
  json& channel(std::size_t c) { return b.doc()["animations"][0]["channels"][c]; }
  AnimatedFile() {
    const int mesh = b.addIndexedMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2});
    spinner = b.addNode({{"name", "spinner"}, {"mesh", mesh}});
    b.addNode({{"name", "root"}, {"children", {spinner}}});
    b.doc()["scenes"] = json::array({{{"nodes", {1}}}});
    times = b.addTightAccessor(std::vector<float>{0.0f, 1.0f}, kFloat, "SCALAR", 2);
    b.doc()["accessors"][std::size_t(times)]["min"] = {0.0};
    b.doc()["accessors"][std::size_t(times)]["max"] = {1.0};
    turns = b.addTightAccessor(std::vector<float>{0, 0, 0, 1, 0, 0.7071068f, 0, 0.7071068f}, kFloat, "VEC4", 2);
    const int moveTimes = b.addTightAccessor(std::vector<float>{0.0f, 1.0f}, kFloat, "SCALAR", 2);
    const int moves = b.addTightAccessor(std::vector<float>{0, 0, 0, 2, 4, 6}, kFloat, "VEC3", 2);
    const json turn = {{"input", times}, {"output", turns}};
    const json move = {{"input", moveTimes}, {"output", moves}, {"interpolation", "STEP"}};
    b.doc()["animations"] = json::array({{{"name", "spin"},
                                          {"samplers", {turn, move}},
                                          {"channels", {{{"sampler", 0}, {"target", {{"node", spinner}, {"path", "rotation"}}}},
                                                        {{"sampler", 1}, {"target", {{"node", spinner}, {"path", "translation"}}}}}}}});
  }
};

// Tricky because channels name file nodes, but SceneData orders nodes parents first: the file's
// node 0 (the child) is SceneData node 1. The nodes stay in their own pose at load.
TEST(GltfLoaderAnimations, ChannelsAreReadOntoTheLoadedNodes) {
  AnimatedFile f;
  const auto scene = load(f.b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_TRUE(scene->warnings.empty()) << scene->warnings.front();
  ASSERT_EQ(scene->animations.size(), 1u);
  const AnimationData& spin = scene->animations[0];
  EXPECT_EQ(spin.name, "spin");
  ASSERT_EQ(spin.channels.size(), 2u);
  ASSERT_EQ(scene->nodes[1].name, "spinner");
  EXPECT_EQ(spin.channels[0].node, 1);
  EXPECT_EQ(spin.channels[0].path, AnimatedPath::Rotation);
  EXPECT_EQ(spin.channels[1].path, AnimatedPath::Translation);
  const AnimationSampler& move = spin.samplers[std::size_t(spin.channels[1].sampler)];
  EXPECT_EQ(move.interpolation, Interpolation::Step);
  EXPECT_EQ(move.times, (std::vector<float>{0.0f, 1.0f}));
  EXPECT_EQ(move.values[1], glm::vec4(2, 4, 6, 0));
  EXPECT_EQ(scene->nodes[1].world, glm::mat4(1.0f)) << "loaded in the node's own pose";
}

// Each broken field drops its channel with a warning naming the animation, the channel and the
// problem; the other channel and the file still load (a broken animation is no reason to draw nothing).
TEST(GltfLoaderAnimations, BadChannelsAreDroppedWithAWarningNamingThem) {
  const std::vector<std::pair<std::function<void(AnimatedFile&)>, std::string>> cases = {
      {[](AnimatedFile& f) { f.b.doc()["accessors"][std::size_t(f.times)]["componentType"] = kUnsignedShort; },
       "sampler 0 input: accessor 2: componentType 5123 is not FLOAT"},
      {[](AnimatedFile& f) { f.b.doc()["accessors"][std::size_t(f.turns)]["count"] = 1; },
       "sampler 0: output count 1 is not 2 (the input count)"},
      {[](AnimatedFile& f) { f.sampler(0)["interpolation"] = "CUBICSPLINE"; },
       "output count 2 is not 6 (3 times the input count; CUBICSPLINE"},
      {[](AnimatedFile& f) { f.sampler(0)["output"] = f.times; }, "sampler 0 output: accessor 2: type is SCALAR, expected VEC4"},
      {[](AnimatedFile& f) { f.channel(0)["target"]["node"] = 7; }, "target node 7 out of range (file has 2)"},
      {[](AnimatedFile& f) { f.channel(0)["target"]["path"] = "weights"; }, "path 'weights' is not played"},
      {[](AnimatedFile& f) { f.channel(0)["sampler"] = 5; }, "sampler 5 out of range (file has 2)"},
  };
  for (const auto& [breakIt, expected] : cases) {
    AnimatedFile f;
    breakIt(f);
    const auto scene = load(f.b);
    ASSERT_TRUE(scene.ok()) << expected << ": " << scene.error().message;
    EXPECT_TRUE(anyWarningContains(*scene, "animation 0 'spin' channel 0: ")) << expected;
    EXPECT_TRUE(anyWarningContains(*scene, expected)) << expected << " not in: " << allWarnings(*scene);
    ASSERT_EQ(scene->animations[0].channels.size(), 1u) << expected;
    EXPECT_EQ(scene->animations[0].channels[0].path, AnimatedPath::Translation) << expected;
  }
}

// Keyframe times that repeat or run backwards, or a NaN keyframe value, cannot be played.
TEST(GltfLoaderAnimations, NonIncreasingTimesAndNaNValuesAreNamed) {
  AnimatedFile f;
  const int backwards = f.b.addTightAccessor(std::vector<float>{1.0f, 1.0f}, kFloat, "SCALAR", 2);
  f.sampler(0)["input"] = backwards;
  auto scene = load(f.b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_TRUE(anyWarningContains(*scene, "input times must increase strictly, but key 1 is 1 after 1"));

  AnimatedFile g;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const int bad = g.b.addTightAccessor(std::vector<float>{0, 0, 0, 1, nan, 0, 0, 1}, kFloat, "VEC4", 2);
  g.sampler(0)["output"] = bad;
  scene = load(g.b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_TRUE(anyWarningContains(*scene, "channel 0: sampler 0 output: accessor")) << allWarnings(*scene);
  EXPECT_TRUE(anyWarningContains(*scene, "must be finite"));
}

// Tricky because a file without meshes (or nodes) is valid glTF and must not be mistaken for an
// error: the result is simply empty.
TEST(GltfLoaderFeatures, SceneWithoutMeshesIsEmptyNotAnError) {
  GltfBuilder b;
  b.addNode({{"name", "empty"}});
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_TRUE(scene->meshes.empty());
  EXPECT_EQ(scene->nodes.size(), 1u);
  EXPECT_TRUE(flattenTriangles(*scene).indices.empty());

  GltfBuilder bare;
  const auto bareScene = load(bare);
  ASSERT_TRUE(bareScene.ok()) << bareScene.error().message;
  EXPECT_TRUE(bareScene->nodes.empty());
}

// Tricky because the vertices shared by two triangles of different areas must get the area-weighted
// average of their face normals, not the plain one: areas 2 (+Z) and 1 (+Y) give
// normalize(2*(0,0,1) + 1*(0,1,0)) = normalize(0,1,2), where a plain average gives normalize(0,1,1).
TEST(GltfLoaderFeatures, MissingNormalsAreAreaWeightedSmoothNormals) {
  GltfBuilder b;
  const std::vector<glm::vec3> positions = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, -1}};
  b.addNode({{"mesh", b.addIndexedMesh(positions, {0, 1, 2, 0, 1, 3})}});
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const auto& normals = scene->meshes[0].primitives[0].normals;
  EXPECT_TRUE(scene->meshes[0].primitives[0].flatNormals) << "glTF asks for flat normals: drawn flat";
  ASSERT_EQ(normals.size(), 4u);
  expectNear(normals[0], glm::normalize(glm::vec3(0, 1, 2)));
  expectNear(normals[1], glm::normalize(glm::vec3(0, 1, 2)));
  expectNear(normals[2], {0, 0, 1});
  expectNear(normals[3], {0, 1, 0});
}

// Tricky because a primitive without indices means "vertices in order", which must be generated.
TEST(GltfLoaderFeatures, MissingIndicesAreGeneratedInOrder) {
  GltfBuilder b;
  b.addNode({{"mesh", b.addMesh(b.addPositions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}, {1, 2, 0}}))}});
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(scene->meshes[0].primitives[0].indices, (std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5}));
}

// Tricky because each index width (and an odd-length uint8 view) must decode to the same uint32
// values; signed bytes are not an index type and must be refused rather than sign-extended.
TEST(GltfLoaderFeatures, EveryIndexComponentTypeDecodes) {
  auto withIndices = [](auto values, int componentType) {
    GltfBuilder b;
    const int positions = b.addPositions(kTriangle);
    b.addNode({{"mesh", b.addMesh(positions, b.addTightAccessor(values, componentType, "SCALAR", values.size()))}});
    return load(b);
  };
  for (const auto& scene : {withIndices(std::vector<std::uint8_t>{2, 0, 1}, kUnsignedByte),
                            withIndices(std::vector<std::uint16_t>{2, 0, 1}, kUnsignedShort),
                            withIndices(std::vector<std::uint32_t>{2, 0, 1}, kUnsignedInt)}) {
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    EXPECT_EQ(scene->meshes[0].primitives[0].indices, (std::vector<std::uint32_t>{2, 0, 1}));
  }
  expectError(withIndices(std::vector<std::int8_t>{2, 0, 1}, kByte), "case.gltf", {"cannot hold indices"});
}

// Tricky because normalized integer positions (KHR_mesh_quantization) map to [0,1] / [-1,1] with
// the spec's rules (-128 and -127 both give -1), and a byteStride larger than the element must be
// honoured (padding between the elements).
TEST(GltfLoaderFeatures, NormalizedAndStridedAttributesDecode) {
  GltfBuilder b;
  // uint16 VEC3 with 2 bytes of padding: stride 8.
  const std::vector<std::uint16_t> quantized = {0, 65535, 32768, 0xEEEE, 65535, 0, 0, 0xEEEE, 0, 0, 65535, 0xEEEE};
  const int view = b.addView(b.addData(quantized), quantized.size() * 2, 8);
  const int positions = b.addAccessor(view, kUnsignedShort, 3, "VEC3", true);
  const std::vector<std::int8_t> normals = {-128, 0, 0, 0, 0, -127, 0, 0, 0, 0, 127, 0};  // stride 4
  const int normalView = b.addView(b.addData(normals), normals.size(), 4);
  const int normalAccessor = b.addAccessor(normalView, kByte, 3, "VEC3", true);
  b.addNode({{"mesh", b.addMesh(positions)}});
  b.doc()["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = normalAccessor;
  b.doc()["extensionsRequired"] = {"KHR_mesh_quantization"};
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const auto& primitive = scene->meshes[0].primitives[0];
  expectNear(primitive.positions[0], {0, 1, 32768.0f / 65535.0f});
  expectNear(primitive.positions[1], {1, 0, 0});
  expectNear(primitive.positions[2], {0, 0, 1});
  expectNear(primitive.normals[0], {-1, 0, 0});
  expectNear(primitive.normals[1], {0, -1, 0});
  expectNear(primitive.normals[2], {0, 0, 1});
  EXPECT_FALSE(primitive.flatNormals) << "the file's normals are drawn as given";
}

// Why: a normal map baked with the mesh's tangents is read in them (glTF: clients SHOULD use
// TANGENT when given), so the importer keeps them, w as the handedness's sign. Tricky because a
// TANGENT of the wrong type (VEC3: no handedness) or count would be read misaligned or past the
// vertices: each is dropped with a warning naming TANGENT (the normal texture then read in the
// derivative frame), not an error; and glTF says a primitive without normals MUST ignore them.
TEST(GltfLoaderFeatures, TangentsAreReadAndMalformedOnesDroppedWithAWarning) {
  const auto loadWithTangents = [](const char* type, std::uint64_t count, bool normals) {
    GltfBuilder b = triangleScene();
    const std::vector<float> tangents = {1, 0, 0, 1, 0, 1, 0, -1, 0, 0, 1, -0.5f, 0, 0, 1, 1};  // room for 4 VEC4
    const int tangentAccessor = b.addTightAccessor(tangents, kFloat, type, count);
    auto& attributes = b.doc()["meshes"][0]["primitives"][0]["attributes"];
    attributes["TANGENT"] = tangentAccessor;
    if (normals) attributes["NORMAL"] = b.addTightAccessor(std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1}, kFloat, "VEC3", 3);
    return load(b);
  };
  const auto read = loadWithTangents("VEC4", 3, true);
  ASSERT_TRUE(read.ok()) << read.error().message;
  const auto& tangents = read->meshes[0].primitives[0].tangents;
  ASSERT_EQ(tangents.size(), 3u) << warningLines(*read);
  EXPECT_EQ(tangents[0], glm::vec4(1, 0, 0, 1));
  EXPECT_EQ(tangents[1], glm::vec4(0, 1, 0, -1));
  EXPECT_EQ(tangents[2], glm::vec4(0, 0, 1, -1)) << "w is the handedness's sign";
  EXPECT_FALSE(anyWarningContains(*read, "TANGENT")) << warningLines(*read);

  const auto vec3 = loadWithTangents("VEC3", 3, true);
  ASSERT_TRUE(vec3.ok()) << vec3.error().message;
  EXPECT_TRUE(vec3->meshes[0].primitives[0].tangents.empty());
  EXPECT_TRUE(anyWarningContains(*vec3, "TANGENT not read")) << warningLines(*vec3);

  const auto miscounted = loadWithTangents("VEC4", 4, true);
  ASSERT_TRUE(miscounted.ok()) << miscounted.error().message;
  EXPECT_TRUE(miscounted->meshes[0].primitives[0].tangents.empty());
  EXPECT_TRUE(anyWarningContains(*miscounted, "TANGENT not read: 4 elements for 3 positions")) << warningLines(*miscounted);

  const auto flat = loadWithTangents("VEC4", 3, false);
  ASSERT_TRUE(flat.ok()) << flat.error().message;
  EXPECT_TRUE(flat->meshes[0].primitives[0].tangents.empty()) << "glTF: tangents without normals are ignored";
}

// Tricky because strips alternate their vertex order to keep one winding, and fans pivot on the
// first vertex; both must come out as CCW triangle lists per the glTF specification.
TEST(GltfLoaderFeatures, TriangleStripsAndFansBecomeLists) {
  GltfBuilder b;
  const int positions = b.addPositions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}});
  b.addMesh(positions, -1, 5);  // TRIANGLE_STRIP
  b.addMesh(positions, -1, 6);  // TRIANGLE_FAN
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(scene->meshes[0].primitives[0].indices, (std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2}));
  EXPECT_EQ(scene->meshes[1].primitives[0].indices, (std::vector<std::uint32_t>{1, 2, 0, 2, 3, 0}));
}

// Tricky because points/lines are valid glTF that this importer does not draw: they must be
// skipped with a warning, not rejected, and not turned into triangles; and a CAD export's
// thousands of curves must give one warning naming a few, not one per primitive.
TEST(GltfLoaderFeatures, LinePrimitivesAreSkippedWithWarning) {
  GltfBuilder b;
  b.addNode({{"mesh", b.addMesh(b.addPositions(kTriangle), -1, 1)}});  // LINES
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_TRUE(scene->meshes[0].primitives.empty());
  EXPECT_TRUE(anyWarningContains(*scene, "1 primitive of points or lines is not drawn")) << warningLines(*scene);
  EXPECT_TRUE(anyWarningContains(*scene, "mesh 0 '' primitive 0 (LINES)")) << warningLines(*scene);

  GltfBuilder many;
  const int positions = many.addPositions(kTriangle);
  for (int mode : {0, 1, 2, 3, 0, 3}) many.addNode({{"mesh", many.addMesh(positions, -1, mode)}});
  many.addNode({{"mesh", many.addMesh(positions)}});  // one triangle, drawn
  const auto curves = load(many);
  ASSERT_TRUE(curves.ok()) << curves.error().message;
  std::size_t said = 0;
  for (const std::string& w : curves->warnings) said += w.find("points or lines") != std::string::npos;
  EXPECT_EQ(said, 1u) << warningLines(*curves);
  EXPECT_TRUE(anyWarningContains(*curves, "6 primitives of points or lines are not drawn")) << warningLines(*curves);
  EXPECT_TRUE(anyWarningContains(*curves, "mesh 3 '' primitive 0 (LINE_STRIP), 2 more")) << warningLines(*curves);
  EXPECT_EQ(curves->meshes[6].primitives.size(), 1u);
}

// Tricky because three rules pick the nodes: `scene` wins over scene 0, and with no scenes every
// root node (not every node) is taken.
TEST(GltfLoaderFeatures, DefaultSceneThenSceneZeroThenAllRoots) {
  GltfBuilder b;
  b.addNode({{"name", "first"}, {"children", {2}}});
  b.addNode({{"name", "second"}});
  b.addNode({{"name", "child_of_first"}});
  auto noScenes = load(b);
  ASSERT_TRUE(noScenes.ok()) << noScenes.error().message;
  ASSERT_EQ(noScenes->nodes.size(), 3u);
  EXPECT_EQ(noScenes->nodes[0].name, "first");
  EXPECT_EQ(noScenes->nodes[1].name, "child_of_first");
  EXPECT_EQ(noScenes->nodes[2].name, "second");

  b.doc()["scenes"] = {{{"nodes", {0}}}, {{"nodes", {1}}}};
  auto sceneZero = load(b);
  ASSERT_TRUE(sceneZero.ok()) << sceneZero.error().message;
  ASSERT_EQ(sceneZero->nodes.size(), 2u);
  EXPECT_EQ(sceneZero->nodes[0].name, "first");

  b.doc()["scene"] = 1;
  auto sceneOne = load(b);
  ASSERT_TRUE(sceneOne.ok()) << sceneOne.error().message;
  ASSERT_EQ(sceneOne->nodes.size(), 1u);
  EXPECT_EQ(sceneOne->nodes[0].name, "second");
}

// Tricky because glTF makes aspectRatio and zfar optional (absent zfar means an infinite
// projection) and tinygltf reports both as 0 when absent: neither may become a 0 aspect or a far
// plane at 0.
TEST(GltfLoaderFeatures, CameraWithoutAspectRatioOrZfar) {
  GltfBuilder b;
  b.doc()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.9}, {"znear", 0.25}}}}};
  b.addNode({{"camera", 0}});
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->cameras.size(), 1u);
  EXPECT_FLOAT_EQ(scene->cameras[0].yfov, 0.9f);
  EXPECT_FLOAT_EQ(scene->cameras[0].znear, 0.25f);
  EXPECT_FALSE(scene->cameras[0].zfar.has_value());
  EXPECT_FALSE(scene->cameras[0].aspectRatio.has_value());
  EXPECT_EQ(scene->nodes[0].camera, 0);
}

// Tricky because a strip or fan of two vertices is valid glTF with no triangle in it: it must be
// skipped with a warning, not kept as a primitive with no indices (which the renderer would draw
// from an index buffer that may not exist), while its longer neighbour in the same mesh is kept.
TEST(GltfLoaderFeatures, StripsAndFansOfFewerThanThreeVerticesAreSkipped) {
  GltfBuilder b;
  const int two = b.addPositions({{0, 0, 0}, {1, 0, 0}});
  const int three = b.addPositions(kTriangle);
  b.addMesh(two, -1, 5);  // TRIANGLE_STRIP
  b.doc()["meshes"][0]["primitives"].push_back({{"attributes", {{"POSITION", two}}}, {"mode", 6}});  // FAN
  b.doc()["meshes"][0]["primitives"].push_back({{"attributes", {{"POSITION", three}}}, {"mode", 5}});
  b.addNode({{"mesh", 0}});
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->meshes[0].primitives.size(), 1u);
  EXPECT_EQ(scene->meshes[0].primitives[0].indices, (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_TRUE(anyWarningContains(*scene, "primitive 0: mode 5 with fewer than 3 vertices"));
  EXPECT_TRUE(anyWarningContains(*scene, "primitive 1: mode 6 with fewer than 3 vertices"));
}

// Tricky because glTF forbids `matrix` together with translation/rotation/scale, yet files with
// both exist; the result must be the matrix (not the TRS, not their product).
TEST(GltfLoaderFeatures, MatrixWinsOverTrs) {
  GltfBuilder b;
  b.addNode({{"name", "both"},
             {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5, 6, 7, 1}},
             {"translation", {100, 100, 100}},
             {"scale", {3, 3, 3}}});
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  glm::mat4 expected(1.0f);
  expected[3] = glm::vec4(5, 6, 7, 1);
  expectMatrixNear(scene->nodes[0].world, expected);
}

// Tricky because a buffer in a subfolder reached through ".." that stays inside the glTF's folder
// is valid (and must load), while the same ".." climbing one level further must not be followed,
// whether written plainly or percent-encoded (tinygltf decodes %2F to '/').
TEST(GltfLoaderFeatures, BufferUrisStayInsideTheFilesFolder) {
  const hsdftest::ScopedTempPath folder("gltf_loader_test_uris");  // its own: tests run side by side
  const std::filesystem::path& root = folder.path();
  std::filesystem::create_directories(root / "scene" / "nested");
  std::vector<float> positions;
  for (const auto& p : kTriangle) positions.insert(positions.end(), {p.x, p.y, p.z});
  const std::vector<std::uint8_t> bin(reinterpret_cast<const std::uint8_t*>(positions.data()),
                                      reinterpret_cast<const std::uint8_t*>(positions.data() + positions.size()));
  ASSERT_TRUE(writeBinaryFile(root / "outside.bin", bin).ok());
  ASSERT_TRUE(writeBinaryFile(root / "scene" / "inside.bin", bin).ok());
  auto sceneWithUri = [&](const std::string& uri) {
    const json doc = {{"asset", {{"version", "2.0"}}},
                      {"buffers", {{{"byteLength", bin.size()}, {"uri", uri}}}},
                      {"bufferViews", {{{"buffer", 0}, {"byteLength", bin.size()}}}},
                      {"accessors", {{{"bufferView", 0}, {"componentType", kFloat}, {"count", 3}, {"type", "VEC3"}}}},
                      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}}},
                      {"nodes", {{{"mesh", 0}}}}};
    const std::filesystem::path path = root / "scene" / "scene.gltf";
    EXPECT_TRUE(writeTextFile(path, doc.dump()).ok());
    return loadGltf(path);
  };
  const auto inside = sceneWithUri("nested/../inside.bin");
  ASSERT_TRUE(inside.ok()) << inside.error().message;
  EXPECT_EQ(inside->meshes[0].primitives[0].positions.size(), 3u);
  expectError(sceneWithUri("../outside.bin"), "scene.gltf", {"outside.bin", "lies outside the folder"});
  expectError(sceneWithUri("nested/../../outside.bin"), "scene.gltf", {"lies outside the folder"});
  expectError(sceneWithUri("..%2Foutside.bin"), "scene.gltf", {"lies outside the folder"});
}

// Tricky because a mirroring transform (negative determinant) reverses the apparent winding; glTF
// says to flip it back, so the flattened triangle must still face +Z after mirroring in X.
TEST(GltfLoaderFeatures, FlattenKeepsWindingUnderMirroring) {
  GltfBuilder b;
  b.addNode({{"mesh", b.addIndexedMesh(kTriangle, {0, 1, 2})}, {"scale", {-1, 1, 1}}});
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const auto soup = flattenTriangles(*scene);
  ASSERT_EQ(soup.indices.size(), 3u);
  const glm::vec3 a = soup.positions[soup.indices[0]], bb = soup.positions[soup.indices[1]], c = soup.positions[soup.indices[2]];
  expectNear(glm::normalize(glm::cross(bb - a, c - a)), {0, 0, 1});
}

// Tricky because images are never needed: an image whose bufferView points far outside its buffer
// (which tinygltf 2.7 would index unchecked) and an image file that does not exist must both be
// ignored without error.
TEST(GltfLoaderFeatures, ImagesAreIgnoredEvenWhenBroken) {
  GltfBuilder b = triangleScene();
  const int farView = b.addView(1000000, 16);
  b.doc()["images"] = {{{"bufferView", farView}, {"mimeType", "image/png"}}, {{"uri", "no_such_image.png"}}};
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(scene->meshes.size(), 1u);
}

// ------------------------------------------------------------------------------------------------
// Malformed files

// Tricky because the content is plain text with a .gltf name: the JSON parser must fail cleanly.
TEST(GltfLoaderMalformed, NotJson) {
  expectError(loadGltf(kDataDir / "not_json.gltf"), "not_json.gltf", {"not valid JSON"});
}

// Tricky because the file itself is missing: the error must come from reading, name the path, and
// not be mistaken for an empty scene.
TEST(GltfLoaderMalformed, MissingFile) {
  const auto result = loadGltf(kDataDir / "no_such_scene.glb");
  expectError(result, "no_such_scene.glb", {});
}

// Tricky because tinygltf looks for external files relative to the base directory *and* the
// current directory; the error must name the missing file.
TEST(GltfLoaderMalformed, MissingExternalBufferFile) {
  expectError(loadGltf(kDataDir / "missing_buffer.gltf"), "missing_buffer.gltf", {"does_not_exist.bin", "not found"});
}

// Tricky because bytes from memory with no base directory must not reach the file system at all
// (the fuzzer and untrusted callers rely on it), even for a file that exists next to the test data.
TEST(GltfLoaderMalformed, ExternalFilesRefusedWithoutBaseDirectory) {
  const auto text = readTextFile(kDataDir / "hierarchy.gltf");
  ASSERT_TRUE(text.ok());
  const std::vector<std::uint8_t> bytes(text->begin(), text->end());
  expectError(loadGltfFromMemory(bytes, "hierarchy.gltf", {}), "hierarchy.gltf", {"not allowed"});
}

// Tricky because every prefix of a valid GLB is a different kind of damage (inside the header,
// inside a chunk header, inside the JSON, inside the BIN chunk); none may crash, all must fail,
// both with the header's length left as it was and with it patched to match (so that only the
// chunk walk can notice).
TEST(GltfLoaderMalformed, TruncatedGlb) {
  const auto bunny = bunnyBytes();
  ASSERT_GT(bunny.size(), 2000u);
  for (const std::size_t length : {std::size_t(1), std::size_t(11), std::size_t(12), std::size_t(16), std::size_t(19),
                                   std::size_t(20), std::size_t(500), std::size_t(1040), std::size_t(1044),
                                   std::size_t(1048), bunny.size() - 4, bunny.size() - 1}) {
    std::vector<std::uint8_t> cut(bunny.begin(), bunny.begin() + std::ptrdiff_t(length));
    expectError(loadGltfFromMemory(cut, "cut.glb", {}), "cut.glb", {});
    if (length >= 12) {
      writeU32(cut, 8, std::uint32_t(length));
      expectError(loadGltfFromMemory(cut, "cut.glb", {}), "cut.glb", {});
    }
  }
}

// Tricky because a BIN chunk length that overruns the file by exactly its own 8-byte header passes
// tinygltf 2.7's check (which forgets the header) and would make it read past the end; the JSON
// chunk length is also broken in a separate case.
TEST(GltfLoaderMalformed, GlbWithWrongChunkLength) {
  const auto bunny = bunnyBytes();
  const std::uint32_t jsonLength = readU32(bunny, 12);
  const std::size_t binHeader = 20 + jsonLength;
  ASSERT_EQ(readU32(bunny, binHeader + 4), 0x004E4942u) << "second chunk of the bunny should be BIN";

  auto binTooLong = bunny;
  writeU32(binTooLong, binHeader, readU32(bunny, binHeader) + 8);
  expectError(loadGltfFromMemory(binTooLong, "bin.glb", {}), "bin.glb", {"chunk 1", "runs past the end"});

  auto jsonTooLong = bunny;
  writeU32(jsonTooLong, 12, 0xFFFFFFF0u);
  expectError(loadGltfFromMemory(jsonTooLong, "json.glb", {}), "json.glb", {"chunk 0", "runs past the end"});

  auto wrongVersion = bunny;
  writeU32(wrongVersion, 4, 1);
  expectError(loadGltfFromMemory(wrongVersion, "v1.glb", {}), "v1.glb", {"version 1"});
}

// Tricky because tinygltf does not check accessor -> bufferView references; ours must, and say
// how many there are (the schema check, gltf_validate.h, catches it before the conversion does).
TEST(GltfLoaderMalformed, AccessorBufferViewOutOfRange) {
  GltfBuilder b = triangleScene();
  b.doc()["accessors"][0]["bufferView"] = 7;
  expectError(load(b, "bad.gltf"), "bad.gltf", {"accessors[0].bufferView: 7 is out of range (the file has 2 bufferViews)"});
}

// Tricky because the view's own numbers are plausible; only comparing with the buffer's real size
// catches it.
TEST(GltfLoaderMalformed, BufferViewBeyondBuffer) {
  GltfBuilder b = triangleScene();
  b.doc()["bufferViews"][0]["byteOffset"] = 40;
  expectError(load(b), "case.gltf", {"bufferView 0", "beyond buffer 0"});
}

// Tricky because 2^62 elements of 12 bytes wrap a 64-bit product to 0, so a naive
// `offset + count * stride <= length` check passes; the count must also never reach an allocation.
TEST(GltfLoaderMalformed, AccessorCountOverflowsAndAbsurdCounts) {
  for (const std::uint64_t count : {std::uint64_t(1) << 62, std::uint64_t(1000000000000), std::uint64_t(4)}) {
    GltfBuilder b = triangleScene();
    b.doc()["accessors"][0]["count"] = count;
    expectError(load(b), "case.gltf", {"accessor 0", "runs past the end of bufferView"});
  }
}

// Tricky because tinygltf accepts any multiple of 4 as byteStride, including one smaller than the
// element, which would make elements overlap.
TEST(GltfLoaderMalformed, StrideSmallerThanElement) {
  GltfBuilder b = triangleScene();
  b.doc()["bufferViews"][0]["byteStride"] = 4;
  expectError(load(b), "case.gltf", {"byteStride 4 is smaller than one element"});
}

// Tricky because the index data itself is in range of its buffer; only the vertex count shows that
// index 3 of a 3-vertex mesh is out of range.
TEST(GltfLoaderMalformed, IndexOutOfRangeOfVertexCount) {
  GltfBuilder b;
  b.addNode({{"mesh", b.addIndexedMesh(kTriangle, {0, 1, 3})}});
  expectError(load(b), "case.gltf", {"mesh 0", "index 3", "out of range of the 3 vertices"});
}

// Tricky because a cycle must be found without following it (a recursive walk would never end),
// whether or not the cycle hangs below a root, and a node may have only one parent.
TEST(GltfLoaderMalformed, NodeCyclesSharedChildrenAndBadChildren) {
  {
    GltfBuilder b;
    b.addNode({{"children", {1}}});
    b.addNode({{"children", {2}}});
    b.addNode({{"children", {1}}});  // 1 -> 2 -> 1 below root 0: node 1 then has two parents
    expectError(load(b), "case.gltf", {"node 1 has two parents"});
  }
  {
    GltfBuilder b;
    b.addNode({{"name", "root"}});
    b.addNode({{"children", {2}}});
    b.addNode({{"children", {1}}});  // a detached 2-cycle: every node has one parent
    expectError(load(b), "case.gltf", {"cycle"});
  }
  {
    GltfBuilder b;
    b.addNode({{"children", {0}}});
    expectError(load(b), "case.gltf", {"node 0 lists itself as a child"});
  }
  {
    GltfBuilder b;
    b.addNode({{"children", {9}}});
    expectError(load(b), "case.gltf", {"nodes[0].children[0]: 9 is out of range (the file has 1 node)"});
  }
  {
    GltfBuilder b;
    b.addNode({{"children", {1}}});
    b.addNode({{"name", "child"}});
    b.doc()["scenes"] = {{{"nodes", {1}}}};
    expectError(load(b), "case.gltf", {"scene 0 lists node 1, which is a child of node 0"});
  }
}

// Tricky because JSON cannot express NaN or infinity, so they can only arrive as buffer bytes;
// they must be caught when decoding, not surface later in the renderer or the SDF baker.
TEST(GltfLoaderMalformed, NonFinitePositions) {
  for (const float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    GltfBuilder b;
    b.addNode({{"mesh", b.addMesh(b.addPositions({{0, 0, 0}, {1, bad, 0}, {0, 1, 0}}))}});
    expectError(load(b), "case.gltf", {"POSITION", "element 1 component 1", "must be finite"});
  }
}

// Tricky because each value is finite on its own; only the product of two huge scales overflows.
TEST(GltfLoaderMalformed, WorldMatrixOverflow) {
  GltfBuilder b;
  b.addNode({{"scale", {1e30, 1e30, 1e30}}, {"children", {1}}});
  b.addNode({{"scale", {1e30, 1e30, 1e30}}});
  expectError(load(b), "case.gltf", {"world matrix is not finite"});

  GltfBuilder tooBig;
  tooBig.addNode({{"scale", {1e300, 1, 1}}});  // a valid double, not a float
  expectError(load(tooBig), "case.gltf", {"scale", "not a finite 32-bit float"});
}

// Tricky because tinygltf's conversion of `extras` recurses once per nesting level: a deep enough
// document would overflow the stack inside the library unless refused first.
TEST(GltfLoaderMalformed, DeeplyNestedJson) {
  std::string text = R"({"asset":{"version":"2.0"},"extras":)";
  text += std::string(100000, '[') + std::string(100000, ']') + "}";
  const std::vector<std::uint8_t> bytes(text.begin(), text.end());
  expectError(loadGltfFromMemory(bytes, "deep.gltf", {}), "deep.gltf", {"nested deeper than"});
}

// Tricky because required extensions change how the data must be read or placed: ignoring one
// would produce wrong geometry instead of an error. The check must come first: with an unknown
// compression the accessors have no data, and an error about that symptom would not tell the user
// what is missing.
TEST(GltfLoaderExtensions, UnsupportedRequiredExtensionsAreRefusedByName) {
  GltfBuilder vendor = triangleScene();
  vendor.doc()["extensionsRequired"] = {"KHR_mesh_quantization", "ACME_mesh_compression"};
  vendor.doc()["accessors"][0].erase("bufferView");  // what an unknown compression leaves behind
  expectError(load(vendor, "vendor.glb"), "vendor.glb", {"requires extension ACME_mesh_compression", "does not support"});

  GltfBuilder notNames = triangleScene();
  notNames.doc()["extensionsRequired"] = {42};
  expectError(load(notNames), "case.gltf", {"extensionsRequired holds a JSON number"});
}

// Tricky because a file may require an extension that only concerns materials or textures: the
// geometry is complete without it, so it must load, with a note, rather than be refused.
TEST(GltfLoaderExtensions, ExtensionsThatDoNotAffectGeometryAreIgnoredWithANote) {
  GltfBuilder b = triangleScene();
  b.doc()["extensionsUsed"] = {"KHR_texture_transform", "KHR_materials_clearcoat", "ACME_metadata"};
  b.doc()["extensionsRequired"] = {"KHR_texture_transform"};
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(scene->meshes.at(0).primitives.at(0).indices.size(), 3u);
  EXPECT_FALSE(anyWarningContains(*scene, "KHR_texture_transform")) << "read (on base colour textures): no note";
  EXPECT_TRUE(anyWarningContains(*scene, "extension KHR_materials_clearcoat ignored: it does not affect geometry"));
  EXPECT_TRUE(anyWarningContains(*scene, "extension ACME_metadata is not supported and was ignored"));
}

// ------------------------------------------------------------------------------------------------
// EXT_mesh_gpu_instancing (tests/data/gltf/gpu_instancing.gltf and in-memory cases)

glm::mat4 trs(const glm::vec3& t, const glm::quat& r, const glm::vec3& s) {
  return glm::translate(glm::mat4(1.0f), t) * glm::mat4_cast(r) * glm::scale(glm::mat4(1.0f), s);
}

// Tricky because an instance is placed by the node's world matrix times its own translation,
// rotation and scale, in that order; the rotations are normalized int16 (x, y, z, w as glTF
// stores quaternions, 23170 / 32767 for sin 45 degrees); the node itself must no longer draw its
// mesh (a fourth copy at the node), and every instance must be a node of its own that the SDF
// objects and the triangle soup see.
TEST(GltfLoaderExtensions, GpuInstancingPlacesTheMeshAtEveryInstance) {
  const auto scene = loadGltf(kDataDir / "gpu_instancing.gltf");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->nodes.size(), 4u);
  const NodeData& node = scene->nodes[0];
  EXPECT_EQ(node.name, "tetras");
  EXPECT_EQ(node.mesh, -1) << "the mesh is drawn at the instances only";
  const glm::mat4 nodeWorld = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, -1.0f));
  const float s45 = 23170.0f / 32767.0f;
  const glm::mat4 expected[3] = {
      trs({0, 0, 0}, glm::quat(1, 0, 0, 0), {1, 1, 1}),
      trs({2, 0, 0}, glm::normalize(glm::quat(s45, 0, 0, s45)), {1, 1, 1}),  // glm::quat takes w first
      trs({0, 3, 0}, glm::quat(1, 0, 0, 0), {2, 2, 2}),
  };
  for (int i = 0; i < 3; ++i) {
    SCOPED_TRACE(i);
    const NodeData& instance = scene->nodes[std::size_t(1 + i)];
    EXPECT_EQ(instance.name, "tetras[" + std::to_string(i) + "]");
    EXPECT_EQ(instance.parent, 0);
    EXPECT_EQ(instance.mesh, 0);
    expectMatrixNear(instance.world, nodeWorld * expected[i]);
  }
  const auto soup = flattenTriangles(*scene);
  EXPECT_EQ(soup.indices.size(), 3u * 12u);
  // The tetrahedron's vertex (1, 0, 0) of instance 1: turned to (0, 1, 0), moved by (2, 0, 0) and
  // by the node's (0, 0, -1).
  bool found = false;
  for (const glm::vec3& p : soup.positions) found = found || glm::length(p - glm::vec3(2.0f, 1.0f, -1.0f)) < 1e-4f;
  EXPECT_TRUE(found);
}

// A scene whose node 0 instances a triangle through `attributes` (accessors added by `build`).
GltfBuilder instancedTriangle(const std::function<json(GltfBuilder&)>& build) {
  GltfBuilder b;
  const int mesh = b.addIndexedMesh(kTriangle, {0, 1, 2});
  const json attributes = build(b);
  b.addNode({{"mesh", mesh}, {"name", "inst"}, {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", attributes}}}}}});
  b.doc()["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  return b;
}

// Tricky because each of these would place instances at garbage or crash a reader that trusted
// the file: counts that disagree, a zero quaternion, an index that is not an accessor, a wrong
// type, no known attribute, and a count forged past what the scene can hold (an accessor of
// zeros costs no file bytes). Each error names the node, the extension and the problem.
TEST(GltfLoaderExtensions, BrokenGpuInstancingIsRefusedNamingTheNode) {
  const std::vector<float> two = {0, 0, 0, 1, 0, 0};
  struct Case {
    std::function<json(GltfBuilder&)> build;
    const char* expected;
  };
  const Case cases[] = {
      {[&](GltfBuilder& b) {
         return json{{"TRANSLATION", b.addTightAccessor(two, kFloat, "VEC3", 2)},
                     {"SCALE", b.addTightAccessor(std::vector<float>{1, 1, 1}, kFloat, "VEC3", 1)}};
       },
       "attribute TRANSLATION has 2 instances, the others 1"},
      {[&](GltfBuilder& b) { return json{{"ROTATION", b.addTightAccessor(std::vector<float>(8, 0.0f), kFloat, "VEC4", 2)}}; },
       "instance 0: rotation quaternion has zero"},
      {[&](GltfBuilder&) { return json{{"TRANSLATION", 99}}; }, "accessor 99"},
      {[&](GltfBuilder&) { return json{{"TRANSLATION", "zero"}}; }, "attribute TRANSLATION is not an accessor index"},
      {[&](GltfBuilder& b) { return json{{"TRANSLATION", b.addTightAccessor(two, kFloat, "VEC2", 3)}}; },
       "type is VEC2, expected VEC3"},
      {[&](GltfBuilder& b) { return json{{"_ID", b.addTightAccessor(two, kFloat, "VEC3", 2)}}; },
       "no TRANSLATION, ROTATION or SCALE attribute"},
      {[&](GltfBuilder& b) {
         const int zeros = b.addAccessor(0, kFloat, (std::uint64_t(1) << 20) + 1, "VEC3");
         b.doc()["accessors"][std::size_t(zeros)].erase("bufferView");
         return json{{"TRANSLATION", zeros}};
       },
       "more than the 1048576 mesh instances a file may place"},
  };
  for (const Case& c : cases) {
    GltfBuilder b = instancedTriangle(c.build);
    expectError(load(b), "case.gltf", {"node 0 'inst': EXT_mesh_gpu_instancing", c.expected});
  }
  GltfBuilder noAttributes = instancedTriangle([](GltfBuilder&) { return json(); });
  noAttributes.doc()["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"].erase("attributes");
  expectError(load(noAttributes), "case.gltf", {"attributes is missing or not an object"});
}

// Tricky because the extension on a node without a mesh has nothing to place: the file loads, with
// a note, and the node stays a plain node (no instance nodes).
TEST(GltfLoaderExtensions, GpuInstancingWithoutAMeshIsIgnoredWithANote) {
  GltfBuilder b = instancedTriangle([](GltfBuilder& builder) {
    return json{{"TRANSLATION", builder.addTightAccessor(std::vector<float>{0, 0, 0, 1, 0, 0}, kFloat, "VEC3", 2)}};
  });
  b.doc()["nodes"][0].erase("mesh");
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(scene->nodes.size(), 1u);
  EXPECT_TRUE(anyWarningContains(*scene, "EXT_mesh_gpu_instancing on a node without a mesh ignored"));
}

// Tricky because the extension is broken (its attribute names no accessor) on a node it could not
// apply to anyway: ignoring it means not reading it, so the file loads with the same note.
TEST(GltfLoaderExtensions, BrokenGpuInstancingWithoutAMeshIsIgnoredUnread) {
  GltfBuilder b = instancedTriangle([](GltfBuilder&) { return json{{"TRANSLATION", 999}}; });
  b.doc()["nodes"][0].erase("mesh");
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(scene->nodes.size(), 1u);
  EXPECT_TRUE(anyWarningContains(*scene, "EXT_mesh_gpu_instancing on a node without a mesh ignored"));
}

// ------------------------------------------------------------------------------------------------
// Sparse accessors and accessors without a bufferView (tests/data/gltf/tetra_sparse_scenes.gltf and
// in-memory cases)

// Tricky because each of the three meshes reaches the same tetrahedron a different way: plain, a
// base view with two vertices swapped that the sparse part swaps back, and zeros (no bufferView)
// with three vertices written by the sparse part. A sparse part applied at the wrong element, not
// applied, or a base that is not zero would each give different positions. The file also has two
// scenes (default 1) and an ignored material extension.
TEST(GltfLoaderSparse, SparseOverAViewAndOverZerosGiveThePlainPositions) {
  const auto scene = loadGltf(kDataDir / "tetra_sparse_scenes.gltf");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->meshes.size(), 3u);
  const auto& plain = scene->meshes[0].primitives.at(0);
  ASSERT_EQ(plain.positions.size(), 4u);
  expectNear(plain.positions[1], {1, 0, 0}, 0.0f);
  expectNear(plain.positions[3], {0, 0, 1}, 0.0f);
  for (int m = 1; m < 3; ++m) {
    const auto& other = scene->meshes[std::size_t(m)].primitives.at(0);
    ASSERT_EQ(other.positions.size(), 4u) << scene->meshes[std::size_t(m)].name;
    for (std::size_t v = 0; v < 4; ++v) expectNear(other.positions[v], plain.positions[v], 0.0f);
    EXPECT_EQ(other.indices, plain.indices);
  }
  // The material's emission is read (since session 39): the factor times emissiveStrength 4.
  ASSERT_EQ(scene->materials.size(), 1u);
  EXPECT_EQ(scene->materials[0].emissive, glm::vec3(4.0f, 2.0f, 0.8f));
  EXPECT_FALSE(anyWarningContains(*scene, "KHR_materials_emissive_strength"));
}

// Tricky because glTF defines an accessor without a bufferView as zeros: reading it must neither
// fail nor touch memory, and the zeros must be exact.
TEST(GltfLoaderSparse, AccessorWithoutBufferViewIsZeros) {
  GltfBuilder b;
  const int positions = b.addPositions(kTriangle);
  b.doc()["accessors"][std::size_t(positions)].erase("bufferView");
  b.addNode({{"mesh", b.addMesh(positions)}});
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  for (const auto& p : scene->meshes.at(0).primitives.at(0).positions) expectNear(p, {0, 0, 0}, 0.0f);
}

// Tricky because every number of a sparse part is a possible out-of-bounds write: indices at or
// past the count, indices that repeat or go backwards (the spec requires strictly increasing),
// counts of 0 or above the accessor's, values running past their view, and an index type that is
// not an unsigned integer. Each must be an error naming the problem.
TEST(GltfLoaderSparse, MalformedSparsePartsAreNamed) {
  auto sparseCase = [](std::vector<std::uint32_t> targets, int count, int indexType = kUnsignedInt) {
    GltfBuilder b = triangleScene();
    const std::size_t indexOffset = b.addData(targets);
    const int indexView = b.addView(indexOffset, targets.size() * 4);
    const std::vector<float> values(targets.size() * 3, 0.5f);
    const std::size_t valueOffset = b.addData(values);
    const int valueView = b.addView(valueOffset, values.size() * 4);
    b.doc()["accessors"][0]["sparse"] = {{"count", count},
                                         {"indices", {{"bufferView", indexView}, {"componentType", indexType}}},
                                         {"values", {{"bufferView", valueView}}}};
    return b;
  };
  GltfBuilder good = sparseCase({0, 2}, 2);
  const auto loaded = load(good);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  expectNear(loaded->meshes[0].primitives[0].positions[2], {0.5f, 0.5f, 0.5f}, 0.0f);
  expectNear(loaded->meshes[0].primitives[0].positions[1], kTriangle[1], 0.0f);

  GltfBuilder pastCount = sparseCase({0, 3}, 2);
  expectError(load(pastCount), "case.gltf", {"accessor 0", "sparse index 3 (entry 1) is not below the accessor's count 3"});
  GltfBuilder repeated = sparseCase({1, 1}, 2);
  expectError(load(repeated), "case.gltf", {"sparse indices must increase strictly, but entry 1 is 1 after 1"});
  GltfBuilder zero = sparseCase({1}, 0);
  expectError(load(zero), "case.gltf", {"accessors[0].sparse.count: 0 is below the minimum (schema: minimum 1)"});
  GltfBuilder tooMany = sparseCase({0, 1, 2}, 4);
  expectError(load(tooMany), "case.gltf", {"accessors[0].sparse.count: 4 is more than the accessor's count 3"});
  GltfBuilder shortValues = sparseCase({0, 1}, 2);
  shortValues.doc()["accessors"][0]["sparse"]["values"]["byteOffset"] = 8;
  expectError(load(shortValues), "case.gltf", {"sparse values", "run past the end of bufferView"});
  GltfBuilder floatIndices = sparseCase({0, 1}, 2, kFloat);
  expectError(load(floatIndices), "case.gltf", {"accessors[0].sparse.indices.componentType: 5126 is not an unsigned integer type"});
}

// ------------------------------------------------------------------------------------------------
// Multiple scenes

// Tricky because the default scene is not scene 0 here: loading scene 0 by habit would give one
// node instead of three. Asking for a scene picks it; a scene that does not exist is an error.
TEST(GltfLoaderScenes, DefaultSceneOrTheRequestedOneWithANote) {
  const auto byDefault = loadGltf(kDataDir / "tetra_sparse_scenes.gltf");
  ASSERT_TRUE(byDefault.ok()) << byDefault.error().message;
  EXPECT_EQ(byDefault->nodes.size(), 3u);
  EXPECT_TRUE(anyWarningContains(*byDefault, "the file has 2 scenes; loaded scene 1 'all three' (the file's default)"));

  GltfLoadOptions first;
  first.scene = 0;
  const auto chosen = loadGltf(kDataDir / "tetra_sparse_scenes.gltf", first);
  ASSERT_TRUE(chosen.ok()) << chosen.error().message;
  ASSERT_EQ(chosen->nodes.size(), 1u);
  EXPECT_EQ(chosen->nodes[0].name, "plain (scene 0)");
  EXPECT_TRUE(anyWarningContains(*chosen, "loaded scene 0 'plain only' (as requested)"));

  GltfLoadOptions missing;
  missing.scene = 2;
  expectError(loadGltf(kDataDir / "tetra_sparse_scenes.gltf", missing), "tetra_sparse_scenes.gltf",
              {"scene 2 was requested but the file has 2 scene(s)"});
}

// Tricky because a POSITION accessor of the wrong shape (SCALAR) or an unknown component type
// would otherwise be read with the wrong element size.
TEST(GltfLoaderMalformed, WrongAccessorTypeOrComponentType) {
  GltfBuilder scalar = triangleScene();
  scalar.doc()["accessors"][0]["type"] = "SCALAR";
  expectError(load(scalar), "case.gltf", {"type is SCALAR, expected VEC3"});

  GltfBuilder intComponents = triangleScene();
  intComponents.doc()["accessors"][0]["componentType"] = 5124;  // INT: not a glTF 2.0 component type
  expectError(load(intComponents), "case.gltf", {"accessors[0].componentType: 5124 is not a glTF 2.0 component type"});
}

// Tricky because node -> mesh/camera and primitive -> material references are not checked by
// tinygltf and would index past the end of the arrays.
TEST(GltfLoaderMalformed, DanglingMeshCameraAndMaterialReferences) {
  GltfBuilder mesh = triangleScene();
  mesh.doc()["nodes"][0]["mesh"] = 5;
  expectError(load(mesh), "case.gltf", {"nodes[0].mesh: 5 is out of range (the file has 1 mesh)"});

  GltfBuilder camera = triangleScene();
  camera.doc()["nodes"][0]["camera"] = 0;
  expectError(load(camera), "case.gltf", {"nodes[0].camera: 0 is out of range (the file has 0 cameras)"});

  GltfBuilder material = triangleScene();
  material.doc()["meshes"][0]["primitives"][0]["material"] = 2;
  expectError(load(material), "case.gltf", {"meshes[0].primitives[0].material: 2 is out of range (the file has 0 materials)"});
}

// Tricky because every index, offset and count in the file is valid: one 9999-vertex accessor
// used by 2000 primitives is a 120 KB buffer that decodes to some 560 MB (positions, generated
// indices and normals). The decode budget (64 MB + 16 bytes per input byte) must stop it after a
// few hundred primitives, with an error, instead of allocating it all.
TEST(GltfLoaderMalformed, OneAccessorReusedByManyPrimitivesHitsTheDecodeBudget) {
  GltfBuilder b;
  std::vector<glm::vec3> positions(9999);
  for (std::size_t i = 0; i < positions.size(); ++i) positions[i] = {float(i % 100), float(i / 100), float(i % 7)};
  const int accessor = b.addPositions(positions);
  json primitives = json::array();
  for (int p = 0; p < 2000; ++p) primitives.push_back({{"attributes", {{"POSITION", accessor}}}});
  b.doc()["meshes"] = {{{"primitives", primitives}}};
  expectError(load(b), "case.gltf", {"decoded geometry would exceed the limit"});
}

// Tricky because loading is cheap here (one 10000-vertex mesh) and the renderer draws instances
// without copying them, so the file is fine until something flattens it: 7000 nodes placing the
// mesh ask for 70 million world-space vertices (some 2.5 GB with indices), which must be refused
// before flattening, naming the count and the limit; a few instances stay well within it.
TEST(GltfLoaderMalformed, InstancingExplosionIsRefusedBeforeFlattening) {
  GltfBuilder b;
  std::vector<glm::vec3> positions(10000);
  for (std::size_t i = 0; i < positions.size(); ++i) positions[i] = {float(i % 100), float(i / 100), 0.0f};
  const int mesh = b.addMesh(b.addPositions(positions), -1, 5);  // one long strip
  for (int n = 0; n < 7000; ++n) b.addNode({{"mesh", mesh}, {"translation", {0, 0, n}}});
  const auto scene = load(b);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const Status status = checkFlattenable(*scene);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.error().message.find("7000 mesh instances flatten to 70000000 vertices, over the limit of 67108864"),
            std::string::npos)
      << status.error().message;
  EXPECT_TRUE(checkFlattenable(*scene, 70000000).ok());
}

// Tricky because a camera's numbers can be well-formed JSON yet unusable (a field of view beyond
// 180 degrees) and must be refused instead of producing a broken projection.
TEST(GltfLoaderMalformed, UnusableCamera) {
  GltfBuilder b;
  b.doc()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 4.0}, {"znear", 0.1}}}}};
  expectError(load(b), "case.gltf", {"camera 0", "yfov"});
}

// A file with one orthographic camera named "plan", loaded.
Expected<SceneData> orthographicCamera(double xmag, double ymag, double znear, double zfar) {
  GltfBuilder b;
  b.doc()["cameras"] = {{{"name", "plan"},
                         {"type", "orthographic"},
                         {"orthographic", {{"xmag", xmag}, {"ymag", ymag}, {"znear", znear}, {"zfar", zfar}}}}};
  return load(b);
}

// Tricky because glTF allows an orthographic znear of exactly 0 (a perspective one must be > 0),
// and a wide, short view (xmag != ymag) must keep both magnifications as they are.
TEST(GltfLoaderCameras, OrthographicCameraWithZeroNearIsKept) {
  const auto scene = orthographicCamera(4.0, 0.5, 0.0, 20.0);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->cameras.size(), 1u);
  const CameraData& camera = scene->cameras[0];
  EXPECT_TRUE(camera.orthographic);
  EXPECT_EQ(camera.name, "plan");
  EXPECT_FLOAT_EQ(camera.xmag, 4.0f);
  EXPECT_FLOAT_EQ(camera.ymag, 0.5f);
  EXPECT_FLOAT_EQ(camera.znear, 0.0f);
  EXPECT_FLOAT_EQ(camera.zfar.value_or(-1.0f), 20.0f);
}

// Tricky because each bad value is otherwise well-formed JSON that the parser accepts, and each
// would make a degenerate (zero size, mirrored, or inverted depth) projection: the error must
// name the camera and the offending field. A negative magnification is only discouraged by glTF,
// but it mirrors the image (and the winding that back-face culling relies on), so it is refused.
TEST(GltfLoaderCameras, UnusableOrthographicCameraNamesTheField) {
  expectError(orthographicCamera(0.0, 1.0, 0.1, 10.0), "case.gltf", {"camera 0 'plan'", "xmag 0"});
  expectError(orthographicCamera(1.0, 0.0, 0.1, 10.0), "case.gltf", {"camera 0 'plan'", "ymag 0"});
  expectError(orthographicCamera(1.0, -2.0, 0.1, 10.0), "case.gltf", {"ymag -2", "not positive"});
  expectError(orthographicCamera(1.0, 1.0, -0.5, 10.0), "case.gltf", {"znear -0.5", "negative"});
  expectError(orthographicCamera(1.0, 1.0, 5.0, 5.0), "case.gltf", {"zfar 5", "not beyond znear 5"});
  expectError(orthographicCamera(1.0, 1.0, 0.0, 1e300), "case.gltf", {"zfar"});
}

// Tricky because the orthographic far plane is required by glTF (unlike the perspective one, whose
// absence means infinite): a file without it must be refused, naming the field.
TEST(GltfLoaderCameras, OrthographicCameraWithoutFarPlaneIsRefused) {
  GltfBuilder b;
  b.doc()["cameras"] = {{{"type", "orthographic"}, {"orthographic", {{"xmag", 1.0}, {"ymag", 1.0}, {"znear", 0.1}}}}};
  expectError(load(b), "case.gltf", {"zfar"});
}

}  // namespace
}  // namespace engine::scene
