#pragma once
// What a baked SDF costs per method and what its cells are: for the panel, the bake logs and the
// screenshot log.
#include <cstdint>
#include <string>

#include "hermite_sdf/core/bake_job.h"

namespace samples {

struct SdfStats {
  int resolution = 0;  // K
  hsdf::CellStats cells;
  std::uint64_t cellScalars = 0;  // 32 per kept cell: f and its gradient at 8 corners
  std::uint64_t cellBytes = 0;    // fp32 records, coordinates included
  std::uint64_t cellBytesHalf = 0;
  std::uint64_t trilinearScalars = 0;  // K^3 values of f
  std::uint64_t hermiteScalars = 0;    // 4 K^3: f and its gradient at every sample
  bool denseField = true;  // the asset holds them (a sparse bake or a cells-only file does not)
};
SdfStats sdfStats(const hsdf::SdfAsset& asset);
// "cells 1234 crossing / 56 ambiguous / 9999 empty; stored scalars: cells N, trilinear N, hermite N"
// (without a dense field: "...: cells N; no dense field (the tracers would store trilinear N, hermite N)")
std::string describeSdfStats(const SdfStats& stats);

}  // namespace samples
