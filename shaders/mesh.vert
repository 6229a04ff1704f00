#version 460
// Triangle meshes. The depth prepass and the shading pass use this same shader so that both
// produce bit-identical depth (the shading pass tests depth EQUAL).
#extension GL_GOOGLE_include_directive : require
#include "shared/host_device.h"

layout(push_constant, scalar) uniform Push { DrawPushConstants pc; };

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inTexcoord;
layout(location = 3) in vec4 inTangent;  // glTF TANGENT; 0 for a mesh without

layout(location = 0) out vec3 outWorldPosition;
layout(location = 1) out vec3 outWorldNormal;
layout(location = 2) flat out uint outObject;
layout(location = 3) out vec2 outTexcoord;
// The tangent in the world (the model matrix moves it as it moves the surface's directions), its
// w the handedness, reversed for a mirrored object: the bitangent cross(normal, tangent) * w turns
// round with the mirror, the texture's directions do not.
layout(location = 4) out vec4 outWorldTangent;

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
  float mirror = (object.flags & OBJECT_FLAG_MIRRORED) != 0u ? -1.0 : 1.0;
  outWorldTangent = vec4(mat3(object.model) * inTangent.xyz, inTangent.w * mirror);
  gl_Position = frame.viewProj * world;
}
