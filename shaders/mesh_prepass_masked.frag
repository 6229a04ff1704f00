#version 460
// Depth prepass of meshes that cut out (glTF alphaMode MASK: a leaf card, a fence, a grille).
// Where the alpha -- the base colour factor's times the texture's -- is below the object's cutoff
// (ObjectData::material.z), the fragment writes the far plane's depth, 0 under reverse-Z, which
// the GREATER test rejects: nothing of it is kept, neither depth nor visibility, and what lies
// behind shows, SDF objects included. It writes no `discard`: a depth declared `depth_less`
// (never nearer than the rasterized one) keeps early depth rejection on GPUs, as the cells'
// misses do (docs/gpu-vs-lavapipe.md). The shading pass draws the mesh with depth EQUAL, so a
// cut-out fragment finds another surface's depth there and is not shaded.
#extension GL_GOOGLE_include_directive : require
#include "shared/host_device.h"

layout(push_constant, scalar) uniform Push { DrawPushConstants pc; };

layout(location = 2) flat in uint inObject;
layout(location = 3) in vec2 inTexcoord;

// The object's base colour texture (engine::render::MeshTextures: a white texel for none).
layout(set = 0, binding = 0) uniform sampler2D baseColorTexture;

layout(location = 0) out uvec2 outVisibility;
layout(location = 1) out float outHitOffset;
layout(depth_less) out float gl_FragDepth;

void main() {
  ObjectData object = ObjectsRef(pc.objects).objects[inObject];
  float alpha = object.color.a * texture(baseColorTexture, inTexcoord).a;
  gl_FragDepth = alpha >= object.material.z ? gl_FragCoord.z : 0.0;
  outVisibility = uvec2(inObject + 1u, 0u);
  outHitOffset = 0.0;
}
