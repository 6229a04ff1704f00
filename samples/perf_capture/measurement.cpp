#include "measurement.h"

#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/render/features.h"
#include "hermite_sdf/render/sphere_trace_feature.h"
#include "tuning.h"
#include "shared/host_device.h"

namespace capture {
namespace {

using namespace engine;

double timingOf(const std::vector<gpu::GpuTiming>& timings, const char* name) {
  for (const gpu::GpuTiming& t : timings)
    if (t.name == name) return t.milliseconds;
  return 0.0;
}

}  // namespace

Expected<TimedFrame> timeFrame(samples::Viewer& viewer) {
  ENGINE_TRY(viewer.step());
  render::Renderer& renderer = viewer.renderer();
  renderer.finish();
  const auto& timings = renderer.lastTimings();
  return TimedFrame{timingOf(timings, "frame"), timingOf(timings, "depth prepass"), timingOf(timings, "opaque"),
                    timings, renderer.lastPipelineStatistics()};
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
  samples::applyTuning(tuning, renderer_->feature<hsdf::HermiteCellFeature>()->settings(),
                       renderer_->feature<hsdf::SphereTraceFeature>()->settings());
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
