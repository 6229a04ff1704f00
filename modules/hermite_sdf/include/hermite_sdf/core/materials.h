#pragma once
// Multi-material SDF objects: a baked mesh keeps the materials of its primitives.
//
// A mesh whose triangles use two or more materials is baked with a material *slot* per grid
// sample: the slot of the material of the sample's closest triangle (the triangle the distance
// query finds: of the equally close ones the lowest in the BVH's order, the same rule that picks
// the gradient, so the bake stays deterministic whatever the thread schedule). A slot is a small
// index (uint8) into the asset's *palette*: per slot the source material's base colour, roughness
// and metallic factor. The kept cells carry their 8 corners' slots (CellMaterialSlots, 8 bytes a
// record, fp32 and fp16 streams alike).
//
// A mesh of one material bakes no slots and no palette: nothing changes (same bytes, same images,
// same memory) and the entity's own colour shades it, as before.
//
// Shading rule, the same for every method: the colour at a hit is the palette entry of the grid
// sample nearest to the hit (for a cell: its nearest corner, nearestCorner below; for the dense
// tracers: the nearest sample of the dense grid -- the same sample). The entity's colour
// (HermiteSdfRenderable::color) multiplies the palette colour, so white shows the materials as
// authored; the roughness is the palette entry's, as the mesh draws it.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/expected.h"
#include "engine/scene/scene_data.h"

namespace hsdf {

// What the shading of a palette entry uses (shaders/shared/host_device.h, ObjectData: color and
// material.x = roughness, material.y = metallic).
struct SdfMaterial {
  glm::vec4 baseColor{0.8f, 0.8f, 0.8f, 1.0f};  // linear
  float roughness = 0.5f;
  float metallic = 0.0f;
  bool operator==(const SdfMaterial&) const = default;
};

using MaterialSlot = std::uint8_t;
// A slot is one byte: at most 256 materials in one asset.
inline constexpr std::size_t kMaxMaterialSlots = 256;
// The slots of a cell's 8 corners, corner index x + 2y + 4z (as CellRecord::corners).
using CellMaterialSlots = std::array<MaterialSlot, 8>;

// The materials of a triangle mesh: the palette and each input triangle's slot in it. Both empty
// when the mesh uses fewer than two materials.
struct MeshMaterials {
  std::vector<SdfMaterial> palette;
  std::vector<MaterialSlot> triangleSlots;  // one per triangle (indices.size() / 3)
  bool empty() const { return palette.empty(); }
};

// The palette entry of a glTF material (a material index of -1 or out of range: the default
// material, as the mesh feature draws it).
SdfMaterial sdfMaterialOf(const engine::scene::SceneData& scene, int material);

// The materials of a soup made by flattenTriangles (TriangleSoup::triangleMaterials): slots in the
// order the materials first appear. Empty when the soup uses one material or carries none. Error
// when it uses more than kMaxMaterialSlots materials (naming both counts) or the per-triangle list
// does not match the triangles.
engine::Expected<MeshMaterials> meshMaterials(const engine::scene::TriangleSoup& soup,
                                              const engine::scene::SceneData& scene);

// Checks slots against a palette: slots present only with a palette of 2..kMaxMaterialSlots
// entries, every slot below the palette size, finite material values. `what` names the slots in
// the error ("field", "cells").
engine::Status checkMaterialSlots(const std::vector<SdfMaterial>& palette, std::span<const MaterialSlot> slots,
                                  const char* what);

// The corner (x + 2y + 4z) of a cell nearest to the cell-local point u in [0,1]^3: a coordinate
// of 0.5 or more goes to the upper corner. The shaders use the same rule
// (hermite/materials.glsl, nearestCorner).
inline int nearestCorner(const glm::dvec3& u) {
  return (u.x >= 0.5 ? 1 : 0) + (u.y >= 0.5 ? 2 : 0) + (u.z >= 0.5 ? 4 : 0);
}

}  // namespace hsdf
