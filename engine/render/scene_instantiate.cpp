#include "engine/render/scene_instantiate.h"

#include <cmath>
#include <limits>
#include <map>
#include <utility>
#include <stdexcept>
#include <vector>

#include "engine/render/components.h"
#include "engine/scene/transform.h"

namespace engine::render {
namespace {

// Flat normals (a glTF primitive without NORMAL, MeshPrimitiveData::flatNormals): each triangle
// gets three vertices of its own with its face normal. The shared vertices' smooth normals drew a
// cube as a rounded blob, unlike the SDF baked from it. A triangle without area gets +Y.
MeshHandle addFlat(const scene::MeshPrimitiveData& primitive, MeshPool& pool) {
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> texcoords;
  std::vector<std::uint32_t> indices;
  positions.reserve(primitive.indices.size());
  normals.reserve(primitive.indices.size());
  indices.reserve(primitive.indices.size());
  for (std::size_t t = 0; t + 2 < primitive.indices.size(); t += 3) {
    glm::vec3 corner[3];
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t index = primitive.indices[t + k];
      if (index >= primitive.positions.size()) throw std::out_of_range("instantiateScene: index out of range");
      corner[k] = primitive.positions[index];
      if (!primitive.texcoords.empty()) texcoords.push_back(primitive.texcoords[index]);
    }
    const glm::dvec3 face = glm::cross(glm::dvec3(corner[1] - corner[0]), glm::dvec3(corner[2] - corner[0]));
    const double length = glm::length(face);
    const glm::vec3 normal = length > 0.0 && std::isfinite(length) ? glm::vec3(face / length) : glm::vec3(0, 1, 0);
    for (const glm::vec3& p : corner) {
      indices.push_back(std::uint32_t(positions.size()));
      positions.push_back(p);
      normals.push_back(normal);
    }
  }
  return pool.add(positions, normals, indices, texcoords);
}

void uploadMeshes(const scene::SceneData& data, MeshPool& pool,
                                                   std::vector<std::vector<MeshHandle>>& handles) {
  handles.resize(data.meshes.size());
  for (std::size_t m = 0; m < data.meshes.size(); ++m)
    for (const auto& primitive : data.meshes[m].primitives)
      handles[m].push_back(primitive.flatNormals
                               ? addFlat(primitive, pool)
                               : pool.add(primitive.positions, primitive.normals, primitive.indices, primitive.texcoords,
                                          primitive.tangents));
}

// Each material's textures as one MeshTextures set, made when a primitive first uses it; each
// texture uploaded once per encoding it is read in (a texture may be both a colour and data).
class MaterialSets {
 public:
  MaterialSets(const scene::SceneData& data, MeshTextures& textures) : data_(data), textures_(textures) {}

  // The set of `material` (SceneData::materials index): set 0, the white texels, for a material
  // without textures.
  TextureHandle of(const scene::MaterialData& material, int index) {
    const auto known = sets_.find(index);
    if (known != sets_.end()) return known->second;
    MaterialImages images;
    bool textured = false;
    for (const MaterialTextureKind& kind : kMaterialTextureKinds) {
      images.*kind.image = image(material.*kind.texture, kind.encoding);
      textured = textured || (images.*kind.image).index != 0;
    }
    return sets_[index] = textured ? textures_.addMaterial(images) : TextureHandle{};
  }

 private:
  MeshImageHandle image(int texture, TexelEncoding encoding) {
    if (texture < 0 || std::size_t(texture) >= data_.textures.size()) return {};
    const auto key = std::pair(texture, encoding);
    const auto known = images_.find(key);
    if (known != images_.end()) return known->second;
    return images_[key] = textures_.addImage(data_.textures[std::size_t(texture)], encoding);
  }

  const scene::SceneData& data_;
  MeshTextures& textures_;
  std::map<std::pair<int, TexelEncoding>, MeshImageHandle> images_;
  std::map<int, TextureHandle> sets_;
};

Camera cameraFromData(const scene::CameraData& data) {
  Camera camera{data.yfov, data.znear, data.name};
  if (!data.orthographic) return camera;
  camera.projection = Projection::kOrthographic;
  camera.xmag = data.xmag;
  camera.ymag = data.ymag;
  camera.zfar = data.zfar.value_or(0.0f);  // the importer requires it; 0 is refused by CameraView
  return camera;
}
}  // namespace

InstantiatedScene instantiateScene(const scene::SceneData& data, ecs::Registry& registry, MeshPool& pool) {
  InstantiatedScene result;
  std::vector<std::vector<MeshHandle>> handles;
  uploadMeshes(data, pool, handles);
  MaterialSets materialSets(data, pool.textures());
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());

  for (std::size_t n = 0; n < data.nodes.size(); ++n) {
    const scene::NodeData& node = data.nodes[n];
    const ecs::Entity entity = registry.create();
    result.nodes.push_back(entity);
    registry.emplace<scene::Transform>(entity, scene::fromMatrix(node.local));
    registry.emplace<scene::Name>(entity, scene::Name{node.name});
    if (node.parent >= 0 && std::size_t(node.parent) < n)
      registry.emplace<scene::Parent>(entity, scene::Parent{result.nodes[std::size_t(node.parent)]});
    if (node.camera >= 0 && std::size_t(node.camera) < data.cameras.size()) {
      const scene::CameraData& camera = data.cameras[std::size_t(node.camera)];
      registry.emplace<Camera>(entity, cameraFromData(camera));
      result.cameras.push_back(entity);
    }
    if (node.mesh < 0 || std::size_t(node.mesh) >= data.meshes.size()) continue;
    const scene::MeshData& mesh = data.meshes[std::size_t(node.mesh)];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const scene::MeshPrimitiveData& primitive = mesh.primitives[p];
      MeshRenderable renderable;
      renderable.mesh = handles[std::size_t(node.mesh)][p];
      if (primitive.material >= 0 && std::size_t(primitive.material) < data.materials.size()) {
        const scene::MaterialData& material = data.materials[std::size_t(primitive.material)];
        renderable.color = material.baseColor;
        renderable.roughness = material.roughness;
        renderable.metallic = material.metallic;
        renderable.doubleSided = material.doubleSided;
        renderable.emissive = material.emissive;
        renderable.alphaCutoff = material.alphaCutoff;
        renderable.alphaBlend = material.alphaBlend;
        renderable.occlusionStrength = material.occlusionStrength;
        // Without texture coordinates the textures cannot be read (the importer said so): the factors alone.
        if (!primitive.texcoords.empty()) {
          renderable.textures = materialSets.of(material, primitive.material);
          const bool normalMapped = material.normalTexture >= 0 && std::size_t(material.normalTexture) < data.textures.size();
          renderable.normalScale = normalMapped ? material.normalScale : 0.0f;
        }
      }
      const ecs::Entity part = registry.create();
      registry.emplace<scene::Transform>(part);
      registry.emplace<scene::Parent>(part, scene::Parent{entity});
      registry.emplace<MeshRenderable>(part, renderable);
      result.renderables.push_back(part);
      // What the triangles use (MeshPool::add's bounds): an unused vertex must not frame the scene.
      for (const std::uint32_t index : primitive.indices) {
        const glm::vec3 world = glm::vec3(node.world * glm::vec4(primitive.positions[index], 1.0f));
        lo = glm::min(lo, world);
        hi = glm::max(hi, world);
      }
    }
  }
  if (!result.renderables.empty()) {
    result.boundsMin = lo;
    result.boundsMax = hi;
  }
  return result;
}

}  // namespace engine::render
