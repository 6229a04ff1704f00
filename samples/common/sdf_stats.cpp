#include "sdf_stats.h"

#include <fmt/format.h>

namespace samples {

SdfStats sdfStats(const hsdf::SdfAsset& asset) {
  SdfStats stats;
  const std::uint64_t k = std::uint64_t(asset.cells.grid.resolution);
  stats.resolution = int(k);
  stats.cells = asset.classification.stats;
  stats.cellScalars = asset.cells.stored_scalars();
  stats.cellBytes = asset.cells.stored_bytes();
  stats.cellBytesHalf = asset.cellsHalf.stored_bytes();
  stats.trilinearScalars = k * k * k;
  stats.hermiteScalars = 4 * k * k * k;
  stats.denseField = !asset.field.samples.empty();
  return stats;
}

std::string describeSdfStats(const SdfStats& s) {
  if (!s.denseField)
    return fmt::format("K {}: cells {} crossing / {} ambiguous / {} empty; stored scalars: cells {}; no dense field "
                       "(the tracers would store trilinear {}, hermite {})",
                       s.resolution, s.cells.crossing, s.cells.ambiguous, s.cells.empty, s.cellScalars,
                       s.trilinearScalars, s.hermiteScalars);
  return fmt::format("K {}: cells {} crossing / {} ambiguous / {} empty; stored scalars: cells {}, trilinear {}, hermite {}",
                     s.resolution, s.cells.crossing, s.cells.ambiguous, s.cells.empty, s.cellScalars, s.trilinearScalars,
                     s.hermiteScalars);
}

}  // namespace samples
