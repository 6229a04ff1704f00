#pragma once
// How the capture renders: every frame goes through the shared frame step, samples::Viewer (the
// scene runner's): the Viewer loads the scene, bakes through the module bake job, applies each
// row's TuningState and renders the timed frames (RGBA8 sRGB, as a user sees them).
//
// Measuring needs what the Viewer does not offer (yet): a float colour target (normals of
// DEBUG_VIEW_NORMALS without 8-bit quantization) and the renderer's per-pixel work counters. So a
// Measurement renderer on the Viewer's device draws the Viewer's registry once more per view with
// those on. When ViewerDesc gains a colour format and Viewer::step frame settings, this becomes a
// second Viewer step and this class goes away.
#include <memory>
#include <vector>

#include "engine/core/expected.h"
#include "engine/ecs/registry.h"
#include "engine/gpu/context.h"
#include "engine/gpu/pipeline_statistics.h"
#include "engine/render/camera_view.h"
#include "engine/render/mesh_pool.h"
#include "engine/render/renderer.h"
#include "metrics.h"
#include "viewer.h"

namespace capture {

struct TimedFrame {
  double frameMs = 0.0;    // "frame": the whole command buffer
  double prepassMs = 0.0;  // "depth prepass"
  double shadingMs = 0.0;  // "opaque"
  std::vector<engine::gpu::GpuTiming> timings;  // every named scope ("prepare", "cells tiling", ...)
  std::vector<engine::gpu::PipelineStatistics> statistics;  // per pass; empty without the feature
};

// One Viewer step, waited for, so that each frame's timestamps are its own.
engine::Expected<TimedFrame> timeFrame(samples::Viewer& viewer);

class Measurement {
 public:
  // `pool` holds the meshes of the registries it will draw (the Viewer's SDF registry has none).
  static engine::Expected<std::unique_ptr<Measurement>> create(const engine::gpu::Context& context,
                                                               engine::render::MeshPool& pool, VkExtent2D extent);
  // Renders the registry with the normals debug view and work counters and reads it back, its
  // features set as `tuning` sets the Viewer's (the row's culling, tiles, early depth...).
  GpuReadback measure(const engine::ecs::Registry& registry, const engine::render::CameraView& camera,
                      const samples::TuningState& tuning);

 private:
  std::unique_ptr<engine::render::Renderer> renderer_;
};

}  // namespace capture
