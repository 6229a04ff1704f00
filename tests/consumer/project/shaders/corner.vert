#version 460
// A triangle over the frame's corner at (CORNER_X, CORNER_Y) in clip space, from the vertex index
// alone (no vertex buffer). The corner comes from hermite_sdf_add_shaders' DEFINES.
#if !defined(CORNER_X) || !defined(CORNER_Y)
#error "CORNER_X and CORNER_Y must be defined (hermite_sdf_add_shaders ... DEFINES)"
#endif

void main() {
  const vec2 corner = vec2(CORNER_X, CORNER_Y);
  const vec2 corners[3] = vec2[](corner, vec2(0.0, corner.y), vec2(corner.x, 0.0));
  gl_Position = vec4(corners[gl_VertexIndex], 0.0, 1.0);
}
