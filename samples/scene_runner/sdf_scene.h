#pragma once
// Turning the scene's triangle meshes into an SDF object: bake (mesh -> Hermite field -> cells)
// and the entity that draws it.
#include <memory>

#include "engine/core/expected.h"
#include "engine/ecs/registry.h"
#include "engine/scene/scene_data.h"
#include "hermite_sdf/renderable.h"
#include "runner_options.h"

namespace runner {

// Bakes every mesh instance of the scene (world space) into one asset, printing progress.
engine::Expected<std::shared_ptr<const hsdf::SdfAsset>> bakeSceneSdf(const engine::scene::SceneData& data,
                                                                     int resolution, int padding);

// Loads a .hsdf file: its dense field (re-classified) when present, else its cells.
engine::Expected<std::shared_ptr<const hsdf::SdfAsset>> loadSdfFile(const std::filesystem::path& path);

// The component the options ask for (method, subdivisions, refinement, normals, precision).
hsdf::HermiteSdfRenderable renderableFromOptions(const Options& options, std::shared_ptr<const hsdf::SdfAsset> asset);

// An entity drawing `asset` translated by `offset`.
engine::ecs::Entity addSdfEntity(engine::ecs::Registry& registry, const hsdf::HermiteSdfRenderable& renderable,
                                 const glm::vec3& offset);

}  // namespace runner
