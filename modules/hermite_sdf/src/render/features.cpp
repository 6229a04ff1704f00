#include "hermite_sdf/render/features.h"

#include <memory>

#include "hermite_sdf/render/cell_feature.h"

namespace hsdf {

engine::Status addRenderFeatures(engine::render::Renderer& renderer, const SphereTraceFeature::Options& tracerOptions) {
  ENGINE_TRY(renderer.addFeature(std::make_unique<HermiteCellFeature>()));
  return renderer.addFeature(std::make_unique<SphereTraceFeature>(tracerOptions));
}

}  // namespace hsdf
