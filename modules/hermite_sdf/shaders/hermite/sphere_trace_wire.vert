#version 460
// Box wireframe debug view of the sphere tracers (DEBUG_VIEW_WIREFRAME): the 12 edges of each
// object's proxy, its grid's bounding box (the box sphere_trace.vert draws), as a line list of 24
// vertices per instance, one instance per SphereTraceDraw.
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/box.glsl"

layout(push_constant, scalar) uniform Push { SphereTracePushConstants pc; };

void main() {
  SphereTraceDraw draw = SphereTraceDrawsRef(pc.draws).draws[gl_InstanceIndex];
  ObjectData object = ObjectsRef(pc.draw.objects).objects[draw.object];
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;
  vec3 grid = wireCorner(gl_VertexIndex) * float(draw.resolution - 1u);
  gl_Position = frame.viewProj * (object.model * vec4(draw.gridOriginSpacing.xyz + draw.gridOriginSpacing.w * grid, 1.0));
}
