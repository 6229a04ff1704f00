// glTF 2.0 schema ranges (engine/scene/gltf_validate.h): one small valid file, and one case per
// schema-violating value, each an edit of that file's JSON. Every case must be refused with an error
// that names the file and the field by its JSON path; 29 of the 60 were accepted before the check
// (tinygltf drops, wraps or defaults the value, and the loader never read the field or read it
// only for the nodes of the chosen scene). A valid file with values at the edges of the ranges
// must still load, and so must every committed glTF test file and fuzz seed.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "engine/scene/gltf/gltf_loader.h"

namespace engine::scene {
namespace {

using nlohmann::json;

const std::filesystem::path kTestData = std::filesystem::path(HSDF_TEST_DATA_DIR);

// One 60-byte buffer: float VEC3 positions (0,0,0) (1,0,0) (0,1,0) at 0; uint16 indices 0 1 2 at
// 36; a uint16 sparse index 1 at 44; a float VEC3 sparse value (1,1,0) at 48.
// Accessors: 0 POSITION, 1 indices, 2 POSITION with the sparse part (vertex 1 -> (1,1,0)), 3 a
// TEXCOORD_0 the loader never reads. Node 0 (TRS) has child 1 (matrix); node 2 has the camera;
// node 3 lies outside the scene (the loader drops it).
constexpr const char* kValidGltf = R"({
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0, 2]}],
  "nodes": [
    {"mesh": 0, "children": [1], "translation": [1, 2, 3], "rotation": [0, 0, 0, 1], "scale": [1, 1, 1]},
    {"mesh": 1, "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,5,1]},
    {"camera": 0},
    {"mesh": 0}
  ],
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
  "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 0.25, 1], "metallicFactor": 0, "roughnessFactor": 1}}],
  "meshes": [
    {"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 3}, "indices": 1, "material": 0, "mode": 4}]},
    {"primitives": [{"attributes": {"POSITION": 2}}]}
  ],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
    {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
    {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
     "sparse": {"count": 1, "indices": {"bufferView": 2, "componentType": 5123}, "values": {"bufferView": 3}}},
    {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC2"}
  ],
  "bufferViews": [
    {"buffer": 0, "byteOffset": 0, "byteLength": 36, "target": 34962},
    {"buffer": 0, "byteOffset": 36, "byteLength": 6, "target": 34963},
    {"buffer": 0, "byteOffset": 44, "byteLength": 2},
    {"buffer": 0, "byteOffset": 48, "byteLength": 12}
  ],
  "buffers": [{"byteLength": 60, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAABAAAAAACAPwAAgD8AAAAA"}]
})";

std::vector<std::uint8_t> bytesOf(const json& document) {
  const std::string text = document.dump();
  return {text.begin(), text.end()};
}

// A GLB around `document` (no BIN chunk: its buffer is a data: URI, which GLB allows).
std::vector<std::uint8_t> glbOf(const json& document) {
  std::string text = document.dump();
  while (text.size() % 4 != 0) text += ' ';
  std::vector<std::uint8_t> glb;
  auto u32 = [&glb](std::uint32_t v) {
    for (int shift = 0; shift < 32; shift += 8) glb.push_back(std::uint8_t(v >> shift));
  };
  u32(0x46546C67);  // "glTF"
  u32(2);
  u32(std::uint32_t(12 + 8 + text.size()));
  u32(std::uint32_t(text.size()));
  u32(0x4E4F534A);  // "JSON"
  glb.insert(glb.end(), text.begin(), text.end());
  return glb;
}

struct Edit {
  std::string pointer;  // RFC 6901 JSON pointer into the valid file
  json value;           // the value written there (a discarded json removes the member)
};

json removed() { return json(json::value_t::discarded); }

json edited(const std::vector<Edit>& edits) {
  json document = json::parse(kValidGltf);
  for (const auto& edit : edits) {
    const json::json_pointer pointer(edit.pointer);
    if (edit.value.is_discarded())
      document.at(pointer.parent_pointer()).erase(pointer.back());
    else
      document[pointer] = edit.value;
  }
  return document;
}

struct SchemaCase {
  const char* why;  // what makes the value tricky
  std::vector<Edit> edits;
  std::string expected;  // the error must contain this (field path, value, rule)
};

// Every class of field the loader reads, one bad value at a time.
std::vector<SchemaCase> schemaCases() {
  return {
      // Accessors
      {"tinygltf reads an unsigned field only from a non-negative JSON integer: -4 became 0 and drew",
       {{"/accessors/0/byteOffset", -4}},
       "accessors[0].byteOffset: -4 is negative (schema: minimum 0)"},
      {"4.0 is a JSON float, which tinygltf took as an absent byteOffset (0), not 4",
       {{"/accessors/0/byteOffset", 4.0}},
       "accessors[0].byteOffset: 4.0 is not an integer (schema: integer)"},
      {"a uint16 accessor at an odd offset: every index straddles two components (the old error blamed the view's length)",
       {{"/accessors/1/byteOffset", 1}},
       "accessors[1].byteOffset: 1 is not a multiple of the component size 2 (UNSIGNED_SHORT)"},
      {"no accessor byteOffset at all, yet the view's offset (37) misaligns the uint16 indices (read anyway, they gave index 256)",
       {{"/bufferViews/1/byteOffset", 37}},
       "accessors[1]: bufferViews[1].byteOffset 37 + byteOffset 0 = 37 is not a multiple of the component size 2"},
      {"a byteOffset without a bufferView would offset into zeros (the schema makes it depend on one)",
       {{"/accessors/3/bufferView", removed()}, {"/accessors/3/byteOffset", 8}},
       "accessors[3].byteOffset: given without a bufferView"},
      {"count 0 on an accessor the loader never reads (TEXCOORD_0) used to pass unnoticed",
       {{"/accessors/3/count", 0}},
       "accessors[3].count: 0 is below the minimum (schema: minimum 1)"},
      {"a negative count (tinygltf refuses it too, with a message that names no accessor)",
       {{"/accessors/0/count", -3}},
       "accessors[0].count: -3 is below the minimum (schema: minimum 1)"},
      {"5130 (DOUBLE) is an OpenGL code tinygltf accepts; glTF 2.0 has no 8-byte components",
       {{"/accessors/3/componentType", 5130}},
       "accessors[3].componentType: 5130 is not a glTF 2.0 component type"},
      {"componentType is required: without it the element size is unknown",
       {{"/accessors/0/componentType", removed()}},
       "accessors[0].componentType: is missing (schema: required)"},
      {"type is an enum of strings; VEC5 does not exist", {{"/accessors/3/type", "VEC5"}},
       "accessors[3].type: \"VEC5\" is not an accessor type"},
      {"type given as a number", {{"/accessors/0/type", 3}}, "accessors[0].type: is a JSON number, not a string"},
      {"normalized on FLOAT: tinygltf and the reader ignored the flag, so the file said one thing and drew another",
       {{"/accessors/0/normalized", true}},
       "accessors[0].normalized: true with componentType 5126 (FLOAT)"},
      {"normalized on UNSIGNED_INT is forbidden too (only 8- and 16-bit integers are normalized)",
       {{"/accessors/3/componentType", 5125}, {"/accessors/3/normalized", true}},
       "accessors[3].normalized: true with componentType 5125 (UNSIGNED_INT)"},
      {"normalized as a string", {{"/accessors/0/normalized", "yes"}},
       "accessors[0].normalized: is a JSON string, not a boolean"},
      {"min needs one entry per component of VEC3", {{"/accessors/0/min", {0, 0}}},
       "accessors[0].min: has 2 elements, expected 3"},
      {"tinygltf drops a non-number in max silently", {{"/accessors/0/max", {1, "1", 0}}},
       "accessors[0].max[1]: is a JSON string, not a number"},
      {"bufferView -1 is what tinygltf uses for 'none': the accessor would silently become zeros",
       {{"/accessors/0/bufferView", -1}},
       "accessors[0].bufferView: -1 is negative (schema: minimum 0)"},
      {"2^32 wraps to bufferView 0 in tinygltf's int, a plausible view",
       {{"/accessors/3/bufferView", 4294967296}},
       "accessors[3].bufferView: 4294967296 is out of range (the file has 4 bufferViews)"},
      // Sparse accessors
      {"a sparse part must substitute at least one element", {{"/accessors/2/sparse/count", 0}},
       "accessors[2].sparse.count: 0 is below the minimum (schema: minimum 1)"},
      {"2^32 + 1 wraps to 1 in tinygltf's int, which the loader's own check would then accept",
       {{"/accessors/2/sparse/count", 4294967297}},
       "accessors[2].sparse.count: 4294967297 is more than the accessor's count 3"},
      {"SHORT is signed: sparse indices are 5121, 5123 or 5125 only",
       {{"/accessors/2/sparse/indices/componentType", 5122}},
       "accessors[2].sparse.indices.componentType: 5122 is not an unsigned integer type (schema: one of 5121, 5123, 5125)"},
      {"sparse values at a negative offset", {{"/accessors/2/sparse/values/byteOffset", -12}},
       "accessors[2].sparse.values.byteOffset: -12 is negative (schema: minimum 0)"},
      {"sparse indices in a view that does not exist", {{"/accessors/2/sparse/indices/bufferView", 9}},
       "accessors[2].sparse.indices.bufferView: 9 is out of range (the file has 4 bufferViews)"},
      {"the values part is required (tinygltf refuses it too, naming no accessor)", {{"/accessors/2/sparse/values", removed()}},
       "accessors[2].sparse.values: is missing (schema: required)"},
      // Buffer views and buffers
      {"tinygltf reads a negative bufferView byteOffset as 0", {{"/bufferViews/0/byteOffset", -8}},
       "bufferViews[0].byteOffset: -8 is negative (schema: minimum 0)"},
      {"an empty view: tinygltf accepts byteLength 0", {{"/bufferViews/2/byteLength", 0}},
       "bufferViews[2].byteLength: 0 is below the minimum (schema: minimum 1)"},
      {"byteStride 0 means 'tightly packed' to tinygltf; the schema's minimum is 4",
       {{"/bufferViews/0/byteStride", 0}}, "bufferViews[0].byteStride: 0 is not a multiple of 4 from 4 to 252"},
      {"byteStride one step past the maximum (tinygltf refuses it too, naming no view)",
       {{"/bufferViews/0/byteStride", 256}}, "bufferViews[0].byteStride: 256 is not a multiple of 4 from 4 to 252"},
      {"byteStride 14 is in range but not a multiple of 4 (tinygltf refuses it too, naming no view)", {{"/bufferViews/0/byteStride", 14}},
       "bufferViews[0].byteStride: 14 is not a multiple of 4"},
      {"a negative byteStride is read by tinygltf as absent, i.e. tightly packed",
       {{"/bufferViews/0/byteStride", -12}}, "bufferViews[0].byteStride: -12 is not a multiple of 4"},
      {"tinygltf turns an unknown target into 0 silently", {{"/bufferViews/0/target", 34964}},
       "bufferViews[0].target: 34964 is not ARRAY_BUFFER or ELEMENT_ARRAY_BUFFER (schema: one of 34962, 34963)"},
      {"a view in a buffer that does not exist", {{"/bufferViews/3/buffer", 1}},
       "bufferViews[3].buffer: 1 is out of range (the file has 1 buffer)"},
      {"buffer byteLength 0", {{"/buffers/0/byteLength", 0}},
       "buffers[0].byteLength: 0 is below the minimum (schema: minimum 1)"},
      // Meshes
      {"mode 7 does not exist", {{"/meshes/0/primitives/0/mode", 7}},
       "meshes[0].primitives[0].mode: 7 is not a primitive mode (schema: 0 POINTS to 6 TRIANGLE_FAN)"},
      {"2^32 + 4 wraps to 4 (TRIANGLES) in tinygltf's int and drew as triangles",
       {{"/meshes/0/primitives/0/mode", 4294967300}},
       "meshes[0].primitives[0].mode: 4294967300 is not a primitive mode"},
      {"an index accessor past the end", {{"/meshes/0/primitives/0/indices", 4}},
       "meshes[0].primitives[0].indices: 4 is out of range (the file has 4 accessors)"},
      {"an attribute the loader never reads (TEXCOORD_0) pointing nowhere used to pass",
       {{"/meshes/0/primitives/0/attributes/TEXCOORD_0", 11}},
       "meshes[0].primitives[0].attributes.TEXCOORD_0: 11 is out of range (the file has 4 accessors)"},
      {"a morph target's accessor out of range", {{"/meshes/1/primitives/0/targets", json::array({{{"POSITION", 7}}})}},
       "meshes[1].primitives[0].targets[0].POSITION: 7 is out of range"},
      {"a mesh without primitives (schema: minItems 1)", {{"/meshes/1/primitives", json::array()}},
       "meshes[1].primitives: has 0 elements (schema: minItems 1)"},
      // Nodes and scenes
      {"2^32 wraps to mesh 0 in tinygltf's int: a wrong mesh, drawn",
       {{"/nodes/0/mesh", 4294967296}},
       "nodes[0].mesh: 4294967296 is out of range (the file has 2 meshes)"},
      {"node 3 lies outside the scene, so the loader never looked at its mesh",
       {{"/nodes/3/mesh", 7}}, "nodes[3].mesh: 7 is out of range (the file has 2 meshes)"},
      {"a camera past the end", {{"/nodes/2/camera", 1}}, "nodes[2].camera: 1 is out of range (the file has 1 camera)"},
      {"a skin in a file without skins (the loader reads none, but the id must exist)",
       {{"/nodes/0/skin", 0}}, "nodes[0].skin: 0 is out of range (the file has 0 skins)"},
      {"a child past the end", {{"/nodes/0/children", {1, 5}}},
       "nodes[0].children[1]: 5 is out of range (the file has 4 nodes)"},
      {"the same child twice (schema: uniqueItems)", {{"/nodes/0/children", {1, 1}}},
       "nodes[0].children[1]: 1 is listed twice (schema: uniqueItems)"},
      {"an empty children list (schema: minItems 1)", {{"/nodes/0/children", json::array()}},
       "nodes[0].children: has 0 elements (schema: minItems 1)"},
      {"matrix with 15 numbers", {{"/nodes/1/matrix", std::vector<double>(15, 0.0)}},
       "nodes[1].matrix: has 15 elements, expected 16"},
      {"tinygltf stops at a string in matrix and keeps the 14 numbers before it: the old error said 14 elements",
       {{"/nodes/1/matrix/14", "5"}}, "nodes[1].matrix[14]: is a JSON string, not a number"},
      {"rotation is a quaternion of 4", {{"/nodes/0/rotation", {0, 0, 1}}},
       "nodes[0].rotation: has 3 elements, expected 4"},
      {"a quaternion component above 1 cannot be part of a unit quaternion (the loader normalised it silently)",
       {{"/nodes/0/rotation", {0, 0, 2, 1}}}, "nodes[0].rotation[2]: 2 is above the maximum (schema: maximum 1)"},
      {"scale of 2", {{"/nodes/0/scale", {1, 1}}}, "nodes[0].scale: has 2 elements, expected 3"},
      {"translation of 4", {{"/nodes/0/translation", {1, 2, 3, 4}}}, "nodes[0].translation: has 4 elements, expected 3"},
      {"a scene node past the end", {{"/scenes/0/nodes", {0, 9}}},
       "scenes[0].nodes[1]: 9 is out of range (the file has 4 nodes)"},
      {"a scene listing a node twice", {{"/scenes/0/nodes", {0, 0}}},
       "scenes[0].nodes[1]: 0 is listed twice (schema: uniqueItems)"},
      {"scene -1 is tinygltf's 'no default scene': scene 0 was loaded instead",
       {{"/scene", -1}}, "scene: -1 is negative (schema: minimum 0)"},
      {"a default scene past the end", {{"/scene", 1}}, "scene: 1 is out of range (the file has 1 scene)"},
      // Material factors (the loader clamped them into [0, 1] silently)
      {"metallicFactor above 1", {{"/materials/0/pbrMetallicRoughness/metallicFactor", 1.5}},
       "materials[0].pbrMetallicRoughness.metallicFactor: 1.5 is outside [0, 1]"},
      {"a negative baseColorFactor component", {{"/materials/0/pbrMetallicRoughness/baseColorFactor/3", -0.25}},
       "materials[0].pbrMetallicRoughness.baseColorFactor[3]: -0.25 is below the minimum (schema: minimum 0)"},
      // doubleSided (tinygltf read a value of another type as the default, false: the back faces
      // were culled, unsaid)
      {"doubleSided as the string \"true\" (a hand-written file, a tool writing strings)",
       {{"/materials/0/doubleSided", "true"}}, "materials[0].doubleSided: is a JSON string, not a boolean (schema: boolean)"},
      {"doubleSided as 1 (C habit): no JSON number is a boolean",
       {{"/materials/0/doubleSided", 1}}, "materials[0].doubleSided: is a JSON number, not a boolean (schema: boolean)"},
      {"doubleSided null on a material without pbrMetallicRoughness (its checks stopped there)",
       {{"/materials/0/pbrMetallicRoughness", removed()}, {"/materials/0/doubleSided", nullptr}},
       "materials[0].doubleSided: is a JSON null, not a boolean (schema: boolean)"},
      // Emission (drawn since session 39: tinygltf passed a negative strength or factor through)
      {"an emissiveFactor component above 1 (glTF puts brightness in KHR_materials_emissive_strength)",
       {{"/materials/0/emissiveFactor", json::array({0.5, 2.0, 0.0})}},
       "materials[0].emissiveFactor[1]: 2 is above the maximum (schema: maximum 1)"},
      {"an emissiveFactor of two components", {{"/materials/0/emissiveFactor", json::array({0.5, 0.5})}},
       "materials[0].emissiveFactor: has 2 elements, expected 3"},
      {"a negative emissiveStrength (it would darken the lit colour)",
       {{"/materials/0/extensions", json{{"KHR_materials_emissive_strength", {{"emissiveStrength", -2.0}}}}}},
       "materials[0].extensions.KHR_materials_emissive_strength.emissiveStrength: -2 is below the minimum (schema: minimum 0)"},
      {"emissiveStrength as a string (tinygltf reads it as 0)",
       {{"/materials/0/extensions", json{{"KHR_materials_emissive_strength", {{"emissiveStrength", "4"}}}}}},
       "materials[0].extensions.KHR_materials_emissive_strength.emissiveStrength: is a JSON string, not a number"},
      // Shapes
      {"a top-level array given as an object: tinygltf ignored it, and the error was about accessor 0 missing", {{"/accessors", json::object()}},
       "accessors: is a JSON object, not an array"},
      {"an element that is not an object (tinygltf refuses it too, naming no index)", {{"/bufferViews/2", 44}}, "bufferViews[2]: is a JSON number, not an object"},
  };
}

// Tricky because the base file must load, or every case below would fail for the wrong reason; the
// sparse part and the matrix child must come out as written.
TEST(GltfSchema, TheValidFileLoads) {
  const auto scene = loadGltfFromMemory(bytesOf(json::parse(kValidGltf)), "valid.gltf", {});
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->meshes.size(), 2u);
  EXPECT_EQ(scene->meshes[1].primitives.at(0).positions.at(1), glm::vec3(1, 1, 0));
  EXPECT_EQ(scene->nodes.size(), 3u);  // node 3 is outside the scene
}

// Tricky because each value is wrong in a different way (negative, float, misaligned, zero, past an
// array's end, wrapped by a 32-bit int, wrong enum, wrong length, wrong JSON type), in a field the
// loader reads or points through; each must be refused naming the file and the field.
TEST(GltfSchema, EverySchemaViolationIsRefusedByName) {
  for (const auto& c : schemaCases()) {
    SCOPED_TRACE(c.why);
    const auto result = loadGltfFromMemory(bytesOf(edited(c.edits)), "bad.gltf", {});
    ASSERT_FALSE(result.ok()) << "accepted: " << c.expected;
    const std::string& message = result.error().message;
    EXPECT_EQ(message.rfind("bad.gltf: ", 0), 0u) << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in: " << message;
  }
}

// Tricky because a GLB's JSON arrives through a different path (the container is taken apart and
// rebuilt); the same check must apply to it.
TEST(GltfSchema, GlbJsonChunkIsCheckedToo) {
  const auto good = loadGltfFromMemory(glbOf(json::parse(kValidGltf)), "valid.glb", {});
  ASSERT_TRUE(good.ok()) << good.error().message;
  const auto bad = loadGltfFromMemory(glbOf(edited({{"/bufferViews/0/byteOffset", -8}})), "bad.glb", {});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("bad.glb: GLB JSON chunk: bufferViews[0].byteOffset: -8 is negative"),
            std::string::npos)
      << bad.error().message;
}

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

// Tricky because a check one step too strict would refuse valid files: every value here sits on
// the edge of its range. byteStride 252 (the maximum) between the three positions, a uint16
// accessor at byteOffset 2 (aligned to its 2-byte components, not to 4), a count of 1 (the
// minimum) on a normalized uint8 accessor, a sparse part as long as its accessor with uint8
// indices, mode 6 (TRIANGLE_FAN, the largest mode), a rotation component of exactly -1, material
// factors of exactly 0 and 1, and both bufferView targets.
TEST(GltfSchema, EdgeOfRangeValuesStillLoad) {
  std::vector<std::uint8_t> bin(568, 0);
  const std::vector<glm::vec3> positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (std::size_t i = 0; i < positions.size(); ++i) std::memcpy(bin.data() + i * 252, &positions[i], 12);
  const std::uint16_t indices[4] = {9, 0, 1, 2};  // the accessor skips the first
  std::memcpy(bin.data() + 516, indices, sizeof(indices));
  bin[524] = 255;                                            // the count-1 accessor
  bin[528] = 0, bin[529] = 1, bin[530] = 2;                  // sparse indices: every element
  const std::vector<glm::vec3> sparseValues = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
  std::memcpy(bin.data() + 532, sparseValues.data(), 36);   // sparse values: the positions doubled
  const json document = {
      {"asset", {{"version", "2.0"}}},
      {"nodes", {{{"mesh", 0}, {"rotation", {0, 0, 0, -1}}}}},
      {"materials", {{{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 1}, {"roughnessFactor", 0}}}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"_WEIGHT", 2}}}, {"indices", 1}, {"mode", 6}, {"material", 0}}}}}}},
      {"accessors",
       {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}, {"min", {0, 0, 0}}, {"max", {2, 2, 0}},
         {"sparse", {{"count", 3}, {"indices", {{"bufferView", 3}, {"componentType", 5121}}}, {"values", {{"bufferView", 4}}}}}},
        {{"bufferView", 1}, {"byteOffset", 2}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}},
        {{"bufferView", 2}, {"componentType", 5121}, {"normalized", true}, {"count", 1}, {"type", "SCALAR"}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteLength", 516}, {"byteStride", 252}, {"target", 34962}},
        {{"buffer", 0}, {"byteOffset", 516}, {"byteLength", 8}, {"target", 34963}},
        {{"buffer", 0}, {"byteOffset", 524}, {"byteLength", 1}},
        {{"buffer", 0}, {"byteOffset", 528}, {"byteLength", 3}},
        {{"buffer", 0}, {"byteOffset", 532}, {"byteLength", 36}}}},
      {"buffers", {{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}}},
  };
  const auto scene = loadGltfFromMemory(bytesOf(document), "edge.gltf", {});
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const auto& primitive = scene->meshes.at(0).primitives.at(0);
  ASSERT_EQ(primitive.positions.size(), 3u);
  for (std::size_t i = 0; i < positions.size(); ++i) EXPECT_EQ(primitive.positions[i], sparseValues[i]) << i;
  EXPECT_EQ(primitive.indices, (std::vector<std::uint32_t>{1, 2, 0}));  // the fan (0 1 2) as the spec orders it
}

// Tricky because the check runs on every file: a committed test file or fuzz seed that broke a
// rule would now be refused at the check, and the fuzz mutations of it would never reach the code
// after it. The deliberately broken files are skipped.
TEST(GltfSchema, CommittedFilesAndFuzzSeedsPassTheCheck) {
  int checked = 0;
  for (const auto* folder : {"gltf", "fuzz/gltf_load_fuzz"}) {
    for (const auto& entry : std::filesystem::directory_iterator(kTestData / folder)) {
      const auto extension = entry.path().extension();
      const auto name = entry.path().filename().string();
      if (extension != ".gltf" && extension != ".glb") continue;
      if (name == "empty.gltf" || name == "not_json.gltf" || name == "missing_buffer.gltf" ||
          name == "draco_declares_2e30_faces.glb")
        continue;
      const auto scene = loadGltf(entry.path());
      EXPECT_TRUE(scene.ok()) << scene.error().message;
      ++checked;
    }
  }
  EXPECT_GE(checked, 14);
}

}  // namespace
}  // namespace engine::scene
