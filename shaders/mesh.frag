#version 460
#extension GL_GOOGLE_include_directive : require
#include "shared/host_device.h"
#include "shared/lighting.glsl"

layout(push_constant, scalar) uniform Push { DrawPushConstants pc; };

layout(location = 0) in vec3 inWorldPosition;
layout(location = 1) in vec3 inWorldNormal;
layout(location = 2) flat in uint inObject;

layout(location = 0) out vec4 outColor;

void main() {
  FrameGlobals frame = FrameGlobalsRef(pc.frameGlobals).globals;
  ObjectData object = ObjectsRef(pc.objects).objects[inObject];
  vec3 color;
  if (pc.debugView == DEBUG_VIEW_NORMALS) {
    color = debugNormalColor(inWorldNormal);
  } else if (pc.debugView == DEBUG_VIEW_DEPTH) {
    color = vec3(gl_FragCoord.z);
  } else {
    // The rasterizer says which side of the triangle the eye sees: a back face (a mesh drawn
    // without culling) is lit as its other side. On the side seen, the interpolated vertex normal
    // may still face away near a silhouette (the vertices' normals lean over it): bent to face the
    // eye, not turned round, which lit single pixels along the outline as the object's far side.
    vec3 n = normalize(inWorldNormal);
    if (!gl_FrontFacing) n = -n;
    n = normalTowardEye(n, normalize(frame.cameraPosition.xyz - inWorldPosition));
    color = shadeSurface(frame, object.color.rgb, object.material.x, inWorldPosition, n);
  }
  outColor = vec4(color, 1.0);
}
