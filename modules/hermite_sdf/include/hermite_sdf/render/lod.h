#pragma once
// Levels of detail for SDF objects: one object baked at K, K/2, K/4, ... from the same
// source through the one bake job, and a per-frame choice of the level from the object's projected
// size, so that the cells' work follows the screen rather than K. A cell of a level whose cells
// cover about `pixelsPerCell` pixels or fewer is drawn; finer levels would only add proxies and
// searches below the pixel scale.
//
// Use: put a HermiteSdfLod beside the entity's HermiteSdfRenderable and WorldTransform, and call
// selectSdfLevels once per frame after the world transforms are updated and before rendering; it
// writes the chosen level's asset into the renderable (the renderers see an ordinary asset).
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "engine/core/expected.h"
#include "engine/ecs/registry.h"
#include "engine/render/camera_view.h"
#include "hermite_sdf/core/bake_job.h"
#include "hermite_sdf/render/renderable.h"

namespace hsdf {

// Switching is allowed only once the wanted level's cells are this factor past the target (coarser:
// at most target / factor pixels a cell; finer: the drawn level over target * factor): an object
// sitting at the threshold keeps its level instead of flickering between two. Each level doubles
// the cell size, so a 15% band never skips a level and never keeps one more than 15% off target.
inline constexpr float kLodHysteresis = 1.15f;
// The coarsest level bakeLodLevels makes: coarser grids lose the shape's features altogether.
inline constexpr int kDefaultLodMinResolution = 16;

// The component. levels[0] is the finest (the K the object was baked at), each next one half its K.
struct HermiteSdfLod {
  std::vector<std::shared_ptr<const SdfAsset>> levels;
  float pixelsPerCell = 2.0f;  // target: the largest on-screen size of a drawn level's cell, in pixels
  std::uint32_t current = 0;   // the level drawn (written by selectSdfLevels; its hysteresis reads it)
};

// Pixels a world length `worldLength` at `distance` covers on an image `viewportHeight` pixels
// tall with vertical field of view fovY (radians). A distance <= 0 (the eye inside) gives +inf.
float projectedPixels(float worldLength, float distance, float fovY, std::uint32_t viewportHeight);
// The same for `camera`'s projection: an orthographic camera shows a length at the same size at
// every distance (CameraView::worldPerPixel), so `distance` only matters to a perspective one.
float projectedPixels(float worldLength, float distance, const engine::render::CameraView& camera,
                      std::uint32_t viewportHeight);

// The largest factor by which `world` stretches an object-space length along an axis (column
// norms): a cell is never drawn larger than this predicts, so a choice made from it errs on the
// finer side.
float largestAxisScale(const glm::mat4& world);

// The level to draw, given each level's projected cell size in pixels (finest first, growing) and
// the level drawn now: the coarsest level within target, with the hysteresis above around `current`.
// No level within target: the finest. Empty input: 0.
std::uint32_t chooseLodLevel(const std::vector<float>& cellPixels, float pixelsPerCell, std::uint32_t current);

// Each level's cell size in pixels for an object placed by `world`: the level's cell spacing times
// the matrix's largest axis scale, seen at the distance from the eye to the object's bounding
// sphere (its finest grid's box). Euclidean distance, not view depth: turning the camera (or
// looking away: an object behind the camera) never switches a level, only moving does.
std::vector<float> levelCellPixels(const HermiteSdfLod& lod, const glm::mat4& world,
                                   const engine::render::CameraView& camera, std::uint32_t viewportHeight);

// The system: for every entity with HermiteSdfLod, HermiteSdfRenderable and WorldTransform, picks
// the level and writes its asset into the renderable. Entities with no levels are left alone.
void selectSdfLevels(engine::ecs::Registry& registry, const engine::render::CameraView& camera,
                     std::uint32_t viewportHeight);

// The settings of the level after `level` (K halved, the rest kept), or nothing when `level` is
// the coarsest bakeLodLevels makes (the next K below minResolution, or no cell inside the padding):
// for callers that bake the levels one job at a time.
std::optional<BakeSettings> coarserLodLevel(const BakeSettings& level, int minResolution = kDefaultLodMinResolution);

// The levels of one object: K = finest.resolution, then K/2, K/4, ... down to minResolution (no
// level below it, and none without a cell inside the padding), each baked by bakeAsset from
// `source` with `finest`'s other settings. `finestAsset`, when given, is level 0 (already baked at
// K: not baked again). Errors: minResolution < 2, and bakeAsset's (naming the level's K).
engine::Expected<std::vector<std::shared_ptr<const SdfAsset>>> bakeLodLevels(
    const BakeSource& source, const BakeSettings& finest, int minResolution = kDefaultLodMinResolution,
    std::shared_ptr<const SdfAsset> finestAsset = nullptr);

}  // namespace hsdf
