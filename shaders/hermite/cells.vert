#version 460
// Hermite cells: one instance per kept cell, drawn as its box (36 vertices from gl_VertexIndex).
// The cell's Hermite data arrive as instance-rate attributes and are handed to the fragment
// shader unchanged (flat), together with the ray set-up in cell-local coordinates.
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/box.glsl"
#include "hermite/proxy_dilation.glsl"

layout(push_constant, scalar) uniform Push { HermitePushConstants pc; };
layout(buffer_reference, scalar) readonly buffer HermiteDrawsRef { HermiteDraw draws[]; };

layout(location = 0) in vec4 inCorners[8];
layout(location = 8) in uvec4 inCell;  // x, y, z, class

layout(location = 0) flat out vec4 outCorners[8];
layout(location = 8) flat out uvec4 outCell;
layout(location = 9) flat out uint outDraw;
layout(location = 10) out vec3 outLocal;              // this vertex in cell-local coordinates
layout(location = 11) flat out vec3 outCameraLocal;   // the eye in cell-local coordinates
layout(location = 12) flat out uint outRecord;        // index of the cell record in its buffer
layout(location = 13) flat out float outDilation;     // how far the proxy reaches beyond the cell, cells

precise gl_Position;

void main() {
  uint drawIndex = pc.drawBase + gl_DrawID;
  HermiteDraw draw = HermiteDrawsRef(pc.draws).draws[drawIndex];
  ObjectData object = ObjectsRef(pc.draw.objects).objects[draw.object];
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;

  vec3 cell = vec3(inCell.xyz);
  float h = draw.gridOriginSpacing.w;
  float dilation = proxyDilation(frame, object, draw.gridOriginSpacing.xyz + h * (cell + 0.5), h);
  vec3 local = boxCorner(gl_VertexIndex, (object.flags & OBJECT_FLAG_MIRRORED) != 0u) * (1.0 + 2.0 * dilation) - dilation;
  vec3 objectPosition = draw.gridOriginSpacing.xyz + h * (cell + local);
  vec3 cameraObject = (object.invModel * vec4(frame.cameraPosition.xyz, 1.0)).xyz;

  outCorners = inCorners;
  outCell = inCell;
  outDraw = drawIndex;
  outRecord = uint(gl_InstanceIndex);  // firstInstance of the command = first record of the range
  outLocal = local;
  outDilation = dilation;
  outCameraLocal = (cameraObject - draw.gridOriginSpacing.xyz) / h - cell;
  gl_Position = frame.viewProj * (object.model * vec4(objectPosition, 1.0));
}
