#pragma once
// Render components: plain structs on entities. Positions come from engine::scene::WorldTransform.
#include <cstdint>
#include <string>

#include <glm/glm.hpp>

namespace engine::render {

// A mesh uploaded into the MeshPool.
struct MeshHandle {
  std::uint32_t index = ~0u;
  bool valid() const { return index != ~0u; }
};

struct MeshRenderable {
  MeshHandle mesh;
  glm::vec4 color{0.8f, 0.8f, 0.8f, 1.0f};  // linear base colour
  float roughness = 0.5f;
  float metallic = 0.0f;
  // Both sides drawn (glTF material doubleSided): no back-face culling, and a back face lit with
  // its normal reversed (MeshFeature). False: back faces are culled.
  bool doubleSided = false;
};

// A perspective camera looking down its local -Z axis.
struct Camera {
  float fovY = 0.8f;     // radians
  float znear = 0.05f;   // the projection is infinite (reverse-Z)
  std::string name;      // the camera's own name (glTF cameras[i].name), beside its node's
};

}  // namespace engine::render
