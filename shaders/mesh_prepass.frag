#version 460
// Depth prepass of meshes: depth comes from the rasterizer; the visibility attachment records
// which object won the depth test (1 + its GPU scene index).
layout(location = 2) flat in uint inObject;
layout(location = 0) out uint outVisibility;

void main() { outVisibility = inObject + 1u; }
