#version 460
// The shading pass's proxy: two triangles over the screen rectangle that holds every drawn cell
// object (HermitePushConstants::screenRect, computed from the objects' grid boxes on the CPU).
// Pixels outside it cannot show a cell, and a full-screen pass would still run the resolve for
// them: on lavapipe a discarded fragment costs the whole shader (docs/perf/cells-breakdown-lavapipe.md).
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"

layout(push_constant, scalar) uniform Push { HermitePushConstants pc; };

const int kQuadCorners[6] = int[6](0, 1, 2, 2, 1, 3);

void main() {
  int corner = kQuadCorners[gl_VertexIndex];
  vec2 t = vec2(corner & 1, corner >> 1);
  gl_Position = vec4(mix(pc.screenRect.xy, pc.screenRect.zw, t), 0.0, 1.0);
}
