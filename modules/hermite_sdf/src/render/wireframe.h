#pragma once
// The wireframe debug view (DEBUG_VIEW_WIREFRAME) shared by the cell feature and the sphere
// tracers: proxy boxes' edges as a line list over the shaded frame.
#include "engine/gpu/pipeline.h"
#include "engine/render/render_feature.h"

namespace hsdf {

// The pipeline state of every wireframe pipeline: lines, no culling, tested against the prepass
// depth (hidden where the surface is in front of them) without writing it, into the colour target.
// The caller sets the name, shaders, vertex layout and push constants.
inline engine::gpu::GraphicsPipelineDesc wireframePipelineDesc(const engine::render::RendererFormats& formats) {
  engine::gpu::GraphicsPipelineDesc wire;
  wire.topology = VK_PRIMITIVE_TOPOLOGY_LINE_LIST;
  wire.cullMode = VK_CULL_MODE_NONE;
  wire.depthFormat = formats.depth;
  wire.colorFormats = {formats.color};
  wire.depthWrite = false;
  wire.depthCompare = VK_COMPARE_OP_GREATER_OR_EQUAL;
  return wire;
}

}  // namespace hsdf
