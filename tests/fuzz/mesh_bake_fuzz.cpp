// Fuzz target for the mesh baker: arbitrary triangle soup through the one bake pipeline
// (hsdf::bakeAsset: mesh checks, BVH, sign, grid fitting, budget, field, classification, cells) at
// a small K. Input layout (every byte string decodes to something; short inputs give fewer parts):
//   byte 0: K = 4 + b % 9 (4..12)         byte 1: padding = b % 3
//   byte 2: bit 0 narrow band, bits 1-2 refinement depth % 3, bit 3 indices as raw 32-bit words
//           (out of range most of the time: the importer's checks) instead of one byte each
//           bit 4 sparse band, bit 5 a shell (BakeSettings::shellThickness) 2^(8 * (bits 6-7) - 12) thick
//   byte 3: vertex count V = 1 + b % 32, then V x 3 floats (raw bits: NaN, inf, denormals, 1e38)
//   rest:   indices (bytes or little-endian 32-bit words), at most 64 triangles
// A bake that succeeds must be consistent: the asked K, finite samples, at least one kept cell
// (bakeAsset's "no surface" check), one record per kept cell, every record inside the grid.
// HSDF_FUZZ_VERBOSE=1 prints each input's outcome (to see what the seeds reach).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "engine/core/log.h"
#include "fuzz_check.h"
#include "hermite_sdf/core/bake_job.h"

namespace {

constexpr std::size_t kMaxTriangles = 64;

float readFloat(const std::uint8_t* p) {
  float value;
  std::memcpy(&value, p, sizeof(value));
  return value;
}

std::uint32_t readWord(const std::uint8_t* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
}

void checkAsset(const hsdf::SdfAsset& asset, int resolution) {
  FUZZ_CHECK(asset.field.grid.resolution == resolution);
  // The sparse bake keeps no dense field (BakeBand::Sparse), the others a complete one.
  FUZZ_CHECK(asset.field.samples.empty() || asset.field.samples.size() == asset.field.grid.sampleCount());
  for (const hsdf::HermiteSample& s : asset.field.samples)
    FUZZ_CHECK(std::isfinite(s.f) && std::isfinite(s.fx) && std::isfinite(s.fy) && std::isfinite(s.fz));
  FUZZ_CHECK(asset.classification.stats.kept() > 0);
  FUZZ_CHECK(asset.cells.records.size() == asset.classification.stats.kept());
  FUZZ_CHECK(asset.cellsHalf.records.size() == asset.cells.records.size());
  const int cells = resolution - 1;
  for (const hsdf::CellRecord& r : asset.cells.records) FUZZ_CHECK(r.x < cells && r.y < cells && r.z < cells);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The bake's one summary line per input (logPreparedSource) would flood the fuzzer's output.
  static const bool quiet = [] {
    engine::log::setMinLevel(engine::log::Level::Error);
    return true;
  }();
  (void)quiet;
  if (size < 4) return 0;
  hsdf::BakeSettings settings;
  settings.resolution = 4 + data[0] % 9;
  settings.padding = data[1] % 3;
  settings.band = (data[2] & 1) ? hsdf::BakeBand::NarrowBand : hsdf::BakeBand::Dense;
  if (data[2] & 16) settings.band = hsdf::BakeBand::Sparse;
  settings.refineDepth = (data[2] >> 1 & 3) % 3;
  settings.threads = 1;  // deterministic, and the fuzzer runs its own processes
  const bool wideIndices = (data[2] & 8) != 0;
  std::size_t offset = 4;
  engine::scene::TriangleSoup soup;
  const std::size_t vertices = std::min<std::size_t>(1 + data[3] % 32, (size - offset) / 12);
  for (std::size_t v = 0; v < vertices; ++v, offset += 12)
    soup.positions.push_back({readFloat(data + offset), readFloat(data + offset + 4), readFloat(data + offset + 8)});
  const std::size_t indexBytes = wideIndices ? 4 : 1;
  const std::size_t indices = std::min((size - offset) / indexBytes / 3, kMaxTriangles) * 3;
  for (std::size_t i = 0; i < indices; ++i, offset += indexBytes)
    soup.indices.push_back(wideIndices ? readWord(data + offset) : data[offset]);

  hsdf::BakeSource source = hsdf::BakeSource::fromTriangles("fuzz", std::move(soup));
  if (data[2] & 32) settings.shellThickness = std::ldexp(1.0, 8 * (data[2] >> 6) - 12);
  auto asset = hsdf::bakeAsset(source, settings);
  static const bool verbose = std::getenv("HSDF_FUZZ_VERBOSE") != nullptr;
  if (verbose)
    std::fprintf(stderr, "K %d: %s\n", settings.resolution,
                 asset.ok() ? ("baked, " + std::to_string((*asset)->cells.records.size()) + " kept cells").c_str()
                            : asset.error().message.c_str());
  if (!asset.ok()) {
    FUZZ_CHECK(!asset.error().message.empty());  // refused with a reason, never silently
    return 0;
  }
  checkAsset(**asset, settings.resolution);
  return 0;
}
