#include "hermite_sdf/render/lod.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "engine/scene/transform.h"

namespace hsdf {

float projectedPixels(float worldLength, float distance, float fovY, std::uint32_t viewportHeight) {
  if (!(distance > 0.0f)) return std::numeric_limits<float>::infinity();
  const float pixelsPerUnitAtOne = float(viewportHeight) / (2.0f * std::tan(0.5f * fovY));
  return worldLength * pixelsPerUnitAtOne / distance;
}

float projectedPixels(float worldLength, float distance, const engine::render::CameraView& camera,
                      std::uint32_t viewportHeight) {
  if (!camera.orthographic()) return projectedPixels(worldLength, distance, camera.fovY, viewportHeight);
  return worldLength / camera.worldPerPixel(distance, viewportHeight);
}

namespace {

// The coarsest level whose cells cover at most `limit` pixels; 0 when none does.
std::uint32_t coarsestWithin(const std::vector<float>& cellPixels, float limit) {
  std::uint32_t level = 0;
  for (std::uint32_t i = 0; i < cellPixels.size(); ++i)
    if (cellPixels[i] <= limit) level = i;
  return level;
}

}  // namespace

float largestAxisScale(const glm::mat4& world) {
  return std::max({glm::length(glm::vec3(world[0])), glm::length(glm::vec3(world[1])), glm::length(glm::vec3(world[2]))});
}

std::uint32_t chooseLodLevel(const std::vector<float>& cellPixels, float pixelsPerCell, std::uint32_t current) {
  if (cellPixels.empty()) return 0;
  // Going coarser needs the target beaten by the hysteresis factor; staying only needs the drawn
  // level within target * factor. Levels between the two choices keep what is drawn.
  const std::uint32_t strict = coarsestWithin(cellPixels, pixelsPerCell / kLodHysteresis);
  const std::uint32_t lenient = coarsestWithin(cellPixels, pixelsPerCell * kLodHysteresis);
  return std::clamp(current, strict, lenient);
}

std::vector<float> levelCellPixels(const HermiteSdfLod& lod, const glm::mat4& world,
                                   const engine::render::CameraView& camera, std::uint32_t viewportHeight) {
  std::vector<float> pixels;
  if (lod.levels.empty() || !lod.levels.front()) return pixels;
  const float scale = largestAxisScale(world);
  const Aabb box = lod.levels.front()->cells.grid.bounds();
  const glm::vec3 center = glm::vec3(world * glm::vec4(glm::vec3(box.center()), 1.0f));
  const float radius = scale * 0.5f * float(glm::length(box.size()));
  const float distance = glm::length(camera.position - center) - radius;
  for (const std::shared_ptr<const SdfAsset>& level : lod.levels) {
    const float cell = scale * float(level ? level->cells.grid.spacing : 0.0);
    pixels.push_back(projectedPixels(cell, distance, camera, viewportHeight));
  }
  return pixels;
}

void selectSdfLevels(engine::ecs::Registry& registry, const engine::render::CameraView& camera,
                     std::uint32_t viewportHeight) {
  registry.view<HermiteSdfLod, HermiteSdfRenderable, engine::scene::WorldTransform>().each(
      [&](engine::ecs::Entity, HermiteSdfLod& lod, HermiteSdfRenderable& renderable,
          const engine::scene::WorldTransform& world) {
        if (lod.levels.empty()) return;
        const std::vector<float> pixels = levelCellPixels(lod, world.matrix, camera, viewportHeight);
        lod.current = chooseLodLevel(pixels, lod.pixelsPerCell, std::min<std::uint32_t>(lod.current, std::uint32_t(pixels.size() - 1)));
        if (lod.levels[lod.current]) renderable.asset = lod.levels[lod.current];
      });
}

namespace {

// A level needs K >= minResolution and at least one cell inside the padding (fitGrid).
bool isLodLevel(const BakeSettings& level, int minResolution) {
  return level.resolution >= minResolution && level.resolution - 1 - 2 * level.padding >= 1;
}

}  // namespace

std::optional<BakeSettings> coarserLodLevel(const BakeSettings& level, int minResolution) {
  BakeSettings coarser = level;
  coarser.resolution /= 2;
  if (!isLodLevel(coarser, minResolution)) return std::nullopt;
  return coarser;
}

engine::Expected<std::vector<std::shared_ptr<const SdfAsset>>> bakeLodLevels(const BakeSource& source,
                                                                             const BakeSettings& finest, int minResolution,
                                                                             std::shared_ptr<const SdfAsset> finestAsset) {
  if (minResolution < 2)
    return engine::makeError(fmt::format("levels of detail: the coarsest level's K must be at least 2 (got {})", minResolution));
  ENGINE_TRY_ASSIGN(PreparedSource prepared, prepareSource(source, finest));
  std::vector<std::shared_ptr<const SdfAsset>> levels;
  BakeSettings settings = finest;
  if (finestAsset) {
    levels.push_back(std::move(finestAsset));
    settings.resolution /= 2;
  }
  for (; isLodLevel(settings, minResolution); settings.resolution /= 2) {
    auto level = bakeAsset(prepared, settings);
    if (!level) return level.error().withContext(fmt::format("levels of detail: level K = {}", settings.resolution));
    levels.push_back(std::move(*level));
  }
  return levels;
}

}  // namespace hsdf
