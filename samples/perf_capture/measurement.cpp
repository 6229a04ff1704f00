#include "measurement.h"

#include <fmt/format.h>

#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/render/features.h"
#include "hermite_sdf/render/sphere_trace_feature.h"
#include "tuning.h"
#include "shared/host_device.h"

namespace capture {
namespace {

using namespace engine;

// A pass's milliseconds; 0 on a device without timestamps (no timings at all: the report leaves
// the time columns out). A frame with timings but not this pass's is an error, not a 0 in the
// table: the renderer's pass names and these would have drifted apart.
Expected<double> timingOf(const std::vector<gpu::GpuTiming>& timings, const char* name) {
  if (timings.empty()) return 0.0;
  if (const gpu::GpuTiming* timing = gpu::findTiming(timings, name)) return timing->milliseconds;
  return makeError(fmt::format("the frame has no GPU timing named '{}' (the renderer's pass names changed?)", name));
}

}  // namespace

Expected<TimedFrame> timeFrame(samples::Viewer& viewer) {
  ENGINE_TRY(viewer.step());
  render::Renderer& renderer = viewer.renderer();
  renderer.finish();
  const auto& timings = renderer.lastTimings();
  ENGINE_TRY_ASSIGN(const double frame, timingOf(timings, "frame"));
  ENGINE_TRY_ASSIGN(const double prepass, timingOf(timings, "depth prepass"));
  ENGINE_TRY_ASSIGN(const double opaque, timingOf(timings, "opaque"));
  return TimedFrame{frame, prepass, opaque, timings, renderer.lastPipelineStatistics()};
}

Expected<std::unique_ptr<Measurement>> Measurement::create(const gpu::Context& context, render::MeshPool& pool,
                                                           VkExtent2D extent) {
  auto measurement = std::unique_ptr<Measurement>(new Measurement());
  render::RendererDesc desc;
  desc.formats.color = VK_FORMAT_R32G32B32A32_SFLOAT;
  measurement->renderer_ = std::make_unique<render::Renderer>(context, desc, extent);
  render::Renderer& r = *measurement->renderer_;
  ENGINE_TRY(hsdf::addSceneFeatures(r, pool));
  return measurement;
}

GpuReadback Measurement::measure(const ecs::Registry& registry, const render::CameraView& camera,
                                 const samples::TuningState& tuning) {
  hsdf::HermiteCellFeature::Settings& cells = renderer_->feature<hsdf::HermiteCellFeature>()->settings();
  hsdf::SphereTraceFeature::Settings& tracers = renderer_->feature<hsdf::SphereTraceFeature>()->settings();
  samples::applyTuning(tuning, cells, tracers);
  samples::applyCapturedFrames(cells, tracers);  // the one frame measured draws whole assets
  render::FrameSettings settings;
  settings.debugView = DEBUG_VIEW_NORMALS;
  settings.countWork = true;
  renderer_->renderFrame(registry, camera, settings);
  GpuReadback readback;
  readback.depth = renderer_->readbackDepth();
  readback.normalColor = renderer_->readbackColorFloat().value();  // a float target by construction
  readback.work = renderer_->readbackWorkCounters();
  const shader::WorkTotals totals = renderer_->readbackWorkTotals();
  readback.raysOutOfSteps = totals.raysOutOfSteps;
  readback.tileEntriesWalked = totals.tileEntriesWalked;
  readback.tileEntriesTested = totals.tileEntriesTested;
  readback.tileMaskWordsRead = totals.tileMaskWordsRead;
  return readback;
}

}  // namespace capture
