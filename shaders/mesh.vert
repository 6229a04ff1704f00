#version 460
// Triangle meshes. The depth prepass and the shading pass use this same shader so that both
// produce bit-identical depth (the shading pass tests depth EQUAL).
#extension GL_GOOGLE_include_directive : require
#include "shared/host_device.h"

layout(push_constant, scalar) uniform Push { DrawPushConstants pc; };

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inTexcoord;

layout(location = 0) out vec3 outWorldPosition;
layout(location = 1) out vec3 outWorldNormal;
layout(location = 2) flat out uint outObject;
layout(location = 3) out vec2 outTexcoord;

// No FMA contraction: both passes must compute bit-identical positions. (`invariant gl_Position`
// would say it more directly, but glslang 12 emits a decoration that the validation layer rejects.)
precise gl_Position;

void main() {
  FrameGlobals frame = FrameGlobalsRef(pc.frameGlobals).globals;
  ObjectData object = ObjectsRef(pc.objects).objects[gl_InstanceIndex];
  vec4 world = object.model * vec4(inPosition, 1.0);
  outWorldPosition = world.xyz;
  outWorldNormal = transpose(mat3(object.invModel)) * inNormal;
  outObject = gl_InstanceIndex;
  outTexcoord = inTexcoord;
  gl_Position = frame.viewProj * world;
}
