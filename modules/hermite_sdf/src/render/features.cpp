#include "hermite_sdf/render/features.h"

#include <memory>

#include "engine/render/mesh_feature.h"
#include "hermite_sdf/render/cell_feature.h"

namespace hsdf {

engine::Status addRenderFeatures(engine::render::Renderer& renderer, const SphereTraceFeature::Options& tracerOptions) {
  ENGINE_TRY(renderer.addFeature(std::make_unique<HermiteCellFeature>()));
  return renderer.addFeature(std::make_unique<SphereTraceFeature>(tracerOptions));
}

engine::Status addSceneFeatures(engine::render::Renderer& renderer, engine::render::MeshPool& meshes,
                                const SphereTraceFeature::Options& tracerOptions) {
  ENGINE_TRY(renderer.addFeature(std::make_unique<engine::render::MeshFeature>(meshes)));
  return addRenderFeatures(renderer, tracerOptions);
}

}  // namespace hsdf
