// The vertex shader of runs.vert and runs_wire.vert (HSDF_WIRE: the box's 12 edges as a line list
// of 24 vertices, DEBUG_VIEW_WIREFRAME, drawn by cells_wire.frag).
// Hermite cell runs (RenderMethod::CellRuns): one instance per run of kept cells that follow each
// other along x in one row, drawn as one box of `length` cells: its front faces as one triangle fan
// (8 vertices, box.glsl frontFanCorner), or all six faces as one strip (14) for runs the near plane
// may cut (drawn by back faces); the box is the union of the run's cells' proxy boxes.
// The fragment shader walks the ray through the run's cells and reads each cell's record by
// buffer device address, so the vertex stream carries 12 bytes per run instead of 136 per cell and
// the faces between cells of a run produce no fragments (issue 13; docs/perf/).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/box.glsl"
#include "hermite/eye.glsl"
#include "hermite/proxy_dilation.glsl"
#include "hermite/record_cell.glsl"

layout(push_constant, scalar) uniform Push { HermitePushConstants pc; };

layout(location = 0) in uvec2 inRun;        // x | y << 16, z | length << 16
layout(location = 1) in uint inFirstRecord;

layout(location = 0) flat out uvec4 outRun;          // x, y, z, length
layout(location = 1) flat out uint outFirstRecord;
layout(location = 2) flat out uint outDraw;
layout(location = 5) flat out float outDilation;     // how far the proxy reaches beyond the run, cells

precise gl_Position;

void main() {
  uint drawIndex = pc.drawBase + gl_DrawID;
  uint drawRecord = hermiteDrawRecord(pc.draws, drawIndex);
  HermiteDraw draw = hermiteDrawAt(pc.draws, drawRecord);
  ObjectData object = ObjectsRef(pc.draw.objects).objects[draw.object];
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;

  uvec4 run = uvec4(inRun.x & 0xffffu, inRun.x >> 16, inRun.y & 0xffffu, inRun.y >> 16);
  vec3 start = vec3(run.xyz);
  vec3 size = vec3(float(run.w), 1.0, 1.0);
  float h = draw.gridOriginSpacing.w;
  // The larger of the dilations at the run's two end cells: the end nearer the eye needs more.
  vec3 firstCentre = draw.gridOriginSpacing.xyz + h * (start + 0.5);
  vec3 lastCentre = firstCentre + vec3(h * (size.x - 1.0), 0.0, 0.0);
  float dilation = max(proxyDilation(frame, object, firstCentre, h), proxyDilation(frame, object, lastCentre, h));
  vec3 cameraObject = (object.invModel * vec4(rayEyePoint(frame), 1.0)).xyz;
  vec3 cameraLocal = (cameraObject - draw.gridOriginSpacing.xyz) / h - start;
  bool mirrored = (object.flags & OBJECT_FLAG_MIRRORED) != 0u;
  // The proxy: the union of the run's cells' proxy boxes (record_cell.glsl), which holds every
  // root of the run (the whole run with HERMITE_FLAG_WHOLE_CELLS). The fragment shader still clips
  // the ray to the whole run and each cell's search to the cell's own box.
  vec3 lo = vec3(3.0e38), hi = vec3(-3.0e38);
  for (uint i = 0u; i < run.w; ++i) {
    vec3 cellLo, cellHi;
    recordProxyBox(draw, inFirstRecord + i, cellLo, cellHi);
    lo = min(lo, cellLo + vec3(float(i), 0.0, 0.0));
    hi = max(hi, cellHi + vec3(float(i), 0.0, 0.0));
  }
#ifdef HSDF_WIRE
  vec3 corner = wireCorner(gl_VertexIndex);
#else
  vec3 corner = (draw.flags & HERMITE_FLAG_NEAR_CELL) != 0u ? boxStripCorner(gl_VertexIndex, mirrored)
                                                             : frontFanCorner(gl_VertexIndex, viewerLocal(frame, object.invModel, cameraLocal), 0.5 * (lo + hi), mirrored);
#endif
  vec3 local = mix(lo - dilation, hi + dilation, corner);

  outRun = run;
  outFirstRecord = inFirstRecord;
  outDraw = drawRecord;  // the fragments read the record without the table's per-command index
  outDilation = dilation;
  gl_Position = anchoredClipPosition(frame, object.model, draw, start + local);
}
