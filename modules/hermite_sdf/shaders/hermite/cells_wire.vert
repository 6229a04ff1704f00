#version 460
// Box wireframe debug view of the Hermite cells: the 12 edges of each drawn cell's proxy box (the
// whole cell with HERMITE_FLAG_WHOLE_CELLS; record_cell.glsl) as a line list.
// Its indirect commands are the boxes' with 24 vertices per instance (cell_feature.cpp).
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/box.glsl"
#include "hermite/record_cell.glsl"

layout(push_constant, scalar) uniform Push { HermitePushConstants pc; };

layout(location = 8) in uvec4 inCell;

void main() {
  if (gl_VertexIndex >= 24) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside: clipped away
    return;
  }
  HermiteDraw draw = hermiteDraw(pc.draws, pc.drawBase + gl_DrawID);
  ObjectData object = ObjectsRef(pc.draw.objects).objects[draw.object];
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;
  vec3 lo, hi;
  proxyBox(inCell.w, draw.flags, lo, hi);
  vec3 local = mix(lo, hi, wireCorner(gl_VertexIndex));
  vec3 objectPosition = draw.gridOriginSpacing.xyz + draw.gridOriginSpacing.w * (vec3(inCell.xyz) + local);
  gl_Position = frame.viewProj * (object.model * vec4(objectPosition, 1.0));
}
