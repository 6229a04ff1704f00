#include "hermite_sdf/core/bake_job.h"

#include <algorithm>
#include <array>
#include <exception>
#include <fstream>
#include <filesystem>
#include <limits>

#include <fmt/format.h>

#include "engine/core/log.h"
#include "engine/core/named_list.h"
#include "engine/scene/gltf/gltf_loader.h"
#include "hermite_sdf/core/analytic.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/core/hsdf_file.h"
#include "hermite_sdf/core/mesh_source.h"
#include "hermite_sdf/core/sparse_bake.h"

namespace hsdf {
namespace {

// Share of the progress bar the field bake takes; classification takes the rest.
constexpr float kBakeShare = 0.9f;

std::string describeMesh(const std::string& name, const MeshSourceStats& s, double shellThickness) {
  std::string description = fmt::format("{}: mesh, {} triangles", name, s.triangles);
  if (s.droppedZeroArea > 0) description += fmt::format(" ({} zero-area dropped)", s.droppedZeroArea);
  if (s.droppedInterior > 0)
    description += fmt::format(" ({} inside the solid dropped: a part nested in another)", s.droppedInterior);
  if (s.droppedOpen > 0)
    description += fmt::format(" ({} dropped: open parts that bound no volume, such as a sheet)", s.droppedOpen);
  description += s.closed ? ", closed" : fmt::format(", open ({} boundary edges)", s.boundaryEdges);
  if (shellThickness > 0.0) return description + fmt::format(", a shell {:g} thick", shellThickness);
  description += s.pseudoNormalSign    ? ", sign from pseudonormals"
                 : s.partsMisoriented ? ", sign from the winding number (parts nested with the same orientation or "
                                        "turned inside out)"
                                      : ", sign from the winding number";
  return description;
}

std::string knownShapes() {
  std::string known;
  for (const std::string& name : analyticShapeNames()) known += (known.empty() ? "" : ", ") + name;
  return known;
}

bool cancelled(const BakeControl& control) { return control.cancel && control.cancel->isCancelled(); }

// The budget is checked on numbers alone, so a refusal costs nothing and names the limit.
engine::Status checkBudget(const GridSpec& grid, const BakeSettings& settings, bool materialSlots) {
  const BakeBudget& budget = settings.budget;
  if (grid.resolution > budget.maxResolution)
    return engine::makeError(fmt::format("resolution {} is over the bake budget's max resolution {}", grid.resolution,
                                         budget.maxResolution));
  // The sparse bake's cost is its kept cells, budgeted while it bakes (bakeCellsSparse).
  if (settings.band == BakeBand::Sparse) return {};
  const std::uint64_t samples = grid.sampleCount();
  if (samples > budget.maxSamples)
    return engine::makeError(fmt::format("resolution {} needs {} samples, over the bake budget's max samples {}",
                                         grid.resolution, samples, budget.maxSamples));
  const std::uint64_t bytes = estimateBakeBytes(grid, settings.band, materialSlots);
  if (bytes > budget.maxBytes)
    return engine::makeError(fmt::format("resolution {} needs {} bytes ({:.1f} MiB), over the bake budget's max bytes "
                                         "{} ({:.1f} MiB)",
                                         grid.resolution, bytes, double(bytes) / 1048576.0, budget.maxBytes,
                                         double(budget.maxBytes) / 1048576.0));
  return {};
}

engine::Expected<HermiteField> bakeField(const SdfSource& source, const GridSpec& grid, const BakeSettings& settings,
                                         const BakeControl& control) {
  BakeOptions options;
  options.memoryBudgetBytes = settings.budget.maxBytes;
  options.threads = settings.threads;
  options.cancel = control.cancel;
  if (control.progress) options.progress = [&control](float f) { return control.progress(f * kBakeShare); };
  return settings.band == BakeBand::NarrowBand ? bakeHermiteFieldNarrowBand(source, grid, options)
                                               : bakeHermiteField(source, grid, options);
}

// A field without a surface draws nothing: an error with the likely causes, not an empty result. A
// closed part thinner than the spacing can fall between two sample planes (a 0.01-thick slab has a
// surface at K = 17 and none at K = 16): the spacing is named so that the user can compare.
engine::Status checkHasSurface(const CellStats& stats, const GridSpec& grid) {
  if (stats.kept() > 0) return {};
  return engine::makeError(fmt::format("the baked field has no surface: none of its {} cells changes sign (the input "
                                       "encloses no volume, e.g. a flat or open sheet, or none thicker than about "
                                       "the grid spacing {:.6g}: a higher resolution may resolve it)",
                                       stats.cells, grid.spacing));
}

// Each node's triangles' bounds in `soup` (flattenTriangles of `scene`) as a BakeSource::Part, in
// node order (a vector by node, not a map: a level may place a mesh a million times).
std::vector<BakeSource::Part> sceneParts(const engine::scene::SceneData& scene, const engine::scene::TriangleSoup& soup) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<std::pair<glm::dvec3, glm::dvec3>> bounds(scene.nodes.size(), {glm::dvec3(kInf), glm::dvec3(-kInf)});
  for (std::size_t t = 0; t < soup.triangleNodes.size(); ++t)
    for (std::size_t k = 0; k < 3; ++k) {
      const glm::dvec3 p(soup.positions[soup.indices[3 * t + k]]);
      auto& [lo, hi] = bounds[soup.triangleNodes[t]];
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
  std::vector<BakeSource::Part> parts;
  for (std::size_t node = 0; node < bounds.size(); ++node) {
    const glm::dvec3 side = bounds[node].second - bounds[node].first;
    if (!(side.x >= 0.0)) continue;  // no triangle of this node
    const std::string& name = scene.nodes[node].name;
    parts.push_back({name.empty() ? fmt::format("node {}", node) : fmt::format("'{}'", name),
                     std::max({side.x, side.y, side.z})});
  }
  return parts;
}

}  // namespace

BakeSource BakeSource::fromTriangles(std::string name, engine::scene::TriangleSoup triangles) {
  BakeSource source;
  source.name = std::move(name);
  source.triangles = std::make_shared<const engine::scene::TriangleSoup>(std::move(triangles));
  return source;
}

BakeSource BakeSource::fromShape(std::string shapeName) {
  BakeSource source;
  source.name = shapeName;
  source.shape = std::move(shapeName);
  return source;
}

engine::Expected<BakeSource> BakeSource::fromScene(std::string name, const engine::scene::SceneData& scene,
                                                  const glm::dvec3& origin) {
  ENGINE_TRY(engine::scene::checkFlattenable(scene));
  engine::scene::TriangleSoup soup = engine::scene::flattenTriangles(scene, origin);
  ENGINE_TRY_ASSIGN(MeshMaterials materials, meshMaterials(soup, scene));
  std::vector<Part> parts = sceneParts(scene, soup);
  BakeSource source = fromTriangles(std::move(name), std::move(soup));
  source.parts = std::move(parts);
  if (!materials.empty()) source.materials = std::make_shared<const MeshMaterials>(std::move(materials));
  return source;
}

engine::Expected<BakeSource> BakeSource::fromPathOrShape(const std::string& input) {
  std::error_code ec;
  if (std::filesystem::exists(input, ec)) {
    std::array<std::uint8_t, 8> head{};
    std::ifstream(input, std::ios::binary).read(reinterpret_cast<char*>(head.data()), std::streamsize(head.size()));
    if (startsWithHsdfMagic(head))
      return engine::makeError(fmt::format("INPUT '{}' is an .hsdf file, already baked: bake a glTF/GLB mesh or an "
                                           "analytic shape (hsdf_bake --inspect reads .hsdf files)",
                                           input));
    ENGINE_TRY_ASSIGN(engine::scene::SceneData scene, engine::scene::loadGltf(input));
    return fromScene(std::filesystem::path(input).filename().string(), scene).withContext(input);
  }
  for (const std::string& name : analyticShapeNames())
    if (name == input) return fromShape(input);
  return engine::makeError(
      fmt::format("INPUT '{}' is neither a file nor an analytic shape (known shapes: {})", input, knownShapes()));
}

engine::Expected<PreparedSource> prepareSource(const BakeSource& source, const BakeSettings& settings) {
  const double shellThickness = settings.shellThickness;
  PreparedSource prepared;
  prepared.name = source.name;
  prepared.shellThickness = shellThickness;
  if (source.triangles) {
    MeshSourceOptions options;
    if (source.materials && !source.materials->empty()) {
      ENGINE_TRY(checkMaterialSlots(source.materials->palette, source.materials->triangleSlots, "triangles")
                     .withContext("mesh source"));
      options.triangleSlots = source.materials->triangleSlots;
      prepared.palette = source.materials->palette;
    }
    options.shellThickness = shellThickness;
    ENGINE_TRY_ASSIGN(std::unique_ptr<MeshSource> mesh, MeshSource::create(*source.triangles, options));
    prepared.description = describeMesh(source.name, mesh->stats(), shellThickness);
    if (!prepared.palette.empty()) prepared.description += fmt::format(", {} materials", prepared.palette.size());
    prepared.droppedTriangles = mesh->stats().droppedOpen + mesh->stats().droppedInterior;
    prepared.source = std::move(mesh);
    return prepared;
  }
  if (shellThickness != 0.0)
    return engine::makeError(fmt::format("{}: a shell is baked around triangles; an analytic shape has none",
                                         source.shape));
  ENGINE_TRY_ASSIGN(prepared.source, makeAnalyticSource(source.shape));
  prepared.description = fmt::format("{}: analytic shape", source.shape);
  return prepared;
}

void logPreparedSource(const PreparedSource& prepared) {
  if (prepared.droppedTriangles > 0) engine::log::warn("bake: {}", prepared.description);
  else engine::log::info("bake: {}", prepared.description);
}

std::uint64_t estimateBakeBytes(const GridSpec& grid, BakeBand band, bool materialSlots) {
  if (band == BakeBand::Sparse) return 0;
  const std::uint64_t samples = grid.sampleCount();
  const std::uint64_t cells = grid.resolution > 1 ? std::uint64_t(grid.cellsPerAxis()) * std::uint64_t(grid.cellsPerAxis()) *
                                                        std::uint64_t(grid.cellsPerAxis())
                                                  : 0;
  const std::uint64_t flags = band == BakeBand::NarrowBand ? samples : 0;
  return estimateFieldBytes(grid, FieldKind::Hermite, materialSlots) + flags + cells * sizeof(CellClass);
}

engine::Expected<GridSpec> planBake(const PreparedSource& source, const BakeSettings& settings) {
  // Without a cell of padding the source's extreme surface lies on the grid's boundary: rays enter
  // the grid at f = 0 and cells there have no outside corner to change sign into, so every method
  // draws holes and specks there (a cube: whole faces).
  if (settings.padding < kMinBakePadding)
    return engine::makeError(fmt::format("padding {}: a bake needs at least {} cell of padding around the source, "
                                         "or its surface lies on the grid's boundary and draws with holes",
                                         settings.padding, kMinBakePadding));
  // The shell is in the prepared source (its distances and bounds): other settings would bake
  // another surface than they name.
  if (settings.shellThickness != source.shellThickness)
    return engine::makeError(fmt::format("shell thickness {:g}: '{}' was prepared for {:g} (prepareSource with these "
                                         "settings)",
                                         settings.shellThickness, source.name, source.shellThickness));
  ENGINE_TRY_ASSIGN(GridSpec grid, fitGrid(source.source->bounds(), settings.resolution, settings.padding)
                                       .withContext("fitting the grid"));
  ENGINE_TRY(checkBudget(grid, settings, source.source->materialSlots() > 0));
  if (settings.fp16) ENGINE_TRY(checkStorable(grid, HsdfScalarType::Float16).withContext("fp16"));
  return grid;
}

namespace {

// The cells path without a dense field: bakeCellsSparse straight into an asset.
engine::Expected<std::shared_ptr<const SdfAsset>> bakeSparseAsset(const PreparedSource& source, const GridSpec& grid,
                                                                  const BakeSettings& settings,
                                                                  const BakeControl& control) {
  SparseBakeOptions options;
  options.refineDepth = settings.refineDepth;
  options.maxKeptCells = settings.budget.maxKeptCells;
  options.maxBytes = settings.budget.maxBytes;
  options.threads = settings.threads;
  options.cancel = control.cancel;
  if (control.progress) options.progress = [&control](float f) { return control.progress(f * kBakeShare); };
  ENGINE_TRY_ASSIGN(SparseBakeResult baked, bakeCellsSparse(*source.source, grid, options).withContext("baking"));
  auto made = makeSdfAssetFromSparseBake(source.name, std::move(baked.cells), baked.stats, settings.refineDepth,
                                         source.source->bounds(), source.palette, settings.threads, control.cancel);
  if (!made && cancelled(control)) return engine::makeError("baking: cancelled");
  return made;
}

}  // namespace

engine::Expected<std::shared_ptr<const SdfAsset>> bakeAsset(const PreparedSource& source, const BakeSettings& settings,
                                                            const BakeControl& control) {
  ENGINE_TRY_ASSIGN(GridSpec grid, planBake(source, settings));
  if (settings.band == BakeBand::Sparse) {
    ENGINE_TRY_ASSIGN(std::shared_ptr<const SdfAsset> asset, bakeSparseAsset(source, grid, settings, control));
    ENGINE_TRY(checkHasSurface(asset->classification.stats, grid));
    if (control.progress && !control.progress(1.0f)) return engine::makeError("baking: cancelled");
    return asset;
  }
  ENGINE_TRY_ASSIGN(HermiteField field,
                    bakeField(*source.source, grid, settings, control).withContext("baking"));
  if (cancelled(control)) return engine::makeError("baking: cancelled");
  ClassifyOptions classify;
  classify.refineDepth = settings.refineDepth;
  classify.threads = settings.threads;
  classify.maxKeptCells = settings.budget.maxKeptCells;
  classify.cancel = control.cancel;
  auto made = makeSdfAsset(source.name, std::move(field), source.source->bounds(), classify, source.palette);
  if (!made && cancelled(control)) return engine::makeError("baking: cancelled");
  ENGINE_TRY_ASSIGN(std::shared_ptr<const SdfAsset> asset, std::move(made));
  ENGINE_TRY(checkHasSurface(asset->classification.stats, grid));
  if (control.progress && !control.progress(1.0f)) return engine::makeError("baking: cancelled");
  return asset;
}

std::optional<std::string> thinShellWarning(const BakeSettings& settings, const GridSpec& grid) {
  if (!(settings.shellThickness > 0.0) || settings.shellThickness >= grid.spacing) return std::nullopt;
  return fmt::format("a shell {:g} thick is thinner than a grid cell ({:g}): it bakes rough, and with holes when far "
                     "thinner; a larger resolution or a thicker shell resolves it",
                     settings.shellThickness, grid.spacing);
}

std::optional<std::string> smallPartsWarning(const BakeSource& source, const BakeSettings& settings, const GridSpec& grid) {
  std::vector<std::string> named;
  std::size_t count = 0;
  for (const BakeSource::Part& part : source.parts) {
    if (!(part.size + 2.0 * settings.shellThickness < grid.spacing)) continue;
    if (++count <= engine::kNamedInMessages) named.push_back(fmt::format("{} ({:g})", part.name, part.size));
  }
  if (count == 0) return std::nullopt;
  return fmt::format("{} of the {} placed meshes fit{} inside one grid cell ({:g}) and may be lost or drawn as a "
                     "blob: {}; a higher resolution, or one SDF per object (scene_runner --objects), resolves {}",
                     count, source.parts.size(), count == 1 ? "s" : "", grid.spacing, engine::namedList(named, count),
                     count == 1 ? "it" : "them");
}

engine::Expected<std::shared_ptr<const SdfAsset>> bakeAsset(const BakeSource& source, const BakeSettings& settings,
                                                            const BakeControl& control) {
  ENGINE_TRY_ASSIGN(PreparedSource prepared, prepareSource(source, settings));
  logPreparedSource(prepared);
  if (const auto grid = planBake(prepared, settings); grid) {  // else bakeAsset says why
    if (const auto thin = thinShellWarning(settings, *grid)) engine::log::warn("bake: {}: {}", source.name, *thin);
    if (const auto small = smallPartsWarning(source, settings, *grid)) engine::log::warn("bake: {}: {}", source.name, *small);
  }
  return bakeAsset(prepared, settings, control);
}

BakeJob::BakeJob(BakeSource source, BakeSettings settings) : settings_(std::move(settings)) {
  thread_ = std::thread([this, source = std::move(source)]() mutable { run(std::move(source)); });
}

BakeJob::~BakeJob() {
  cancel();
  if (thread_.joinable()) thread_.join();
}

void BakeJob::run(BakeSource source) {
  BakeControl control;
  control.cancel = &cancel_;
  control.progress = [this](float f) {
    progress_.store(f, std::memory_order_relaxed);
    return true;
  };
  // An exception must not escape the thread (std::terminate): the large allocations are the likely
  // source, and the caller gets them as an error like any other.
  Result result = engine::makeError("bake job: not run");
  try {
    result = bakeAsset(source, settings_, control);
  } catch (const std::exception& e) {
    result = engine::makeError(std::string("bake job: ") + e.what());
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    result_ = std::move(result);
    done_.store(true, std::memory_order_release);  // under the lock: waitUntilDone cannot miss it
  }
  doneChanged_.notify_all();
}

std::optional<BakeJob::Result> BakeJob::take() {
  if (!done()) return std::nullopt;
  std::lock_guard<std::mutex> lock(mutex_);
  std::optional<Result> result = std::move(result_);
  result_.reset();
  return result;
}

void BakeJob::waitUntilDone() {
  std::unique_lock<std::mutex> lock(mutex_);
  doneChanged_.wait(lock, [this] { return done(); });
}

BakeJob::Result BakeJob::wait() {
  if (thread_.joinable()) thread_.join();
  std::optional<Result> result = take();
  if (!result) return engine::makeError("bake job: the result was already taken");
  return std::move(*result);
}

}  // namespace hsdf
