#include <atomic>

#include "hermite_sdf/renderable.h"

namespace hsdf {

const char* renderMethodName(RenderMethod method) {
  switch (method) {
    case RenderMethod::Cells: return "cells";
    case RenderMethod::TrilinearSphereTrace: return "trilinear";
    case RenderMethod::HermiteSphereTrace: return "hermite";
  }
  return "?";
}

engine::Expected<std::shared_ptr<const SdfAsset>> makeSdfAsset(std::string name, HermiteField field,
                                                               const Aabb& surfaceBounds,
                                                               const ClassifyOptions& options) {
  static std::atomic<std::uint64_t> nextId{1};
  auto asset = std::make_shared<SdfAsset>();
  asset->name = std::move(name);
  asset->id = nextId.fetch_add(1);
  asset->surfaceBounds = surfaceBounds;
  auto classification = classifyCells(field, options);
  if (!classification) return classification.error().withContext("asset '" + asset->name + "'");
  auto cells = extractCells(field, *classification);
  if (!cells) return cells.error().withContext("asset '" + asset->name + "'");
  asset->classification = std::move(classification.value());
  asset->cells = std::move(cells.value());
  asset->cellsHalf = toHalf(asset->cells);
  asset->field = std::move(field);
  return std::shared_ptr<const SdfAsset>(std::move(asset));
}

}  // namespace hsdf
