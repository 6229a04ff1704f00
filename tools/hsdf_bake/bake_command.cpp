#include "bake_command.h"

#include <chrono>
#include <cstdio>
#include <memory>

#include <fmt/format.h>

#include "engine/core/files.h"
#include "engine/scene/gltf_loader.h"
#include "hermite_sdf/analytic.h"
#include "hermite_sdf/cells.h"
#include "hermite_sdf/hsdf_file.h"
#include "hermite_sdf/mesh_source.h"
#include "progress_bar.h"

namespace hsdf::tools {
namespace {

struct LoadedSource {
  std::unique_ptr<SdfSource> source;
  std::string description;
};

engine::Expected<LoadedSource> loadMesh(const std::filesystem::path& path) {
  auto scene = engine::scene::loadGltf(path);
  if (!scene) return scene.error();
  if (auto flattenable = engine::scene::checkFlattenable(*scene); !flattenable)
    return flattenable.error().withContext(path.string());
  const engine::scene::TriangleSoup soup = engine::scene::flattenTriangles(*scene);
  auto mesh = MeshSource::create(soup);
  if (!mesh) return mesh.error().withContext(path.string());
  const MeshSourceStats& s = (*mesh)->stats();
  std::string description = fmt::format("{}: mesh, {} triangles", path.filename().string(), s.triangles);
  if (s.droppedZeroArea > 0) description += fmt::format(" ({} zero-area dropped)", s.droppedZeroArea);
  description += s.closed ? ", closed" : fmt::format(", open ({} boundary edges)", s.boundaryEdges);
  description += s.pseudoNormalSign ? ", sign from pseudonormals" : ", sign from the winding number";
  return LoadedSource{std::move(mesh.value()), std::move(description)};
}

// A path that exists is read as glTF/GLB (the loader names what is wrong with it); anything else
// must be an analytic shape name.
engine::Expected<LoadedSource> loadSource(const std::string& input) {
  std::error_code ec;
  if (std::filesystem::exists(input, ec)) return loadMesh(input);
  auto shape = makeAnalyticSource(input);
  if (!shape) {
    std::string known;
    for (const std::string& name : analyticShapeNames()) known += (known.empty() ? "" : ", ") + name;
    return engine::makeError(fmt::format("INPUT '{}' is neither a file nor an analytic shape (known shapes: {})",
                                         input, known));
  }
  return LoadedSource{std::move(shape.value()), fmt::format("{}: analytic shape", input)};
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

engine::Expected<HermiteField> bakeField(const SdfSource& source, const GridSpec& grid, const BakeRequest& request) {
  ProgressBar bar(request.payload == Payload::Cells ? "baking (narrow band)" : "baking (dense)", stderr);
  BakeOptions options;
  options.threads = request.threads;
  if (request.progress) options.progress = [&bar](float f) { return bar.update(f); };
  auto field = request.payload == Payload::Cells ? bakeHermiteFieldNarrowBand(source, grid, options)
                                                 : bakeHermiteField(source, grid, options);
  if (request.progress) bar.finish();
  return field;
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
  return {};
}

// A field without a surface gives a file that draws nothing: an error, with the likely cause.
engine::Status checkHasSurface(const CellStats& stats) {
  if (stats.kept() > 0) return {};
  return engine::makeError(fmt::format("the field has no surface: none of its {} cells changes sign (the input "
                                       "encloses no volume, e.g. a flat or open sheet)",
                                       stats.cells));
}

}  // namespace

int runBake(const BakeRequest& request) {
  if (auto output = checkOutput(request); !output) return fail(output.error().message);
  auto loaded = loadSource(request.input);
  if (!loaded) return fail(loaded.error().message);
  std::printf("input: %s\n", loaded->description.c_str());
  auto grid = fitGrid(loaded->source->bounds(), request.resolution, request.padding);
  if (!grid) return fail(grid.error().withContext("fitting the grid").message);
  std::printf("grid: K=%d, spacing %.9g, origin (%.9g, %.9g, %.9g), padding %d\n", grid->resolution, grid->spacing,
              grid->origin.x, grid->origin.y, grid->origin.z, request.padding);
  const HsdfScalarType scalarType = request.fp16 ? HsdfScalarType::Float16 : HsdfScalarType::Float32;
  if (auto storable = checkStorable(*grid, scalarType); !storable)
    return fail(storable.error().withContext(request.fp16 ? "--fp16" : "fp32").message);

  const auto bakeStart = std::chrono::steady_clock::now();
  auto field = bakeField(*loaded->source, *grid, request);
  if (!field) return fail(field.error().withContext("baking").message);
  std::printf("baked %zu samples in %.3f s\n", field->samples.size(), secondsSince(bakeStart));

  ClassifyOptions classifyOptions;
  classifyOptions.refineDepth = request.refineDepth;
  classifyOptions.threads = request.threads;
  auto classes = classifyCells(*field, classifyOptions);
  if (!classes) return fail(classes.error().withContext("classifying cells").message);
  if (auto surface = checkHasSurface(classes->stats); !surface) return fail(surface.error().withContext(request.input).message);
  printStorage(*grid, classes->stats, request.fp16);
  if (request.falsePositives) {
    const FalsePositiveReport report = countFalsePositives(*field, *classes);
    std::printf("false positives: %llu of %llu kept cells (%.3f%%) are empty by 17^3 dense sampling\n",
                (unsigned long long)report.falsePositives, (unsigned long long)report.keptCells, 100.0 * report.rate());
  }

  HsdfContents contents;
  contents.grid = *grid;
  contents.scalarType = scalarType;
  if (request.payload != Payload::Dense) {
    auto cells = extractCells(*field, *classes);
    if (!cells) return fail(cells.error().withContext("extracting cells").message);
    contents.cells = std::move(*cells);
  }
  if (request.payload != Payload::Cells) contents.dense = std::move(*field);
  auto bytes = serializeHsdf(contents);
  if (!bytes) return fail(bytes.error().message);
  if (auto written = engine::writeBinaryFile(request.output, *bytes); !written) return fail(written.error().message);
  std::printf("wrote %s: %zu bytes (%s%s%s)\n", request.output.string().c_str(), bytes->size(),
              contents.dense ? "dense field" : "", contents.dense && contents.cells ? " + " : "",
              contents.cells ? "cell stream" : "");
  return 0;
}

// Loads with full validation, prints the contents, and when both payloads are present re-derives
// the cells from the dense field: the stored stream must be exactly the kept cells.
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
  if (!contents->dense || !contents->cells) return 0;
  auto classes = classifyCells(*contents->dense);
  if (!classes) return fail(classes.error().message);
  auto expected = extractCells(*contents->dense, *classes);
  if (!expected) return fail(expected.error().message);
  bool match = expected->records.size() == contents->cells->records.size();
  for (std::size_t r = 0; match && r < expected->records.size(); ++r) {
    const CellRecord& a = expected->records[r];
    const CellRecord& b = contents->cells->records[r];
    match = a.x == b.x && a.y == b.y && a.z == b.z && a.cellClass == b.cellClass;
  }
  std::printf("cells match the dense field: %s\n", match ? "yes" : "no");
  return match ? 0 : 1;
}

}  // namespace hsdf::tools
