#include "hermite_sdf/core/materials.h"

#include <cmath>
#include <unordered_map>

#include <fmt/format.h>

namespace hsdf {
namespace {

bool isFinite(const SdfMaterial& m) {
  return std::isfinite(m.baseColor.r) && std::isfinite(m.baseColor.g) && std::isfinite(m.baseColor.b) &&
         std::isfinite(m.baseColor.a) && std::isfinite(m.roughness) && std::isfinite(m.metallic);
}

}  // namespace

SdfMaterial sdfMaterialOf(const engine::scene::SceneData& scene, int material) {
  const bool known = material >= 0 && std::size_t(material) < scene.materials.size();
  const engine::scene::MaterialData data = known ? scene.materials[std::size_t(material)] : engine::scene::MaterialData{};
  return {data.baseColor, data.roughness, data.metallic};
}

engine::Expected<MeshMaterials> meshMaterials(const engine::scene::TriangleSoup& soup,
                                              const engine::scene::SceneData& scene) {
  if (soup.triangleMaterials.empty()) return MeshMaterials{};
  const std::size_t triangles = soup.indices.size() / 3;
  if (soup.triangleMaterials.size() != triangles)
    return engine::makeError(fmt::format("materials: {} per-triangle materials for {} triangles",
                                         soup.triangleMaterials.size(), triangles));
  // Slots in order of first use: the same mesh gives the same slots however often it is baked.
  std::unordered_map<std::int32_t, std::size_t> slotOf;
  std::vector<std::int32_t> used;
  for (const std::int32_t material : soup.triangleMaterials)
    if (slotOf.emplace(material, used.size()).second) used.push_back(material);
  if (used.size() < 2) return MeshMaterials{};
  if (used.size() > kMaxMaterialSlots)
    return engine::makeError(fmt::format("materials: the mesh uses {} materials, more than the {} an SDF asset can "
                                         "hold (one byte per sample); merge materials or split the mesh",
                                         used.size(), kMaxMaterialSlots));
  MeshMaterials out;
  for (const std::int32_t material : used) out.palette.push_back(sdfMaterialOf(scene, material));
  out.triangleSlots.reserve(triangles);
  for (const std::int32_t material : soup.triangleMaterials) out.triangleSlots.push_back(MaterialSlot(slotOf[material]));
  return out;
}

engine::Status checkMaterialSlots(const std::vector<SdfMaterial>& palette, std::span<const MaterialSlot> slots,
                                  const char* what) {
  if (palette.empty()) {
    if (!slots.empty()) return engine::makeError(fmt::format("{} has material slots but there is no palette", what));
    return {};
  }
  if (palette.size() < 2 || palette.size() > kMaxMaterialSlots)
    return engine::makeError(fmt::format("a palette of {} materials (a multi-material asset has 2..{})", palette.size(),
                                         kMaxMaterialSlots));
  for (std::size_t i = 0; i < palette.size(); ++i)
    if (!isFinite(palette[i])) return engine::makeError(fmt::format("palette entry {} is not finite", i));
  for (std::size_t i = 0; i < slots.size(); ++i)
    if (slots[i] >= palette.size())
      return engine::makeError(fmt::format("{}: material slot {} at entry {} is past the palette's {} entries", what,
                                           int(slots[i]), i, palette.size()));
  return {};
}

}  // namespace hsdf
