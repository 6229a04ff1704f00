#version 460
// The top-left corner triangle of the frame, from the vertex index alone (no vertex buffer).

void main() {
  const vec2 corners[3] = vec2[](vec2(-1.0, -1.0), vec2(0.0, -1.0), vec2(-1.0, 0.0));
  gl_Position = vec4(corners[gl_VertexIndex], 0.0, 1.0);
}
