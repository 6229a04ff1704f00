#version 460
// Sphere-tracing baselines: the proxy of an object is its grid's bounding box, 36 vertices from
// gl_VertexIndex, one instance per SphereTraceDraw (gl_InstanceIndex = the draw's index). The
// fragment shaders trace in grid units (object space / h), where sample (i,j,k) lies at (i,j,k).
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/box.glsl"
#include "hermite/eye.glsl"

layout(push_constant, scalar) uniform Push { SphereTracePushConstants pc; };

layout(location = 0) flat out uint outDraw;
layout(location = 2) flat out vec3 outEyeGrid;  // the rays' eye point in grid units (eye.glsl, pixel_ray.glsl)

// The prepass and the shading pass rasterize the same box: keep their coverage identical.
precise gl_Position;

void main() {
  SphereTraceDraw draw = SphereTraceDrawsRef(pc.draws).draws[gl_InstanceIndex];
  ObjectData object = ObjectsRef(pc.draw.objects).objects[draw.object];
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;

  vec3 grid = boxCorner(gl_VertexIndex, (object.flags & OBJECT_FLAG_MIRRORED) != 0u) * float(draw.resolution - 1u);
  float h = draw.gridOriginSpacing.w;
  vec3 eyeObject = (object.invModel * vec4(rayEyePoint(frame), 1.0)).xyz;

  outDraw = uint(gl_InstanceIndex);
  outEyeGrid = (eyeObject - draw.gridOriginSpacing.xyz) / h;
  gl_Position = frame.viewProj * (object.model * vec4(draw.gridOriginSpacing.xyz + h * grid, 1.0));
}
