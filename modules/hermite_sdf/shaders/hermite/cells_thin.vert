#version 460
// Hermite cells, thin boxes (HermiteCellFeature::Settings::thinBoxes; issue 20 step 2): one
// instance per kept cell as in cells.vert, but only the cell's coordinate arrives as an attribute
// and the box costs 8 vertex-shader invocations (its front faces as one triangle fan, box.glsl
// frontFanCorner), or 14 for cells the near plane may cut (all six faces as one strip, drawn by
// their back faces). The vertex shader hands on 12 bytes; the fragment shader reads the cell's 32
// scalars by buffer address and rebuilds the pixel's ray (cells_thin_depth.glsl). cells.vert, the
// paper's variant, hands each of its 8 vertices the 8 corners (128 bytes) and more.
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/box.glsl"
#include "hermite/eye.glsl"
#include "hermite/cell_instance.glsl"
#include "hermite/proxy_dilation.glsl"
#include "hermite/record_cell.glsl"

layout(push_constant, scalar) uniform Push { HermitePushConstants pc; };

layout(location = 8) in uvec4 inCell;  // x, y, z, class (the record's last 8 bytes)

// Every varying is flat: 3 x 4 bytes per vertex (issue 20's target: at most 16).
layout(location = 0) flat out uint outRecord;     // index of the cell record in its buffer
layout(location = 1) flat out uint outDraw;       // the HermiteDraw record (hermiteDrawAt)
layout(location = 2) flat out float outDilation;  // how far the proxy reaches beyond the cell, cells

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

  outRecord = instanceRecord(pc.cellRecords);
  outDraw = drawRecord;  // the fragments read the record without the table's per-command index
  outDilation = dilation;
  gl_Position = anchoredClipPosition(frame, object.model, draw, cell + local);
}
