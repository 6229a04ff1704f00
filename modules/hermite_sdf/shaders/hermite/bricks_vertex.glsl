// The vertex shader of bricks.vert and bricks_wire.vert (HSDF_WIRE: the box's 12 edges as a line list
// of 24 vertices, DEBUG_VIEW_WIREFRAME, drawn by cells_wire.frag).
// Hermite cell bricks (RenderMethod::CellBricks, issue 20 steps 2 and 3): one instance per brick of
// CELL_BRICK_SIZE^3 cells holding a kept cell, drawn as the box of its kept cells: the front faces
// as one triangle fan (8 vertices, box.glsl frontFanCorner), or all six faces as one triangle strip
// (14 vertices) for bricks the near plane may cut (drawn by back faces). The vertex shader hands on
// 12 bytes (brick, draw, dilation): the fragment shader reads the brick by address, rebuilds the
// pixel's ray from gl_FragCoord and walks the brick's kept cells (bricks_depth.glsl).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/box.glsl"
#include "hermite/eye.glsl"
#include "hermite/brick.glsl"
#include "hermite/proxy_dilation.glsl"

layout(push_constant, scalar) uniform Push { HermitePushConstants pc; };

layout(location = 0) in uvec4 inBrick;  // CellBrickGpu: xyz, firstIndex, maskLo, maskHi

// Every varying is flat: 3 x 4 bytes per vertex (issue 20's target: at most 16).
layout(location = 0) flat out uint outBrick;     // index of the CellBrickGpu in pc.bricks
layout(location = 1) flat out uint outDraw;      // the HermiteDraw record (hermiteDrawAt)
layout(location = 2) flat out float outDilation; // how far the proxy reaches beyond the kept cells, cells

precise gl_Position;

void main() {
  uint drawIndex = pc.drawBase + gl_DrawID;
  uint drawRecord = hermiteDrawRecord(pc.draws, drawIndex);
  HermiteDraw draw = hermiteDrawAt(pc.draws, drawRecord);
  ObjectData object = ObjectsRef(pc.draw.objects).objects[draw.object];
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;

  CellBrickGpu brick = CellBrickGpu(inBrick.x, inBrick.y, inBrick.z, inBrick.w);
  uvec3 lo, hi;
  brickCellBounds(brick, lo, hi);
  vec3 start = vec3(brickCoordinate(brick) * CELL_BRICK_SIZE + lo);  // the kept cells' box, grid units
  vec3 size = vec3(hi - lo + 1u);
  float h = draw.gridOriginSpacing.w;
  // The largest of the dilations at the box's corner cells: each cell's own proxy would need its own.
  float dilation = 0.0;
  for (int c = 0; c < 8; ++c) {
    vec3 cellCentre = draw.gridOriginSpacing.xyz + h * (start + 0.5 + cornerPosition(c) * (size - 1.0));
    dilation = max(dilation, proxyDilation(frame, object, cellCentre, h));
  }
  vec3 cameraObject = (object.invModel * vec4(rayEyePoint(frame), 1.0)).xyz;
  vec3 cameraLocal = (cameraObject - draw.gridOriginSpacing.xyz) / h - start;
  bool mirrored = (object.flags & OBJECT_FLAG_MIRRORED) != 0u;
#ifdef HSDF_WIRE
  vec3 corner = wireCorner(gl_VertexIndex);
#else
  vec3 corner = (draw.flags & HERMITE_FLAG_NEAR_CELL) != 0u ? boxStripCorner(gl_VertexIndex, mirrored)
                                                             : frontFanCorner(gl_VertexIndex, viewerLocal(frame, object.invModel, cameraLocal), 0.5 * size, mirrored);
#endif
  vec3 local = corner * (size + 2.0 * dilation) - dilation;

  outBrick = uint(gl_InstanceIndex);  // firstInstance of the command = the object's first brick
  outDraw = drawRecord;  // the fragments read the record without the table's per-command index
  outDilation = dilation;
  gl_Position = anchoredClipPosition(frame, object.model, draw, start + local);
}
