#version 460
// After the cells' early depth stage (hit_depth.glsl; chosen on software rasterizers only): the
// depth buffer holds the faces of the boxes that found the nearest hits; this pass, drawn over the
// cell objects' screen rectangle (cells_resolve.vert) before any other prepass draw, replaces them
// with the hits' true depth and clears the per-pixel buffer for the next frame. Visibility is left
// as the early stage wrote it.
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"

layout(push_constant, scalar) uniform Push { HermitePushConstants pc; };
layout(buffer_reference, scalar) buffer HitDepthsRef { uint depths[]; };

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;
  uint index = uint(pixel.y * int(frame.viewport.x) + pixel.x);
  uint bits = HitDepthsRef(pc.hitDepths).depths[index];
  if (bits == 0u) discard;  // no hit here (reverse-Z depth 0 is infinitely far)
  HitDepthsRef(pc.hitDepths).depths[index] = 0u;
  gl_FragDepth = uintBitsToFloat(bits);
}
