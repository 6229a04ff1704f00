#include "bake_command.h"

#include <chrono>
#include <cstdio>
#include <memory>

#include <fmt/format.h>

#include "engine/core/files.h"
#include "hermite_sdf/core/bake_job.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/core/hsdf_file.h"
#include "progress_bar.h"

namespace hsdf::tools {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

BakeSettings bakeSettings(const BakeRequest& request) {
  BakeSettings settings;
  settings.resolution = request.resolution;
  settings.padding = request.padding;
  // Cells only: the sparse bake (no dense field, cost ~ kept cells); otherwise every sample exact.
  settings.band = request.payload == Payload::Cells ? BakeBand::Sparse : BakeBand::Dense;
  settings.fp16 = request.fp16;
  settings.shellThickness = request.shell;
  settings.refineDepth = request.refineDepth;
  settings.threads = request.threads;
  return settings;
}

void printStorage(const GridSpec& grid, const CellStats& stats, bool fp16) {
  const std::uint64_t k = std::uint64_t(grid.resolution);
  std::printf("%s\n", formatCellStats(stats).c_str());
  std::printf("kept cells: %llu of %llu (%.2f%%)\n", (unsigned long long)stats.kept(), (unsigned long long)stats.cells,
              100.0 * double(stats.kept()) / double(stats.cells));
  std::printf("stored scalars: trilinear dense %llu, Hermite dense %llu, Hermite cells %llu\n",
              (unsigned long long)(k * k * k), (unsigned long long)(4 * k * k * k),
              (unsigned long long)(32 * stats.kept()));
  std::printf("cell stream bytes: %llu (%s records of %zu bytes)\n",
              (unsigned long long)(stats.kept() * (fp16 ? sizeof(CellRecordHalf) : sizeof(CellRecord))),
              fp16 ? "fp16" : "fp32", fp16 ? sizeof(CellRecordHalf) : sizeof(CellRecord));
}

int fail(const std::string& message) {
  std::fprintf(stderr, "hsdf_bake: error: %s\n", message.c_str());
  return 1;
}

// Checked before the bake, which may take minutes: writing must not fail afterwards for a reason
// known now, and must never replace the input.
engine::Status checkOutput(const BakeRequest& request) {
  std::error_code ec;
  if (std::filesystem::is_directory(request.output, ec))
    return engine::makeError(fmt::format("-o {}: is a directory, not a file", request.output.string()));
  if (std::filesystem::equivalent(request.input, request.output, ec))
    return engine::makeError(fmt::format("-o {}: is the INPUT file; baking would overwrite it",
                                         request.output.string()));
  return engine::checkWritable(request.output).withContext("-o");
}

}  // namespace

int runBake(const BakeRequest& request) {
  if (auto output = checkOutput(request); !output) return fail(output.error().message);
  auto source = BakeSource::fromPathOrShape(request.input);
  if (!source) return fail(source.error().message);
  const BakeSettings settings = bakeSettings(request);
  auto prepared = prepareSource(*source, settings);
  if (!prepared) return fail(prepared.error().withContext(request.input).message);
  std::printf("input: %s\n", prepared->description.c_str());
  auto grid = planBake(*prepared, settings);
  if (!grid) return fail(grid.error().message);
  std::printf("grid: K=%d, spacing %.9g, origin (%.9g, %.9g, %.9g), padding %d\n", grid->resolution, grid->spacing,
              grid->origin.x, grid->origin.y, grid->origin.z, request.padding);
  if (const auto thin = thinShellWarning(settings, *grid)) std::printf("warning: --shell: %s\n", thin->c_str());
  if (const auto small = smallPartsWarning(*source, settings, *grid)) std::printf("warning: %s\n", small->c_str());

  const auto bakeStart = std::chrono::steady_clock::now();
  ProgressBar bar(settings.band == BakeBand::Sparse ? "baking (sparse cells)" : "baking (dense)", stderr);
  BakeControl control;
  if (request.progress) control.progress = [&bar](float f) { return bar.update(f); };
  auto asset = bakeAsset(*prepared, settings, control);
  if (request.progress) bar.finish();
  if (!asset) return fail(asset.error().withContext(request.input).message);
  const SdfAsset& baked = **asset;
  if (settings.band == BakeBand::Sparse)
    std::printf("baked and classified %llu kept cells (sparse, no dense field) in %.3f s\n",
                (unsigned long long)baked.cells.records.size(), secondsSince(bakeStart));
  else
    std::printf("baked and classified %zu samples in %.3f s\n", baked.field.samples.size(), secondsSince(bakeStart));
  printStorage(baked.field.grid, baked.classification.stats, request.fp16);
  if (request.falsePositives) {
    const FalsePositiveReport report = countFalsePositives(baked.cells);
    std::printf("false positives: %llu of %llu kept cells (%.3f%%) are empty by 17^3 dense sampling\n",
                (unsigned long long)report.falsePositives, (unsigned long long)report.keptCells, 100.0 * report.rate());
  }

  // By reference: a copy of the cells would be the largest allocation of a K = 2048 bake.
  HsdfContentsView contents;
  contents.grid = baked.field.grid;
  contents.scalarType = request.fp16 ? HsdfScalarType::Float16 : HsdfScalarType::Float32;
  if (request.payload != Payload::Dense) contents.cells = &baked.cells;
  if (request.payload != Payload::Cells) contents.dense = &baked.field;
  contents.palette = &baked.palette;  // a mesh of several materials (none for one: the file is as before)
  auto bytes = serializeHsdf(contents);
  if (!bytes) return fail(bytes.error().message);
  if (auto written = engine::writeBinaryFile(request.output, *bytes); !written) return fail(written.error().message);
  std::printf("wrote %s: %zu bytes (%s%s%s%s)\n", request.output.string().c_str(), bytes->size(),
              contents.dense ? "dense field" : "", contents.dense && contents.cells ? " + " : "",
              contents.cells ? "cell stream" : "",
              baked.palette.empty() ? "" : fmt::format(" + {} materials", baked.palette.size()).c_str());
  return 0;
}

// Loads with full validation, prints the contents, and when both payloads are present checks that
// the stream is the field's: every stored cell holds the field's samples at its corners, and every
// cell whose corners change sign is stored (no surface lost). Ambiguous cells may differ from the
// field's own depth-0 classification, and are counted: the baker refines them (--refine; the file
// does not record the depth) and classifies the fp32 field that an fp16 file rounds.
int runInspect(const std::filesystem::path& file) {
  auto contents = loadHsdf(file);
  if (!contents) return fail(contents.error().message);
  const GridSpec& g = contents->grid;
  std::printf("%s: version %u, resolution %d, spacing %.9g, origin (%.9g, %.9g, %.9g), %s\n", file.string().c_str(),
              kHsdfVersion, g.resolution, g.spacing, g.origin.x, g.origin.y, g.origin.z,
              contents->scalarType == HsdfScalarType::Float16 ? "fp16" : "fp32");
  std::printf("dense field: %s\n", contents->dense ? fmt::format("{} samples", contents->dense->samples.size()).c_str()
                                                    : "none");
  std::printf("cell stream: %s\n", contents->cells ? fmt::format("{} cells", contents->cells->records.size()).c_str()
                                                    : "none");
  std::printf("materials: %s\n", contents->palette.empty() ? "one (no material section)"
                                                             : fmt::format("{}", contents->palette.size()).c_str());
  if (!contents->dense || !contents->cells) return 0;
  const HermiteField& field = *contents->dense;
  auto classes = classifyCells(field);
  if (!classes) return fail(classes.error().message);
  std::vector<bool> stored(classes->classes.size(), false);
  std::size_t wrongValues = 0;
  for (const CellRecord& r : contents->cells->records) {
    stored[classes->cellIndex(r.x, r.y, r.z)] = true;
    for (int c = 0; c < 8; ++c) {
      const HermiteSample& s = field.at(r.x + (c & 1), r.y + ((c >> 1) & 1), r.z + ((c >> 2) & 1));
      const HermiteSample& t = r.corners[std::size_t(c)];
      if (s.f != t.f || s.fx != t.fx || s.fy != t.fy || s.fz != t.fz) {
        ++wrongValues;
        break;
      }
    }
  }
  std::size_t crossingMissing = 0, ambiguousNotStored = 0, storedEmpty = 0;
  for (std::size_t i = 0; i < stored.size(); ++i) {
    crossingMissing += classes->classes[i] == CellClass::Crossing && !stored[i];
    ambiguousNotStored += classes->classes[i] == CellClass::Ambiguous && !stored[i];
    storedEmpty += classes->classes[i] == CellClass::Empty && stored[i];
  }
  const bool match = wrongValues == 0 && crossingMissing == 0;
  std::printf("cells match the dense field: %s (stored cells with other values than the field's: %zu; cells whose "
              "corners change sign not stored: %zu; ambiguous cells not stored (refined to empty): %zu; stored cells "
              "the field's depth-0 classification finds empty (classified before fp16 rounding): %zu)\n",
              match ? "yes" : "no", wrongValues, crossingMissing, ambiguousNotStored, storedEmpty);
  return match ? 0 : 1;
}

}  // namespace hsdf::tools
