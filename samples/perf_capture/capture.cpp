#include "capture.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "capture_rows.h"
#include "engine/core/log.h"
#include "engine/gpu/context.h"
#include "engine/render/mesh_pool.h"
#include "engine/render/scene_instantiate.h"
#include "engine/scene/gltf/gltf_loader.h"
#include "engine/scene/transform.h"
#include "measurement.h"
#include "ground_truth.h"
#include "hermite_sdf/core/analytic.h"
#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/render/lod.h"
#include "hermite_sdf/core/cells.h"
#include "metrics.h"
#include "report.h"
#include "viewer.h"

namespace capture {
namespace {

using namespace engine;

// What is captured: its ground truth and, for a glTF scene, the scene data the mesh rows measure.
struct Subject {
  std::string name;
  std::unique_ptr<TruthSurface> truth;
  std::optional<scene::SceneData> scene;
  std::uint64_t meshScalars = 0, meshBytes = 0;
};

Status loadSubject(const Options& options, Subject& subject) {
  if (!options.shape.empty()) {
    subject.name = options.shape;
    ENGINE_TRY_ASSIGN(auto source, hsdf::makeAnalyticSource(options.shape));
    subject.truth = analyticSurface(std::move(source));
    return {};
  }
  subject.name = options.scene.filename().string();
  ENGINE_TRY_ASSIGN(scene::SceneData data, scene::loadGltf(options.scene));
  ENGINE_TRY(scene::checkFlattenable(data).withContext(options.scene.string()));
  const scene::TriangleSoup soup = scene::flattenTriangles(data);
  if (soup.indices.empty()) return makeError(options.scene.string() + ": no triangle meshes to capture");
  subject.truth = meshSurface(soup);
  // As the mesh pool stores them: position + normal per vertex, 32-bit indices.
  subject.meshScalars = 3 * soup.positions.size() + soup.indices.size();
  subject.meshBytes = 24 * soup.positions.size() + 4 * soup.indices.size();
  subject.scene = std::move(data);
  return {};
}

// With SceneDesc::objects the scene holds one asset per mesh: storage is their sum (each stored once
// however many nodes draw it).
void storage(const RowSpec& spec, const Subject& subject, const std::vector<const hsdf::SdfAsset*>& assets,
             RowResult& result) {
  if (spec.isMesh()) {
    result.storedScalars = subject.meshScalars;
    result.storedBytes = subject.meshBytes;
    return;
  }
  const std::uint64_t k = std::uint64_t(spec.resolution), dense = k * k * k * assets.size();
  if (spec.render == hsdf::RenderMethod::TrilinearSphereTrace) {
    result.storedScalars = dense;
    result.storedBytes = dense * (spec.fp16 ? 2 : 4);
  } else if (spec.render == hsdf::RenderMethod::HermiteSphereTrace) {
    result.storedScalars = 4 * dense;
    result.storedBytes = 4 * dense * (spec.fp16 ? 2 : 4);
  } else {
    for (const hsdf::SdfAsset* asset : assets) {
      result.cells += asset->cells.records.size();
      result.storedScalars += asset->cells.stored_scalars();
    }
    result.storedBytes = result.cells * (spec.fp16 ? sizeof(hsdf::CellRecordHalf) : sizeof(hsdf::CellRecord));
  }
}

double median(std::vector<double> v) { return percentile(std::move(v), 0.5); }

// Every named GPU timing over the timed frames, by name in the order first seen: a scope a frame
// did not record (a feature with nothing to cull) is left out of that frame, not counted as 0.
class NamedTimings {
 public:
  void add(const std::vector<gpu::GpuTiming>& timings) {
    for (const gpu::GpuTiming& t : timings) {
      auto it = std::find_if(samples_.begin(), samples_.end(), [&](const auto& s) { return s.first == t.name; });
      if (it == samples_.end()) it = samples_.insert(samples_.end(), {t.name, {}});
      it->second.push_back(t.milliseconds);
    }
  }
  std::vector<std::pair<std::string, double>> medians() const {
    std::vector<std::pair<std::string, double>> result;
    for (const auto& [name, ms] : samples_) result.emplace_back(name, median(ms));
    return result;
  }

 private:
  std::vector<std::pair<std::string, std::vector<double>>> samples_;
};

void addStatistics(const TimedFrame& frame, double views, RowResult& result) {
  for (const gpu::PipelineStatistics& s : frame.statistics) {
    const bool prepass = s.name == "depth prepass";
    (prepass ? result.prepassFsInvocations : result.shadingFsInvocations) += double(s.fragmentShaderInvocations) / views;
    result.fsInvocations += double(s.fragmentShaderInvocations) / views;
    result.vsInvocations += double(s.vertexShaderInvocations) / views;
    if (prepass) result.prepassVsInvocations += double(s.vertexShaderInvocations) / views;
    result.clippedPrimitives += double(s.clippingPrimitives) / views;
  }
}

std::string fileName(const std::string& label) {
  std::string name;
  for (char c : label) name += (std::isalnum(static_cast<unsigned char>(c)) ? c : '_');
  return name;
}

// The scene cameras the views look through (--scene-cameras), by index; empty for the orbit views.
// A camera named is one the capture must look through (refused if it cannot be one); "all" takes
// every camera that can be one and skips, with a warning, those that cannot (a zero scale).
Expected<std::vector<std::size_t>> sceneCameraViews(samples::Viewer& viewer, const Options& options) {
  std::vector<std::size_t> cameras;
  for (const std::string& camera : options.sceneCameras) {
    if (camera == "all") {
      for (std::size_t i = 0; i < viewer.sceneCameraNames().size(); ++i) {
        if (Status usable = viewer.lookThroughSceneCamera(i); !usable)
          log::warn("--scene-cameras all: skipped: {}", usable.error().message);
        else
          cameras.push_back(i);
      }
      continue;
    }
    ENGINE_TRY_ASSIGN(const std::size_t index, viewer.findSceneCamera(camera).withContext("--scene-cameras"));
    cameras.push_back(index);
  }
  if (!options.sceneCameras.empty() && cameras.empty())
    return makeError("--scene-cameras: " + options.scene.string() + " has no camera the capture can look "
                     "through");
  return cameras;
}

// View v: scene camera sceneCameras[v], or orbit view v `distance` times farther from the
// framing's target (the scene bounds' centre).
Status showView(samples::Viewer& viewer, std::size_t v, const Options& options, const std::vector<std::size_t>& sceneCameras) {
  if (!sceneCameras.empty()) return viewer.lookThroughSceneCamera(sceneCameras[v]).withContext("--scene-cameras");
  viewer.setOrbitView(int(v));
  if (options.distance == 1.0f) return {};
  const glm::dvec3 target = 0.5 * (glm::dvec3(viewer.boundsMin()) + glm::dvec3(viewer.boundsMax()));
  viewer.setCamera(target + double(options.distance) * (glm::dvec3(viewer.cameraView().position) - target), target);
  return {};
}

// The fixed views of the capture: the scene's cameras, or the Viewer's orbit views framed on the
// source's bounds (glTF: its mesh vertices; shapes: the shape's bounds), never on the grid's padded
// bounds.
Expected<std::vector<render::CameraView>> captureViews(samples::Viewer& viewer, const Options& options,
                                                       const std::vector<std::size_t>& sceneCameras) {
  const std::size_t count = sceneCameras.empty() ? options.views : sceneCameras.size();
  std::vector<render::CameraView> cameras;
  for (std::size_t v = 0; v < count; ++v) {
    ENGINE_TRY(showView(viewer, v, options, sceneCameras));
    cameras.push_back(viewer.cameraView());
  }
  return cameras;
}

bool sameCamera(const render::CameraView& a, const render::CameraView& b) {
  return a.view == b.view && a.proj == b.proj && a.znear == b.znear;
}

// Everything one group of rows (drawn by one Viewer) shares.
struct Group {
  const Options& options;
  VkExtent2D extent;
  const Subject& subject;
  samples::Viewer& viewer;
  Measurement& measurement;
  const ecs::Registry& measured;  // what Measurement draws: the Viewer's registry, or the meshes
  const std::vector<render::CameraView>& cameras;
  const std::vector<std::size_t>& sceneCameras;  // the scene cameras of the views (sceneCameraViews)
  const std::vector<TruthImage>& truth;
  double diagonal;
};

// The distinct assets the scene draws (one; with SceneDesc::objects, one per mesh).
std::vector<const hsdf::SdfAsset*> drawnAssets(samples::Viewer& viewer) {
  std::vector<const hsdf::SdfAsset*> assets;
  viewer.registry().view<hsdf::HermiteSdfRenderable>().each([&assets](ecs::Entity, const hsdf::HermiteSdfRenderable& r) {
    if (std::find(assets.begin(), assets.end(), r.asset.get()) == assets.end()) assets.push_back(r.asset.get());
  });
  return assets;
}

// The distinct assets the scene holds: those drawn and, with levels of detail, every level.
std::vector<const hsdf::SdfAsset*> heldAssets(samples::Viewer& viewer) {
  std::vector<const hsdf::SdfAsset*> assets = drawnAssets(viewer);
  viewer.registry().view<hsdf::HermiteSdfLod>().each([&assets](ecs::Entity, const hsdf::HermiteSdfLod& lod) {
    for (const auto& level : lod.levels)
      if (std::find(assets.begin(), assets.end(), level.get()) == assets.end()) assets.push_back(level.get());
  });
  return assets;
}

std::uint64_t cellsOf(const std::vector<const hsdf::SdfAsset*>& assets) {
  std::uint64_t cells = 0;
  for (const hsdf::SdfAsset* asset : assets) cells += asset->cells.records.size();
  return cells;
}

// One row over every view: warm-up, timed frames (Viewer steps), one measured frame.
Status captureRow(const Group& g, const RowSpec& spec, std::size_t index, std::size_t total, RowResult& result) {
  g.viewer.setTuning(spec.tuning());
  ENGINE_TRY(g.viewer.waitForBake());  // a new K re-bakes through the module bake job
  const std::vector<const hsdf::SdfAsset*> assets = drawnAssets(g.viewer);
  if (!spec.isMesh() && assets.empty()) return makeError("no SDF in the scene");
  // With levels of detail the rows held every level and drew the ones their views picked (the
  // frames select them): the storage of all, the cells of those drawn. They reported level 0's.
  const bool levels = spec.state.lod && !spec.isMesh();
  storage(spec, g.subject, levels ? heldAssets(g.viewer) : assets, result);
  double drawnCells = 0.0;
  QualityAccumulator quality(g.diagonal);
  std::vector<double> frameMs, prepassMs, shadingMs;
  NamedTimings named;
  const double views = double(g.cameras.size());
  for (std::size_t v = 0; v < g.cameras.size(); ++v) {
    std::fprintf(stderr, "\r[%zu/%zu] %-26s view %zu/%zu   ", index + 1, total, spec.label.c_str(), v + 1,
                 g.cameras.size());
    ENGINE_TRY(showView(g.viewer, v, g.options, g.sceneCameras));
    for (std::uint32_t f = 0; f < g.options.warmup; ++f) ENGINE_TRY(timeFrame(g.viewer));
    TimedFrame last;
    for (std::uint32_t f = 0; f < g.options.frames; ++f) {
      ENGINE_TRY_ASSIGN(last, timeFrame(g.viewer));
      frameMs.push_back(last.frameMs);
      prepassMs.push_back(last.prepassMs);
      shadingMs.push_back(last.shadingMs);
      named.add(last.timings);
    }
    addStatistics(last, views, result);
    // A row of occlusion culling measured without it (its depth pyramid could not be made) is not
    // that row: it fails, naming why (it was measured and reported as passing).
    if (spec.state.cullOcclusion && !g.viewer.renderer().occlusionFailure().empty())
      return makeError("occlusion culling culls nothing: " + g.viewer.renderer().occlusionFailure());
    drawnCells += double(cellsOf(drawnAssets(g.viewer))) / views;
    const hsdf::HermiteCellFeature& cellFeature = *g.viewer.renderer().feature<hsdf::HermiteCellFeature>();
    const hsdf::HermiteCellFeature::Stats& cells = cellFeature.stats();
    // Culled bricks or cells: the boxes drawn are those the culling pass kept (the frame has completed).
    const shader::BrickCullTotals culled = cellFeature.cullTotals();
    const double drawn = double(cells.bricks > 0 ? cells.bricks : cells.runs > 0 ? cells.runs : cells.cells);
    // Tiled cells: the proxies are the tiles' quads.
    const double proxies = cells.tiles ? double(cellFeature.tileTotals().instanceCount) : culled.tested > 0 ? double(culled.kept) : drawn;
    result.boxes += proxies / views;
    if (g.options.objects && v == 0 && samples::drawsCells(spec.state.method))
      std::fprintf(stderr, "\n%s: %zu assets, %u cell objects in %u indirect commands\n", spec.label.c_str(),
                   assets.size(), cells.objects, cells.draws);
    if (v == 0) {
      result.image = "images/" + fileName(spec.label) + ".png";
      ENGINE_TRY(g.viewer.writeScreenshot(g.options.out / result.image));
    }
    quality.add(g.truth[v], g.measurement.measure(g.measured, g.cameras[v], spec.state), g.cameras[v]);
  }
  if (levels) result.cells = std::uint64_t(std::llround(drawnCells));
  result.gpuMsMedian = median(frameMs);
  result.gpuMsP95 = percentile(frameMs, 0.95);
  result.prepassMs = median(prepassMs);
  result.shadingMs = median(shadingMs);
  result.passMs = named.medians();
  result.quality = quality.result();
  result.parts = quality.parts();
  if (result.quality.coveredPixels == 0) return makeError("drew nothing in any view");
  result.ok = true;
  return {};
}

std::string commandOutput(const std::string& command) {
  std::string out;
  if (FILE* pipe = popen(command.c_str(), "r")) {
    char buffer[256];
    while (std::fgets(buffer, sizeof(buffer), pipe)) out += buffer;
    pclose(pipe);
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

RunInfo runInfo(const Options& options, const gpu::Context& context, const Subject& subject) {
  RunInfo info;
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  properties.pNext = &driver;
  vkGetPhysicalDeviceProperties2(context.physicalDevice(), &properties);
  info.device = context.capabilities().deviceName;
  info.driver = std::string(driver.driverName) + " " + driver.driverInfo;
  info.commandLine = options.commandLine;
  // HSDF_COMMIT names the build's commit where the source folder's git does not (a packed build run
  // on another machine: there the folder may hold another checkout, or none).
  const char* stated = std::getenv("HSDF_COMMIT");
  const std::string commit = stated && *stated ? std::string(stated)
                                               : commandOutput("git -C '" HSDF_SOURCE_DIR "' describe --always --dirty 2>/dev/null");
  info.commit = commit.empty() ? "unknown" : commit;
  const std::time_t now = std::time(nullptr);
  char date[64];
  std::strftime(date, sizeof(date), "%Y-%m-%d %H:%M:%S UTC", std::gmtime(&now));
  info.date = date;
  info.scene = subject.name;
  if (subject.scene)
    for (const scene::NodeData& node : subject.scene->nodes)
      info.partNames.push_back(node.mesh >= 0 && std::size_t(node.mesh) < subject.scene->meshes.size()
                                   ? fmt::format("{} ({})", node.name, subject.scene->meshes[std::size_t(node.mesh)].name)
                                   : node.name);
  info.width = options.width;
  info.height = options.height;
  info.views = options.views;
  info.frames = options.frames;
  info.warmup = options.warmup;
  info.pipelineStatistics = context.capabilities().pipelineStatistics;
  info.softwareRasterizer = context.capabilities().isSoftwareRasterizer;
  return info;
}

// Which rows may still start (--time-limit), and the finished rows written out after each one, so
// that a capture stopped from outside (a device call's time limit, a crash) keeps what it measured.
class Progress {
 public:
  explicit Progress(const Options& options) : options_(options), start_(std::chrono::steady_clock::now()) {}

  // Why the next row does not start, if it does not: past the time limit, once a row was measured
  // (a capture always measures its first row).
  std::optional<std::string> refusal(const std::vector<RowResult>& results) const {
    if (options_.timeLimitSeconds <= 0.0) return std::nullopt;
    const bool measured = std::any_of(results.begin(), results.end(), [](const RowResult& r) { return r.ok; });
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (!measured || elapsed < options_.timeLimitSeconds) return std::nullopt;
    return fmt::format("not run: --time-limit {} s reached ({:.0f} s)", options_.timeLimitSeconds, elapsed);
  }

  // results.csv and results.json as they stand (the report and charts come at the end).
  Status save(const RunInfo& info, const std::vector<RowResult>& results) const {
    ENGINE_TRY(writeCsv(options_.out / "results.csv", info, results));
    return writeJson(options_.out / "results.json", info, results);
  }

 private:
  const Options& options_;
  std::chrono::steady_clock::time_point start_;
};

// A row that did not start, listed with why (a failed row: the capture exits non-zero).
void addNotRun(const RowSpec& spec, const std::string& why, std::vector<RowResult>& results) {
  RowResult& result = results.emplace_back();
  result.spec = spec;
  result.ok = false;
  result.error = why;
  std::fprintf(stderr, "\n%s: %s\n", spec.label.c_str(), why.c_str());
}

// A group's headless Viewer, its scene loaded with the settings of the group's first row.
Expected<std::unique_ptr<samples::Viewer>> openViewer(const Options& options, const RowSpec& first) {
  samples::ViewerDesc desc;
  desc.title = "hermite_sdf perf capture";
  desc.width = options.width;
  desc.height = options.height;
  desc.headless = true;
  desc.device = options.device;
  ENGINE_TRY_ASSIGN(std::unique_ptr<samples::Viewer> viewer, samples::Viewer::create(desc));
  samples::SceneDesc scene;
  scene.gltf = options.scene;
  scene.shape = options.shape;
  scene.groundPlane = false;
  scene.objects = options.objects;
  ENGINE_TRY(viewer->loadScene(scene, first.tuning()));
  return viewer;
}

// The group's views (`sceneCameras`: the scene cameras they show, named in `info`): the first
// group's become every group's `cameras`, with their ground truth cast; a later group's must be
// the same, or the rows would not be comparable.
Status frameViews(samples::Viewer& viewer, const Options& options, const Subject& subject,
                  const std::vector<std::size_t>& sceneCameras, std::vector<render::CameraView>& cameras,
                  std::vector<TruthImage>& truth, RunInfo& info) {
  ENGINE_TRY_ASSIGN(const std::vector<render::CameraView> views, captureViews(viewer, options, sceneCameras));
  info.views = std::uint32_t(views.size());
  info.viewNames.clear();
  for (const std::size_t camera : sceneCameras) info.viewNames.push_back(viewer.sceneCameraNames()[camera]);
  if (cameras.empty()) {
    cameras = views;
    for (std::size_t v = 0; v < cameras.size(); ++v) {
      std::fprintf(stderr, "\rground truth view %zu/%zu   ", v + 1, cameras.size());
      truth.push_back(castTruth(*subject.truth, cameras[v], int(options.width), int(options.height)));
    }
  }
  for (std::size_t v = 0; v < views.size(); ++v)
    if (!sameCamera(views[v], cameras[v]))
      return makeError("the mesh and the SDF scenes are framed differently; the views would not be comparable");
  return {};
}

// One row into `result`: an error or exception fails that row only (said, and recorded in it).
void runRow(const Group& group, const RowSpec& spec, std::size_t index, std::size_t total, RowResult& result) {
  result.spec = spec;
  Status status;
  try {
    status = captureRow(group, spec, index, total, result);
  } catch (const std::exception& e) {
    status = makeError(e.what());
  }
  if (!status.ok()) {
    result.ok = false;
    result.error = status.error().message;
    std::fprintf(stderr, "\n%s: failed: %s\n", spec.label.c_str(), result.error.c_str());
  }
}

// The group's rows, each saved as it finishes; those past the time limit listed as not run.
Status captureRows(const Group& group, const std::vector<RowSpec>& rows, std::vector<RowResult>& results,
                   std::size_t& index, std::size_t total, const RunInfo& info, const Progress& progress) {
  for (const RowSpec& spec : rows) {
    if (const std::optional<std::string> why = progress.refusal(results)) {
      addNotRun(spec, *why, results);
      ++index;
      continue;
    }
    runRow(group, spec, index++, total, results.emplace_back());
    ENGINE_TRY(progress.save(info, results));
  }
  return {};
}

// The rows one Viewer draws: the mesh rows (Method::Mesh keeps the scene's triangles) or the SDF
// rows (the scene baked at each row's K). One Viewer at a time: each owns a device.
Status captureGroup(const Options& options, const Subject& subject, const std::vector<RowSpec>& rows,
                    std::vector<render::CameraView>& cameras, std::vector<TruthImage>& truth,
                    std::vector<RowResult>& results, std::size_t& index, std::size_t total,
                    std::optional<RunInfo>& info, const Progress& progress) {
  ENGINE_TRY_ASSIGN(std::unique_ptr<samples::Viewer> viewer, openViewer(options, rows.front()));
  if (!info) {
    info = runInfo(options, viewer->context(), subject);
    info->rowsPlanned = total;
  }
  const glm::vec3 size = viewer->boundsMax() - viewer->boundsMin();
  const double diagonal = glm::length(glm::dvec3(size));
  ENGINE_TRY_ASSIGN(const std::vector<std::size_t> sceneCameras, sceneCameraViews(*viewer, options));
  ENGINE_TRY(frameViews(*viewer, options, subject, sceneCameras, cameras, truth, *info));

  // The meshes Measurement draws for the mesh rows live in a pool of its own on the same device.
  auto pool = std::make_unique<render::MeshPool>(viewer->context());
  ecs::Registry meshes;
  if (rows.front().isMesh() && subject.scene) {
    render::instantiateScene(*subject.scene, meshes, *pool);
    scene::updateWorldTransforms(meshes);
  }
  {
    const VkExtent2D extent{options.width, options.height};
    // Scene objects: the SDF rows' registry also holds the triangle nodes, in the Viewer's pool.
    render::MeshPool& measuredPool = options.objects && !rows.front().isMesh() ? viewer->meshPool() : *pool;
    ENGINE_TRY_ASSIGN(std::unique_ptr<Measurement> measurement,
                      Measurement::create(viewer->context(), measuredPool, extent));
    const Group group{options, extent, subject, *viewer, *measurement,
                      rows.front().isMesh() ? meshes : viewer->registry(), cameras, sceneCameras, truth, diagonal};
    ENGINE_TRY(captureRows(group, rows, results, index, total, *info, progress));
    viewer->context().waitIdle();
  }
  meshes.clear();
  pool.reset();
  return viewer->close();  // an error if the validation layers reported anything
}

// The rows each Viewer draws: the mesh rows, then the SDF rows; with --objects one Viewer per K,
// since scene objects are baked when the scene loads (a new K does not re-bake them).
std::vector<std::vector<RowSpec>> groupRows(const Options& options, const std::vector<RowSpec>& meshRows,
                                            const std::vector<RowSpec>& sdfRows) {
  std::vector<std::vector<RowSpec>> groups;
  if (!meshRows.empty()) groups.push_back(meshRows);
  if (!options.objects) {
    if (!sdfRows.empty()) groups.push_back(sdfRows);
    return groups;
  }
  std::vector<int> ks;  // in row order; trilinear rows add 2K to the --resolutions
  for (const RowSpec& row : sdfRows)
    if (std::find(ks.begin(), ks.end(), row.resolution) == ks.end()) ks.push_back(row.resolution);
  for (const int k : ks) {
    std::vector<RowSpec> atK;
    for (const RowSpec& row : sdfRows)
      if (row.resolution == k) atK.push_back(row);
    groups.push_back(std::move(atK));
  }
  return groups;
}

}  // namespace

// What the end of a capture writes into --out, removed at its start: an interrupted capture left
// an earlier run's results.md and charts beside its own partial CSV and JSON, one folder of two runs.
constexpr const char* kFinalOutputs[] = {"results.md", "objects.csv", "time_vs_k.png", "normal_error_vs_bytes.png",
                                         "work_vs_k.png"};

Status run(const Options& options, int& failedRows) {
  std::error_code ec;
  std::filesystem::create_directories(options.out / "images", ec);
  if (ec) return makeError("--out: cannot create '" + options.out.string() + "': " + ec.message());
  // A capture that ends before its first image (no device, a bad subject) leaves no empty folder.
  struct RemoveIfEmpty {
    std::filesystem::path folder;
    ~RemoveIfEmpty() {
      std::error_code ignored;
      if (std::filesystem::is_empty(folder, ignored)) std::filesystem::remove(folder, ignored);
    }
  } images{options.out / "images"};
  for (const char* name : kFinalOutputs) std::filesystem::remove(options.out / name, ec);
  Subject subject;
  ENGINE_TRY(loadSubject(options, subject));
  const std::vector<RowSpec> rows = buildRows(options);
  std::vector<RowSpec> meshRows, sdfRows;
  for (const RowSpec& row : rows) (row.isMesh() ? meshRows : sdfRows).push_back(row);
  std::vector<render::CameraView> cameras;
  std::vector<TruthImage> truth;
  std::vector<RowResult> results;
  std::size_t index = 0;
  std::optional<RunInfo> info;
  const Progress progress(options);
  for (const std::vector<RowSpec>& group : groupRows(options, meshRows, sdfRows)) {
    // Out of time: the group's rows are listed, without opening a device for them.
    if (const std::optional<std::string> why = progress.refusal(results)) {
      for (const RowSpec& spec : group) addNotRun(spec, *why, results);
      index += group.size();
      continue;
    }
    ENGINE_TRY(captureGroup(options, subject, group, cameras, truth, results, index, rows.size(), info, progress));
  }
  std::fprintf(stderr, "\n");
  if (!info) return makeError("--methods: no rows to capture");
  info->complete = true;
  ENGINE_TRY(progress.save(*info, results));  // the rows not run after the last save included
  ENGINE_TRY(writeObjectsCsv(options.out / "objects.csv", *info, results));
  ENGINE_TRY(writeMarkdown(options.out, *info, results));
  failedRows = int(std::count_if(results.begin(), results.end(), [](const RowResult& r) { return !r.ok; }));
  std::fprintf(stderr, "wrote %s (%zu rows, %d failed)\n", (options.out / "results.md").string().c_str(),
               results.size(), failedRows);
  return {};
}

}  // namespace capture
