#include <atomic>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>

#include "cells/cell_derived.h"
#include "hermite_sdf/core/normal_cone.h"
#include "hermite_sdf/core/sdf_asset.h"

namespace hsdf {
namespace {

std::uint64_t nextAssetId() {
  static std::atomic<std::uint64_t> next{1};
  return next.fetch_add(1);
}

bool isFinite(const HermiteSample& s) {
  return std::isfinite(s.f) && std::isfinite(s.fx) && std::isfinite(s.fy) && std::isfinite(s.fz);
}

// A field from a file or a user's generator (the bake already refuses non-finite sources): NaN or
// infinity would reach the shaders, where comparisons with NaN are false and a search can run on
// garbage. The error names the first bad sample.
engine::Status checkFiniteSamples(const HermiteField& field) {
  ENGINE_TRY(validateGrid(field.grid));
  if (field.samples.size() != field.grid.sampleCount())
    return engine::makeError(fmt::format("{} samples for a grid of {}^3", field.samples.size(), field.grid.resolution));
  const int k = field.grid.resolution;
  for (std::size_t index = 0; index < field.samples.size(); ++index) {
    const HermiteSample& s = field.samples[index];
    if (isFinite(s)) continue;
    const int i = int(index % std::size_t(k)), j = int(index / std::size_t(k) % std::size_t(k)),
              l = int(index / (std::size_t(k) * std::size_t(k)));
    return engine::makeError(fmt::format("sample ({}, {}, {}) is not finite (f {}, gradient [{}, {}, {}])", i, j, l,
                                         s.f, s.fx, s.fy, s.fz));
  }
  return {};
}

engine::Status checkFiniteRecords(const CellStream& cells) {
  for (const CellRecord& r : cells.records)
    for (std::size_t c = 0; c < r.corners.size(); ++c)
      if (!isFinite(r.corners[c]))
        return engine::makeError(fmt::format("cell ({}, {}, {}) corner {} is not finite (f {}, gradient [{}, {}, {}])",
                                             r.x, r.y, r.z, c, r.corners[c].f, r.corners[c].fx, r.corners[c].fy,
                                             r.corners[c].fz));
  return {};
}

// The slots of every corner of the stream, flattened for checkMaterialSlots.
std::span<const MaterialSlot> cornerSlots(const CellStream& cells) {
  return {cells.materials.empty() ? nullptr : cells.materials.front().data(), cells.materials.size() * 8};
}

// A multi-material asset's slots and palette (materials.h): slots beside every record (and every
// dense sample, where there is a field) exactly when there is a palette, each within it.
engine::Status checkMaterials(const CellStream& cells, const HermiteField* field, const std::vector<SdfMaterial>& palette) {
  if (!palette.empty() && cells.materials.size() != cells.records.size())
    return engine::makeError(fmt::format("{} material slot entries for {} cell records", cells.materials.size(),
                                         cells.records.size()));
  ENGINE_TRY(checkMaterialSlots(palette, cornerSlots(cells), "cells"));
  if (field == nullptr || field->samples.empty()) return {};
  if (!palette.empty() && field->materials.size() != field->samples.size())
    return engine::makeError(fmt::format("{} material slots for {} field samples", field->materials.size(),
                                         field->samples.size()));
  return checkMaterialSlots(palette, field->materials, "field");
}

// What every asset derives from its fp32 records, whichever way they were made. Errors:
// "cancelled" (the token).
engine::Status deriveFromCells(SdfAsset& asset, unsigned threads, const engine::CancelToken* cancel) {
  asset.cellsHalf = toHalf(asset.cells);
  asset.boundaryPositive = boundaryIsPositive(asset.cells);
  asset.proxyBoxes = proxyBoxCodes(asset.cells);
  asset.proxyBoxesHalf = proxyBoxCodes(asset.cellsHalf);
  ENGINE_TRY_ASSIGN(asset.derived, deriveCellData(asset.cells, threads, cancel));
  return {};
}

}  // namespace

engine::Expected<std::shared_ptr<const SdfAsset>> makeSdfAssetFromCells(std::string name, CellStream cells,
                                                                        std::vector<SdfMaterial> palette) {
  if (auto valid = validateGrid(cells.grid); !valid) return valid.error().withContext("asset '" + name + "'");
  if (auto finite = checkFiniteRecords(cells); !finite) return finite.error().withContext("asset '" + name + "'");
  if (auto materials = checkMaterials(cells, nullptr, palette); !materials)
    return materials.error().withContext("asset '" + name + "'");
  auto asset = std::make_shared<SdfAsset>();
  asset->name = std::move(name);
  asset->id = nextAssetId();
  asset->surfaceBounds = cells.grid.bounds();
  asset->classification.grid = cells.grid;
  for (const CellRecord& r : cells.records)
    (r.cellClass == std::uint16_t(CellClass::Ambiguous) ? asset->classification.stats.ambiguous
                                                        : asset->classification.stats.crossing)++;
  asset->cells = std::move(cells);
  asset->palette = std::move(palette);
  if (auto derived = deriveFromCells(*asset, 0, nullptr); !derived)
    return derived.error().withContext("asset '" + asset->name + "'");
  return std::shared_ptr<const SdfAsset>(std::move(asset));
}

engine::Expected<std::shared_ptr<const SdfAsset>> makeSdfAssetFromSparseBake(std::string name, CellStream cells,
                                                                             const CellStats& stats, int refineDepth,
                                                                             const Aabb& surfaceBounds,
                                                                             std::vector<SdfMaterial> palette,
                                                                             unsigned threads,
                                                                             const engine::CancelToken* cancel) {
  if (auto valid = validateGrid(cells.grid); !valid) return valid.error().withContext("asset '" + name + "'");
  if (auto finite = checkFiniteRecords(cells); !finite) return finite.error().withContext("asset '" + name + "'");
  if (auto materials = checkMaterials(cells, nullptr, palette); !materials)
    return materials.error().withContext("asset '" + name + "'");
  if (cells.records.size() != stats.kept())
    return engine::makeError(fmt::format("asset '{}': {} cell records but the counts say {} kept cells", name,
                                         cells.records.size(), stats.kept()));
  auto asset = std::make_shared<SdfAsset>();
  asset->name = std::move(name);
  asset->id = nextAssetId();
  asset->surfaceBounds = surfaceBounds;
  asset->field.grid = cells.grid;
  asset->classification.grid = cells.grid;
  asset->classification.stats = stats;
  asset->classification.refineDepth = refineDepth;
  asset->cells = std::move(cells);
  asset->palette = std::move(palette);
  if (auto derived = deriveFromCells(*asset, threads, cancel); !derived)
    return derived.error().withContext("asset '" + asset->name + "'");
  return std::shared_ptr<const SdfAsset>(std::move(asset));
}

engine::Expected<std::shared_ptr<const SdfAsset>> makeSdfAsset(std::string name, HermiteField field,
                                                               const Aabb& surfaceBounds,
                                                               const ClassifyOptions& options,
                                                               std::vector<SdfMaterial> palette) {
  auto asset = std::make_shared<SdfAsset>();
  asset->name = std::move(name);
  asset->id = nextAssetId();
  asset->surfaceBounds = surfaceBounds;
  if (auto finite = checkFiniteSamples(field); !finite) return finite.error().withContext("asset '" + asset->name + "'");
  auto classification = classifyCells(field, options);
  if (!classification) return classification.error().withContext("asset '" + asset->name + "'");
  if (const std::uint64_t kept = classification->stats.kept(); kept > options.maxKeptCells)
    return engine::makeError(fmt::format("asset '{}': {} kept cells, over the budget's max kept cells {}", asset->name, kept,
                                         options.maxKeptCells));
  auto cells = extractCells(field, *classification);
  if (!cells) return cells.error().withContext("asset '" + asset->name + "'");
  if (auto materials = checkMaterials(*cells, &field, palette); !materials)
    return materials.error().withContext("asset '" + asset->name + "'");
  asset->classification = std::move(classification.value());
  asset->cells = std::move(cells.value());
  asset->palette = std::move(palette);
  if (auto derived = deriveFromCells(*asset, options.threads, options.cancel); !derived)
    return derived.error().withContext("asset '" + asset->name + "'");
  asset->field = std::move(field);
  return std::shared_ptr<const SdfAsset>(std::move(asset));
}

}  // namespace hsdf
