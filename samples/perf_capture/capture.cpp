#include "capture.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "capture_rows.h"
#include "engine/core/image_io.h"
#include "engine/gpu/context.h"
#include "engine/platform/camera_controller.h"
#include "engine/render/mesh_pool.h"
#include "engine/render/scene_instantiate.h"
#include "engine/scene/gltf_loader.h"
#include "engine/scene/transform.h"
#include "frame_step.h"
#include "ground_truth.h"
#include "hermite_sdf/analytic.h"
#include "hermite_sdf/cells.h"
#include "hermite_sdf/field.h"
#include "hermite_sdf/mesh_source.h"
#include "metrics.h"
#include "report.h"

namespace capture {
namespace {

using namespace engine;

constexpr float kFovY = 0.8f;

// What is captured: the source the fields are baked from, its ground truth and, for a scene, its
// triangle meshes as the mesh rows draw them.
struct Subject {
  std::string name;
  hsdf::Aabb bounds;  // of the source surface: the framing of every view (not the padded grid)
  std::unique_ptr<hsdf::SdfSource> source;
  std::unique_ptr<TruthSurface> truth;
  ecs::Registry meshRegistry;  // the scene's meshes (empty for a shape)
  std::uint64_t meshScalars = 0, meshBytes = 0;
};

Status loadSubject(const Options& options, render::MeshPool& pool, Subject& subject) {
  if (!options.shape.empty()) {
    subject.name = options.shape;
    ENGINE_TRY_ASSIGN(subject.source, hsdf::makeAnalyticSource(options.shape));
    ENGINE_TRY_ASSIGN(auto truthSource, hsdf::makeAnalyticSource(options.shape));
    subject.truth = analyticSurface(std::move(truthSource));
    subject.bounds = subject.source->bounds();
    return {};
  }
  subject.name = options.scene.filename().string();
  ENGINE_TRY_ASSIGN(scene::SceneData data, scene::loadGltf(options.scene));
  ENGINE_TRY(scene::checkFlattenable(data).withContext(options.scene.string()));
  const scene::TriangleSoup soup = scene::flattenTriangles(data);
  if (soup.indices.empty()) return makeError(options.scene.string() + ": no triangle meshes to capture");
  ENGINE_TRY_ASSIGN(auto mesh, hsdf::MeshSource::create(soup).withContext(options.scene.string()));
  subject.bounds = mesh->bounds();
  subject.source = std::move(mesh);
  subject.truth = meshSurface(soup);
  render::instantiateScene(data, subject.meshRegistry, pool);
  scene::updateWorldTransforms(subject.meshRegistry);
  // As the mesh pool stores them: position + normal per vertex, 32-bit indices.
  subject.meshScalars = 3 * soup.positions.size() + soup.indices.size();
  subject.meshBytes = 24 * soup.positions.size() + 4 * soup.indices.size();
  return {};
}

double diagonal(const hsdf::Aabb& b) { return glm::length(b.size()); }

std::vector<render::CameraView> orbitViews(const Subject& subject, std::uint32_t views, VkExtent2D extent) {
  std::vector<render::CameraView> cameras;
  const glm::vec3 lo(subject.bounds.min), hi(subject.bounds.max);
  const float znear = float(0.01 * diagonal(subject.bounds));
  for (std::uint32_t v = 0; v < views; ++v) {
    const platform::OrbitController orbit = platform::framingOrbit(lo, hi, kFovY, int(v));
    cameras.push_back(render::CameraView::lookAt(orbit.eye(), orbit.target, kFovY, znear,
                                                 float(extent.width) / float(extent.height)));
  }
  return cameras;
}

Expected<std::shared_ptr<const hsdf::SdfAsset>> bake(const Subject& subject, int resolution) {
  ENGINE_TRY_ASSIGN(hsdf::GridSpec grid, hsdf::fitGrid(subject.bounds, resolution, 1));
  hsdf::BakeOptions options;
  options.progress = [resolution](float fraction) {
    std::fprintf(stderr, "\rbaking K=%d %3d%%   ", resolution, int(fraction * 100.0f));
    return true;
  };
  ENGINE_TRY_ASSIGN(hsdf::HermiteField field, hsdf::bakeHermiteField(*subject.source, grid, options));
  return hsdf::makeSdfAsset(subject.name + " K=" + std::to_string(resolution), std::move(field), subject.bounds);
}

void storage(const RowSpec& spec, const Subject& subject, const hsdf::SdfAsset* asset, RowResult& result) {
  if (spec.isMesh()) {
    result.storedScalars = subject.meshScalars;
    result.storedBytes = subject.meshBytes;
    return;
  }
  const std::uint64_t k = std::uint64_t(spec.resolution), dense = k * k * k;
  if (spec.render == hsdf::RenderMethod::TrilinearSphereTrace) {
    result.storedScalars = dense;
    result.storedBytes = dense * (spec.fp16 ? 2 : 4);
  } else if (spec.render == hsdf::RenderMethod::HermiteSphereTrace) {
    result.storedScalars = 4 * dense;
    result.storedBytes = 4 * dense * (spec.fp16 ? 2 : 4);
  } else {
    result.cells = asset->cells.records.size();
    result.storedScalars = asset->cells.stored_scalars();
    result.storedBytes = result.cells * (spec.fp16 ? sizeof(hsdf::CellRecordHalf) : sizeof(hsdf::CellRecord));
  }
}

double median(std::vector<double> v) { return percentile(std::move(v), 0.5); }

void addStatistics(const TimedFrame& frame, double views, RowResult& result) {
  for (const gpu::PipelineStatistics& s : frame.statistics) {
    const bool prepass = s.name == "depth prepass";
    (prepass ? result.prepassFsInvocations : result.shadingFsInvocations) += double(s.fragmentShaderInvocations) / views;
    result.fsInvocations += double(s.fragmentShaderInvocations) / views;
    result.vsInvocations += double(s.vertexShaderInvocations) / views;
    result.clippedPrimitives += double(s.clippingPrimitives) / views;
  }
}

std::string fileName(const std::string& label) {
  std::string name;
  for (char c : label) name += (std::isalnum(static_cast<unsigned char>(c)) ? c : '_');
  return name;
}

struct Context {
  const Options& options;
  VkExtent2D extent;
  FrameStep& step;
  const Subject& subject;
  const std::vector<render::CameraView>& cameras;
  const std::vector<TruthImage>& truth;
};

// One row over every view: warm-up, timed frames, one measured frame.
void captureRow(const Context& ctx, const RowSpec& spec, const ecs::Registry& registry, std::size_t index,
                std::size_t total, RowResult& result) {
  QualityAccumulator quality(diagonal(ctx.subject.bounds));
  std::vector<double> frameMs, prepassMs, shadingMs;
  const double views = double(ctx.cameras.size());
  for (std::size_t v = 0; v < ctx.cameras.size(); ++v) {
    std::fprintf(stderr, "\r[%zu/%zu] %-26s view %zu/%zu   ", index + 1, total, spec.label.c_str(), v + 1,
                 ctx.cameras.size());
    const render::CameraView& camera = ctx.cameras[v];
    for (std::uint32_t f = 0; f < ctx.options.warmup; ++f) ctx.step.timeFrame(registry, camera);
    TimedFrame last;
    for (std::uint32_t f = 0; f < ctx.options.frames; ++f) {
      last = ctx.step.timeFrame(registry, camera);
      frameMs.push_back(last.frameMs);
      prepassMs.push_back(last.prepassMs);
      shadingMs.push_back(last.shadingMs);
    }
    addStatistics(last, views, result);
    if (v == 0) {
      result.image = "images/" + fileName(spec.label) + ".png";
      const Status written = writePng(ctx.options.out / result.image, ctx.step.screenshot(), ctx.extent.width,
                                      ctx.extent.height, 4);
      if (!written.ok()) throw std::runtime_error(written.error().message);
    }
    quality.add(ctx.truth[v], ctx.step.measureFrame(registry, camera), camera);
  }
  result.gpuMsMedian = median(frameMs);
  result.gpuMsP95 = percentile(frameMs, 0.95);
  result.prepassMs = median(prepassMs);
  result.shadingMs = median(shadingMs);
  result.quality = quality.result();
  result.ok = result.quality.coveredPixels > 0;
  if (!result.ok) result.error = "drew nothing in any view";
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
  const std::string commit = commandOutput("git -C '" HSDF_SOURCE_DIR "' describe --always --dirty 2>/dev/null");
  info.commit = commit.empty() ? "unknown" : commit;
  const std::time_t now = std::time(nullptr);
  char date[64];
  std::strftime(date, sizeof(date), "%Y-%m-%d %H:%M:%S UTC", std::gmtime(&now));
  info.date = date;
  info.scene = subject.name;
  info.width = options.width;
  info.height = options.height;
  info.views = options.views;
  info.frames = options.frames;
  info.warmup = options.warmup;
  info.pipelineStatistics = context.capabilities().pipelineStatistics;
  info.softwareRasterizer = context.capabilities().isSoftwareRasterizer;
  return info;
}

gpu::DevicePreference devicePreference(const std::string& name) {
  if (name == "gpu") return gpu::DevicePreference::Hardware;
  if (name == "lavapipe") return gpu::DevicePreference::Software;
  return gpu::DevicePreference::Auto;
}

Status checkImageSize(const Options& options, const gpu::Context& context) {
  VkPhysicalDeviceProperties properties;
  vkGetPhysicalDeviceProperties(context.physicalDevice(), &properties);
  const std::uint32_t limit = properties.limits.maxImageDimension2D;
  if (options.width <= limit && options.height <= limit) return {};
  return makeError(fmt::format("--size {}x{}: the device '{}' supports images up to {} pixels per side",
                               options.width, options.height, context.capabilities().deviceName, limit));
}

// Renders every row into `results`; the SDF rows of one K share one baked asset.
void captureRows(const Context& ctx, const std::vector<RowSpec>& rows, std::vector<RowResult>& results) {
  ecs::Registry sdfRegistry;
  const ecs::Entity entity = sdfRegistry.create();
  sdfRegistry.emplace<scene::Transform>(entity);
  scene::updateWorldTransforms(sdfRegistry);
  std::shared_ptr<const hsdf::SdfAsset> asset;
  std::optional<std::string> bakeError;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const RowSpec& spec = rows[i];
    RowResult& result = results.emplace_back();
    result.spec = spec;
    if (!spec.isMesh() && (!asset || asset->field.grid.resolution != spec.resolution)) {
      asset.reset();  // one K at a time in memory
      auto baked = bake(ctx.subject, spec.resolution);
      bakeError = baked ? std::nullopt : std::optional<std::string>(baked.error().message);
      if (baked) asset = std::move(baked.value());
    }
    if (!spec.isMesh() && !asset) {
      result.error = "bake failed: " + bakeError.value_or("?");
      continue;
    }
    if (!spec.isMesh()) {
      hsdf::HermiteSdfRenderable renderable;
      renderable.asset = asset;
      renderable.method = spec.render;
      renderable.subdivisions = spec.subdivisions == 0 ? 3 : spec.subdivisions;
      renderable.refineSteps = spec.refine;
      renderable.normals = spec.normals;
      renderable.halfPrecision = spec.fp16;
      sdfRegistry.emplaceOrReplace<hsdf::HermiteSdfRenderable>(entity, renderable);
    }
    storage(spec, ctx.subject, asset.get(), result);
    try {
      captureRow(ctx, spec, spec.isMesh() ? ctx.subject.meshRegistry : sdfRegistry, i, rows.size(), result);
    } catch (const std::exception& e) {
      result.ok = false;
      result.error = e.what();
    }
    if (!result.ok) std::fprintf(stderr, "\n%s: failed: %s\n", spec.label.c_str(), result.error.c_str());
  }
  std::fprintf(stderr, "\n");
}

}  // namespace

Status run(const Options& options, int& failedRows) {
  std::error_code ec;
  std::filesystem::create_directories(options.out / "images", ec);
  if (ec) return makeError("--out: cannot create '" + options.out.string() + "': " + ec.message());
  gpu::ContextDesc desc;
  desc.applicationName = "hermite_sdf perf capture";
  desc.device = devicePreference(options.device);
  ENGINE_TRY_ASSIGN(std::unique_ptr<gpu::Context> context, gpu::Context::create(desc));
  ENGINE_TRY(checkImageSize(options, *context));
  const VkExtent2D extent{options.width, options.height};
  auto pool = std::make_unique<render::MeshPool>(*context);
  Subject subject;
  ENGINE_TRY(loadSubject(options, *pool, subject));
  const std::vector<render::CameraView> cameras = orbitViews(subject, options.views, extent);
  std::vector<TruthImage> truth;
  for (std::size_t v = 0; v < cameras.size(); ++v) {
    std::fprintf(stderr, "\rground truth view %zu/%zu   ", v + 1, cameras.size());
    truth.push_back(castTruth(*subject.truth, cameras[v], int(extent.width), int(extent.height)));
  }
  std::vector<RowResult> results;
  {
    ENGINE_TRY_ASSIGN(std::unique_ptr<FrameStep> step, FrameStep::create(*context, *pool, extent));
    const Context ctx{options, extent, *step, subject, cameras, truth};
    captureRows(ctx, buildRows(options), results);
    context->waitIdle();
  }
  const RunInfo info = runInfo(options, *context, subject);
  ENGINE_TRY(writeCsv(options.out / "results.csv", info, results));
  ENGINE_TRY(writeJson(options.out / "results.json", info, results));
  ENGINE_TRY(writeMarkdown(options.out, info, results));
  failedRows = int(std::count_if(results.begin(), results.end(), [](const RowResult& r) { return !r.ok; }));
  subject.meshRegistry.clear();
  pool.reset();
  // With HSDF_VALIDATION=1 (the CI test) a validation message fails the capture.
  if (const std::uint32_t messages = context->validationMessageCount(); messages > 0)
    return makeError(std::to_string(messages) + " Vulkan validation message(s); see the log above");
  std::fprintf(stderr, "wrote %s (%zu rows, %d failed)\n", (options.out / "results.md").string().c_str(),
               results.size(), failedRows);
  return {};
}

}  // namespace capture
