#pragma once
// A closed box of two materials, as a glTF scene: one mesh of two primitives, the upper part of the
// box (its top and the sides above y = kSplitY) in material 0 (red) and the lower part (the bottom
// and the sides below) in material 1 (blue). The primitives share their vertices along the split,
// so the mesh is closed (pseudonormal signs, as an artist's model would be). Half extents differ per
// axis and the split is off the box's centre, so that no grid of the tests puts the split, a face
// or a medial plane on a sample plane by accident of symmetry.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/scene/scene_data.h"

namespace hsdftest {

inline constexpr glm::vec3 kBoxHalf{1.0f, 0.8f, 0.6f};
inline constexpr float kSplitY = 0.1f;
inline constexpr glm::vec4 kRed{0.9f, 0.08f, 0.05f, 1.0f};
inline constexpr glm::vec4 kBlue{0.05f, 0.1f, 0.9f, 1.0f};

// One primitive: quads (counter-clockwise seen from outside) of `material`.
struct QuadList {
  engine::scene::MeshPrimitiveData primitive;
  void quad(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d) {
    const std::uint32_t base = std::uint32_t(primitive.positions.size());
    primitive.positions.insert(primitive.positions.end(), {a, b, c, d});
    // Wound so that the normal points away from the box's centre (the origin).
    const glm::vec3 n = glm::cross(b - a, c - a);
    const bool outward = glm::dot(n, a + b + c + d) > 0.0f;
    const std::array<std::uint32_t, 6> ccw = {0, 1, 2, 0, 2, 3}, cw = {0, 2, 1, 0, 3, 2};
    for (const std::uint32_t i : outward ? ccw : cw) primitive.indices.push_back(base + i);
    for (int i = 0; i < 4; ++i) primitive.normals.push_back(glm::normalize(outward ? n : -n));
  }
};

// The side quads between heights y0 < y1, then the cap at `capY`, of a box of half extents h.
inline void addBand(QuadList& list, float y0, float y1, float capY, const glm::vec3& h) {
  const glm::vec2 ring[4] = {{-h.x, -h.z}, {h.x, -h.z}, {h.x, h.z}, {-h.x, h.z}};
  for (int s = 0; s < 4; ++s) {
    const glm::vec2 p = ring[s], q = ring[(s + 1) % 4];
    list.quad({p.x, y0, p.y}, {q.x, y0, q.y}, {q.x, y1, q.y}, {p.x, y1, p.y});
  }
  list.quad({ring[0].x, capY, ring[0].y}, {ring[1].x, capY, ring[1].y}, {ring[2].x, capY, ring[2].y},
            {ring[3].x, capY, ring[3].y});
}

// `twoMaterials` false: both primitives use material 0 (a mesh of one material, split the same way).
// `half`: other half extents (a box whose caps are its nearest faces has samples equally close to
// both materials on its medial plane).
inline engine::scene::SceneData twoMaterialBoxScene(bool twoMaterials = true, const glm::vec3& half = kBoxHalf) {
  engine::scene::SceneData scene;
  scene.materials.push_back({"red", kRed, 0.0f, 0.35f});
  scene.materials.push_back({"blue", kBlue, 0.0f, 0.7f});
  QuadList upper, lower;
  addBand(upper, kSplitY, half.y, half.y, half);
  addBand(lower, -half.y, kSplitY, -half.y, half);
  upper.primitive.material = 0;
  lower.primitive.material = twoMaterials ? 1 : 0;
  scene.meshes.push_back({"two_material_box", {upper.primitive, lower.primitive}});
  engine::scene::NodeData node;
  node.name = "box";
  node.mesh = 0;
  scene.nodes.push_back(node);
  return scene;
}

}  // namespace hsdftest
