#version 460
// Sphere-tracing baselines: the proxy of an object is its grid's bounding box, 36 vertices from
// gl_VertexIndex, one instance per SphereTraceDraw (gl_InstanceIndex = the draw's index). The
// fragment shaders trace in grid units (object space / h), where sample (i,j,k) lies at (i,j,k),
// on rays based at the draw's anchor (pixel_ray.glsl).
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/box.glsl"
#include "hermite/eye.glsl"

layout(push_constant, scalar) uniform Push { SphereTracePushConstants pc; };

layout(location = 0) flat out uint outDraw;

// The prepass and the shading pass rasterize the same box: keep their coverage identical.
precise gl_Position;

void main() {
  SphereTraceDraw draw = SphereTraceDrawsRef(pc.draws).draws[gl_InstanceIndex];
  ObjectData object = ObjectsRef(pc.draw.objects).objects[draw.object];
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;

  vec3 grid = boxCorner(gl_VertexIndex, (object.flags & OBJECT_FLAG_MIRRORED) != 0u) * float(draw.resolution - 1u);
  outDraw = uint(gl_InstanceIndex);
  // As an offset from the rays' anchor (eye.glsl): through the model's float translation, as long
  // as the camera's distance, a corner rounds by up to ~0.5 cell ~1e7 cells out, and the
  // conservative depth (the hit never in front of the face) would hold the hits to that face.
  gl_Position = anchoredClipPosition(frame, object.model, draw.gridOriginSpacing.w, draw.rayAnchor, grid);
}
