#include <atomic>
#include <cstdint>

#include <fmt/format.h>

#include "hermite_sdf/renderable.h"

namespace hsdf {
namespace {

std::uint64_t nextAssetId() {
  static std::atomic<std::uint64_t> next{1};
  return next.fetch_add(1);
}

}  // namespace

const char* renderMethodName(RenderMethod method) {
  switch (method) {
    case RenderMethod::Cells: return "cells";
    case RenderMethod::TrilinearSphereTrace: return "trilinear";
    case RenderMethod::HermiteSphereTrace: return "hermite";
  }
  return "?";
}

engine::Expected<std::shared_ptr<const SdfAsset>> makeSdfAssetFromCells(std::string name, CellStream cells) {
  if (auto valid = validateGrid(cells.grid); !valid) return valid.error().withContext("asset '" + name + "'");
  auto asset = std::make_shared<SdfAsset>();
  asset->name = std::move(name);
  asset->id = nextAssetId();
  asset->surfaceBounds = cells.grid.bounds();
  asset->classification.grid = cells.grid;
  for (const CellRecord& r : cells.records)
    (r.cellClass == std::uint16_t(CellClass::Ambiguous) ? asset->classification.stats.ambiguous
                                                        : asset->classification.stats.crossing)++;
  asset->cellsHalf = toHalf(cells);
  asset->cells = std::move(cells);
  return std::shared_ptr<const SdfAsset>(std::move(asset));
}

engine::Expected<std::shared_ptr<const SdfAsset>> makeSdfAsset(std::string name, HermiteField field,
                                                               const Aabb& surfaceBounds,
                                                               const ClassifyOptions& options) {
  auto asset = std::make_shared<SdfAsset>();
  asset->name = std::move(name);
  asset->id = nextAssetId();
  asset->surfaceBounds = surfaceBounds;
  auto classification = classifyCells(field, options);
  if (!classification) return classification.error().withContext("asset '" + asset->name + "'");
  if (const std::uint64_t kept = classification->stats.kept(); kept > options.maxKeptCells)
    return engine::makeError(fmt::format("asset '{}': {} kept cells, over the budget's max kept cells {}", asset->name, kept,
                                         options.maxKeptCells));
  auto cells = extractCells(field, *classification);
  if (!cells) return cells.error().withContext("asset '" + asset->name + "'");
  asset->classification = std::move(classification.value());
  asset->cells = std::move(cells.value());
  asset->cellsHalf = toHalf(asset->cells);
  asset->field = std::move(field);
  return std::shared_ptr<const SdfAsset>(std::move(asset));
}

}  // namespace hsdf
