#pragma once
// Render components: plain structs on entities. Positions come from engine::scene::WorldTransform.
#include <cstdint>
#include <optional>
#include <string>

#include <glm/glm.hpp>

namespace engine::render {

// A mesh uploaded into the MeshPool.
struct MeshHandle {
  std::uint32_t index = ~0u;
  bool valid() const { return index != ~0u; }
};

// A material's textures in MeshTextures (MeshPool::textures): one descriptor set; 0: none (white
// texels, the factors alone).
struct TextureHandle {
  std::uint32_t index = 0;
};

struct MeshRenderable {
  MeshHandle mesh;
  glm::vec4 color{0.8f, 0.8f, 0.8f, 1.0f};  // linear base colour
  float roughness = 0.5f;
  float metallic = 0.0f;
  // Both sides drawn (glTF material doubleSided): no back-face culling, and a back face lit with
  // its normal reversed (MeshFeature). False: back faces are culled.
  bool doubleSided = false;
  glm::vec3 emissive{0.0f};  // linear light given off, added to the lit colour (glTF emission)
  // Read through the mesh's texture coordinates (glTF's material textures): the base colour texture
  // multiplies `color`, the metallic-roughness one `roughness` and `metallic`, the emissive one
  // `emissive`; the occlusion one darkens the ambient light, by `occlusionStrength`; the normal one
  // tilts the shading normal, by `normalScale`.
  TextureHandle textures;
  float occlusionStrength = 1.0f;  // glTF occlusionTexture.strength: 0 none, 1 the texel's full occlusion
  // glTF normalTexture.scale when `textures` holds a normal texture (its x and y times this); 0: the
  // vertex normals, no normal texture read.
  float normalScale = 0.0f;
  // Where the alpha (color.a times the texture's) is below this, the surface is cut out: nothing
  // drawn, what lies behind seen (glTF alphaMode MASK). None: opaque.
  std::optional<float> alphaCutoff;
  // Blended over what lies behind it by its alpha (color.a times the texture's; glTF alphaMode
  // BLEND): a glass pane, a tinted visor. Drawn after every opaque surface, in no depth prepass
  // (MeshFeature), alphaCutoff unused. False: opaque (or cut out by alphaCutoff).
  bool alphaBlend = false;
};

enum class Projection { kPerspective, kOrthographic };

// A camera looking down its local -Z axis. Perspective: reverse-Z with an infinite far plane.
// Orthographic: reverse-Z between znear and zfar; the view is 2 ymag world units tall and as wide
// as the image's aspect makes it (xmag is kept from the file but the viewport's aspect wins, as
// fovY's does for a perspective camera).
struct Camera {
  float fovY = 0.8f;     // radians (perspective)
  float znear = 0.05f;   // > 0 perspective, >= 0 orthographic
  std::string name;      // the camera's own name (glTF cameras[i].name), beside its node's
  Projection projection = Projection::kPerspective;
  float xmag = 1.0f;     // orthographic half extents, world units
  float ymag = 1.0f;
  float zfar = 0.0f;     // orthographic far plane (> znear); unused by a perspective camera
};

}  // namespace engine::render
