#version 460
// One level of the depth pyramid (engine::render::DepthPyramid): each texel holds the farthest
// depth (reverse-Z: the minimum) of the texels of the level below that it covers. A texel on an odd
// edge covers the one or two texels that exist (the clamp), so every level is conservative for
// occlusion tests: nothing drawn at a pixel is farther than the pyramid over it.
#extension GL_GOOGLE_include_directive : require
#include "shared/host_device.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(buffer_reference, scalar) buffer PyramidRef { float depth[]; };
layout(push_constant, scalar) uniform Push { DepthPyramidPushConstants pc; };

float sourceDepth(uint x, uint y) {
  x = min(x, pc.srcWidth - 1u);
  y = min(y, pc.srcHeight - 1u);
  return PyramidRef(pc.pyramid).depth[pc.srcOffset + y * pc.srcWidth + x];
}

void main() {
  uvec2 texel = gl_GlobalInvocationID.xy;
  if (texel.x >= pc.dstWidth || texel.y >= pc.dstHeight) return;
  uvec2 src = texel * 2u;
  float farthest = min(min(sourceDepth(src.x, src.y), sourceDepth(src.x + 1u, src.y)),
                       min(sourceDepth(src.x, src.y + 1u), sourceDepth(src.x + 1u, src.y + 1u)));
  PyramidRef(pc.pyramid).depth[pc.dstOffset + texel.y * pc.dstWidth + texel.x] = farthest;
}
