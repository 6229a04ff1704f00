#pragma once
// CPU-side scene description produced by the glTF importer: plain data, no GPU handles, no ECS.
// The renderer turns it into entities (engine/render/scene_instantiate.h); tools such as
// hsdf_bake flatten it into world-space triangles.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/expected.h"
#include "engine/scene/animation.h"

namespace engine::scene {

struct MeshPrimitiveData {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;     // same count as positions (area-weighted smooth ones when the file has none)
  std::vector<std::uint32_t> indices; // triangle list
  std::vector<glm::vec2> texcoords;   // TEXCOORD_0 through the KHR_texture_transform of the material; as many as positions, or none
  // TANGENT: xyz toward +u, w = +-1 the handedness (glTF: bitangent = cross(normal, xyz) * w); as many
  // as positions, or none (the normal texture's frame then comes from the screen derivatives). Made
  // at load for a normal-mapped primitive whose file has none (engine/scene/tangents.h).
  std::vector<glm::vec4> tangents;
  int material = -1;                  // index into SceneData::materials, -1 for the default
  // The file gave no normals: glTF asks for flat ones, each triangle's own. The triangles keep their
  // shared vertices (an SDF's closedness and pseudonormals need them); the drawn mesh gives each
  // triangle its face normal (render::instantiateScene).
  bool flatNormals = false;
};

struct MeshData {
  std::string name;
  std::vector<MeshPrimitiveData> primitives;
};

struct MaterialData {
  std::string name;
  glm::vec4 baseColor{0.8f, 0.8f, 0.8f, 1.0f};
  float metallic = 0.0f;
  float roughness = 0.5f;
  // glTF `doubleSided` (default false): both sides of each triangle are drawn, a back face lit
  // with its normal reversed. False: back faces are culled (a closed mesh's inside is never seen).
  bool doubleSided = false;
  // Light the surface gives off (linear RGB), added to its lit colour: glTF emissiveFactor times
  // KHR_materials_emissive_strength's emissiveStrength (so it may exceed 1). Zero: none.
  glm::vec3 emissive{0.0f};
  // SceneData::textures indices of the material's textures, all read through TEXCOORD_0; -1: none.
  // glTF baseColorTexture (sRGB): multiplies baseColor.
  int baseColorTexture = -1;
  // glTF metallicRoughnessTexture (linear): its green multiplies roughness, its blue metallic.
  int metallicRoughnessTexture = -1;
  // glTF occlusionTexture (linear): its red is how much of the ambient light reaches the surface,
  // applied by occlusionStrength (1 + strength * (red - 1)).
  int occlusionTexture = -1;
  float occlusionStrength = 1.0f;
  // glTF emissiveTexture (sRGB): multiplies emissive.
  int emissiveTexture = -1;
  // glTF normalTexture (linear): the shading normal in the surface's tangent frame, its x and y
  // times normalScale.
  int normalTexture = -1;
  float normalScale = 1.0f;
  // glTF alphaMode MASK: where the alpha (baseColor's times the texture's) is below the cutoff,
  // the surface is not there (a leaf card, a fence, a grille). None: opaque (OPAQUE) or blended
  // (BLEND).
  std::optional<float> alphaCutoff;
  // glTF alphaMode BLEND: the surface is blended over what lies behind it by its alpha, baseColor's
  // times the texture's (a glass pane). False: OPAQUE (the alpha is not used) or MASK.
  bool alphaBlend = false;
};

// How a texture is sampled (a glTF sampler).
enum class TextureFilter : std::uint8_t { Nearest, Linear };
enum class TextureWrap : std::uint8_t { Repeat, ClampToEdge, MirroredRepeat };

// A decoded texture image with its sampler.
struct TextureData {
  std::string name;                // the image's name, else "image N"
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<std::uint8_t> rgba;  // sRGB-encoded RGBA8, first row first: texture coordinate (0, 0) is the first texel's corner
  TextureFilter magFilter = TextureFilter::Linear;
  TextureFilter minFilter = TextureFilter::Linear;
  bool mipmaps = true;             // false: glTF minFilter NEAREST or LINEAR, the full-size image only
  TextureFilter mipmapFilter = TextureFilter::Linear;
  TextureWrap wrapS = TextureWrap::Repeat;
  TextureWrap wrapT = TextureWrap::Repeat;
};

struct CameraData {
  std::string name;
  bool orthographic = false;         // glTF "orthographic": xmag/ymag/zfar; else "perspective": yfov
  float yfov = 0.8f;                 // radians (perspective)
  float xmag = 1.0f;                 // half width / height of the view, world units (orthographic)
  float ymag = 1.0f;
  float znear = 0.05f;               // > 0 (perspective), >= 0 (orthographic)
  std::optional<float> zfar;         // none: infinite projection (perspective only)
  std::optional<float> aspectRatio;
};

struct NodeData {
  std::string name;
  int parent = -1;
  glm::mat4 local{1.0f};
  glm::mat4 world{1.0f};             // product of the parents' local matrices and this one
  int mesh = -1;
  int camera = -1;
  std::string extras;                // the node's `extras` as JSON text; empty when it has none
};

struct SceneData {
  std::vector<MeshData> meshes;
  std::vector<MaterialData> materials;
  std::vector<TextureData> textures;  // those the materials use, each decoded once
  std::vector<CameraData> cameras;
  std::vector<NodeData> nodes;       // parents come before their children
  std::vector<AnimationData> animations;  // node animations (channels name `nodes` indices); posed by scene_pose.h
  std::vector<std::string> warnings; // what the importer skipped or ignored (also logged)
};

// The base colour of `material` (an index into scene.materials), else a default material's: how
// a primitive without a material is drawn, as triangles or as the SDF standing for it.
inline glm::vec4 baseColorOf(const SceneData& scene, int material) {
  return material >= 0 && std::size_t(material) < scene.materials.size() ? scene.materials[std::size_t(material)].baseColor
                                                                          : MaterialData{}.baseColor;
}

// World-space triangles of every mesh instance in a scene.
struct TriangleSoup {
  std::vector<glm::vec3> positions;
  std::vector<std::uint32_t> indices;
  // flattenTriangles: the SceneData::nodes index of each triangle's instance (indices.size() / 3
  // entries), so that a hit on the soup names its object; empty for soups built otherwise.
  std::vector<std::uint32_t> triangleNodes;
  // flattenTriangles: the SceneData::materials index of each triangle's primitive (-1: the default
  // material), indices.size() / 3 entries, so that a baked surface can keep its primitives'
  // materials; empty for soups built otherwise.
  std::vector<std::int32_t> triangleMaterials;
};

}  // namespace engine::scene
