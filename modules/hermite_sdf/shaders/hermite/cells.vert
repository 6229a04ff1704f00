#version 460
// Hermite cells: one instance per kept cell, drawn as its box: its front faces as one triangle fan
// (8 vertices from gl_VertexIndex, box.glsl frontFanCorner), or all six faces as one strip (14) for
// near-plane cells drawn by back faces. Every varying is flat, so the triangulation is free: a
// list of 18 vertices per box (until issue 20) ran the vertex shader and its 150 bytes of output
// 2.25x as often.
// The cell's Hermite data arrive as instance-rate attributes and are handed to the fragment
// shader unchanged (flat); the fragment shader rebuilds the ray from gl_FragCoord and the record's
// anchor (pixel_ray.glsl, HermiteDraw::rayAnchor).
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/box.glsl"
#include "hermite/eye.glsl"
#include "hermite/cell_instance.glsl"
#include "hermite/proxy_dilation.glsl"
#include "hermite/record_cell.glsl"

layout(push_constant, scalar) uniform Push { HermitePushConstants pc; };

layout(location = 0) in vec4 inCorners[8];
layout(location = 8) in uvec4 inCell;  // x, y, z, class

layout(location = 0) flat out vec4 outCorners[8];
layout(location = 8) flat out uvec4 outCell;
layout(location = 9) flat out uint outDraw;
layout(location = 12) flat out uint outRecord;        // index of the cell record in its buffer
layout(location = 13) flat out float outDilation;     // how far the proxy reaches beyond the cell, cells

precise gl_Position;

void main() {
  uint drawIndex = pc.drawBase + gl_DrawID;
  uint drawRecord = hermiteDrawRecord(pc.draws, drawIndex);
  HermiteDraw draw = hermiteDrawAt(pc.draws, drawRecord);
  ObjectData object = ObjectsRef(pc.draw.objects).objects[draw.object];
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;

  vec3 cell = vec3(inCell.xyz);
  float h = draw.gridOriginSpacing.w;
  float dilation = proxyDilation(frame, object, draw.gridOriginSpacing.xyz + h * (cell + 0.5), h);
  vec3 cameraObject = (object.invModel * vec4(rayEyePoint(frame), 1.0)).xyz;
  vec3 cameraLocal = (cameraObject - draw.gridOriginSpacing.xyz) / h - cell;
  bool mirrored = (object.flags & OBJECT_FLAG_MIRRORED) != 0u;
  vec3 lo, hi;  // the cell's proxy box (record_cell.glsl), the part of the cell that can hold its roots
  proxyBox(inCell.w, draw.flags, lo, hi);
  vec3 corner = (draw.flags & HERMITE_FLAG_NEAR_CELL) != 0u
                    ? boxStripCorner(gl_VertexIndex, mirrored)
                    : frontFanCorner(gl_VertexIndex, viewerLocal(frame, object.invModel, cameraLocal), 0.5 * (lo + hi), mirrored);
  vec3 local = mix(lo - dilation, hi + dilation, corner);

  outCorners = inCorners;
  outCell = inCell;
  outDraw = drawRecord;  // the fragments read the record without the table's per-command index
  outRecord = instanceRecord(pc.cellRecords);
  outDilation = dilation;
  gl_Position = anchoredClipPosition(frame, object.model, draw, cell + local);
}
