#pragma once
// The capture's frame step: one renderer that times frames as a user sees them (RGBA8 sRGB colour,
// counters off) and one with a float colour target that measures (DEBUG_VIEW_NORMALS read back as
// floats, depth, per-pixel work counters), both with every SDF feature and the mesh feature.
//
// THE PLACE TO SWITCH TO THE SHARED FRAME STEP: this file drives engine::render::Renderer directly
// because the shared Viewer / TuningState of samples/common (issue "tuning UI") had not landed when
// the capture was written. When it has, FrameStep becomes a thin wrapper over the Viewer and the
// rest of the capture stays as it is (it only calls timeFrame / measureFrame / screenshot).
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/core/expected.h"
#include "engine/ecs/registry.h"
#include "engine/gpu/context.h"
#include "engine/gpu/gpu_timer.h"
#include "engine/gpu/pipeline_statistics.h"
#include "engine/render/camera_view.h"
#include "engine/render/mesh_pool.h"
#include "engine/render/renderer.h"
#include "metrics.h"

namespace capture {

struct TimedFrame {
  double frameMs = 0.0;    // "frame": the whole command buffer
  double prepassMs = 0.0;  // "depth prepass"
  double shadingMs = 0.0;  // "opaque"
  std::vector<engine::gpu::PipelineStatistics> statistics;  // per pass; empty without the feature
};

class FrameStep {
 public:
  static engine::Expected<std::unique_ptr<FrameStep>> create(const engine::gpu::Context& context,
                                                            engine::render::MeshPool& pool, VkExtent2D extent);
  // Renders one frame and waits for it (so each frame's timestamps are its own).
  TimedFrame timeFrame(const engine::ecs::Registry& registry, const engine::render::CameraView& camera);
  // Renders the frame with the normals debug view and work counters and reads it back.
  GpuReadback measureFrame(const engine::ecs::Registry& registry, const engine::render::CameraView& camera);
  // The last timed frame, RGBA8 sRGB.
  std::vector<std::uint8_t> screenshot();

 private:
  std::unique_ptr<engine::render::Renderer> timing_;
  std::unique_ptr<engine::render::Renderer> measuring_;
};

}  // namespace capture
