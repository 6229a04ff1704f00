#include "frame_step.h"

#include "engine/render/mesh_feature.h"
#include "hermite_sdf/cell_feature.h"
#include "hermite_sdf/sphere_trace_feature.h"
#include "shared/host_device.h"

namespace capture {
namespace {

using namespace engine;

Expected<std::unique_ptr<render::Renderer>> makeRenderer(const gpu::Context& context, render::MeshPool& pool,
                                                          VkExtent2D extent, VkFormat color) {
  render::RendererDesc desc;
  desc.formats.color = color;
  auto renderer = std::make_unique<render::Renderer>(context, desc, extent);
  ENGINE_TRY(renderer->addFeature(std::make_unique<render::MeshFeature>(pool)));
  ENGINE_TRY(renderer->addFeature(std::make_unique<hsdf::HermiteCellFeature>()));
  ENGINE_TRY(renderer->addFeature(std::make_unique<hsdf::SphereTraceFeature>()));
  return renderer;
}

double timingOf(const std::vector<gpu::GpuTiming>& timings, const char* name) {
  for (const gpu::GpuTiming& t : timings)
    if (t.name == name) return t.milliseconds;
  return 0.0;
}

}  // namespace

Expected<std::unique_ptr<FrameStep>> FrameStep::create(const gpu::Context& context, render::MeshPool& pool,
                                                       VkExtent2D extent) {
  auto step = std::unique_ptr<FrameStep>(new FrameStep());
  ENGINE_TRY_ASSIGN(step->timing_, makeRenderer(context, pool, extent, VK_FORMAT_R8G8B8A8_SRGB));
  ENGINE_TRY_ASSIGN(step->measuring_, makeRenderer(context, pool, extent, VK_FORMAT_R32G32B32A32_SFLOAT));
  return step;
}

TimedFrame FrameStep::timeFrame(const ecs::Registry& registry, const render::CameraView& camera) {
  timing_->renderFrame(registry, camera);
  timing_->finish();
  const auto& timings = timing_->lastTimings();
  return {timingOf(timings, "frame"), timingOf(timings, "depth prepass"), timingOf(timings, "opaque"),
          timing_->lastPipelineStatistics()};
}

GpuReadback FrameStep::measureFrame(const ecs::Registry& registry, const render::CameraView& camera) {
  render::FrameSettings settings;
  settings.debugView = DEBUG_VIEW_NORMALS;
  settings.countWork = true;
  measuring_->renderFrame(registry, camera, settings);
  GpuReadback readback;
  readback.depth = measuring_->readbackDepth();
  readback.normalColor = measuring_->readbackColorFloat().value();  // a float target by construction
  readback.work = measuring_->readbackWorkCounters();
  return readback;
}

std::vector<std::uint8_t> FrameStep::screenshot() { return timing_->readbackColor(); }

}  // namespace capture
