#version 460
// Depth prepass of meshes: depth comes from the rasterizer; the visibility buffer records which
// object (1 + its GPU scene index) won the depth test; its hit offset is 0 (the depth is the
// rasterizer's own, nothing to rebuild: RendererFormats::hitOffset).
layout(location = 2) flat in uint inObject;
layout(location = 0) out uvec2 outVisibility;
layout(location = 1) out float outHitOffset;

// The part id stays 0: gl_PrimitiveID in fragment shaders would need the geometryShader feature.
void main() {
  outVisibility = uvec2(inObject + 1u, 0u);
  outHitOffset = 0.0;
}
