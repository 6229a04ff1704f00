// The 36 vertices of a box proxy (a cell or a grid's bounding box), generated from gl_VertexIndex.
#ifndef HSDF_BOX_GLSL
#define HSDF_BOX_GLSL

// Corner (x + 2y + 4z) of each vertex: 12 outward counter-clockwise triangles.
const int kBoxCorners[36] = int[36](0, 6, 2, 0, 4, 6, 1, 3, 7, 1, 7, 5, 0, 5, 4, 0, 1, 5,
                                    2, 6, 7, 2, 7, 3, 0, 3, 1, 0, 2, 3, 4, 5, 7, 4, 7, 6);

// The corner of box vertex `vertexIndex` as a 0/1 position. A mirroring model matrix (negative
// determinant, OBJECT_FLAG_MIRRORED) turns counter-clockwise triangles clockwise on screen, so the
// pipelines' fixed culling would keep the wrong faces; swapping the last two vertices of each
// triangle restores the winding, and every object can share one pipeline and one draw.
vec3 boxCorner(int vertexIndex, bool mirrored) {
  int v = vertexIndex;
  if (mirrored && v % 3 != 0) v += (v % 3 == 1) ? 1 : -1;
  int corner = kBoxCorners[v];
  return vec3(corner & 1, (corner >> 1) & 1, corner >> 2);
}

// Fewer vertices per box (issue 20 step 2: the vertex shader runs once per vertex of a
// non-indexed draw): every cell proxy (cells.vert, cells_thin.vert, runs.vert, bricks.vert) is a
// fan of its front faces or a strip of all six. Corners are numbered x + 2y + 4z as in kBoxCorners.
vec3 cornerPosition(int corner) { return vec3(corner & 1, (corner >> 1) & 1, corner >> 2); }

// Corner c mirrored through the plane y = z, which maps the box onto itself and reverses the
// winding of every face (a reflection), without changing which corners a face has.
int swapCornerYZ(int corner) { return (corner & 1) | ((corner & 2) << 1) | ((corner & 4) >> 1); }

// The three faces of the box that meet at corner 0 (-x, -y, -z), outward counter-clockwise, as one
// triangle fan around corner 0: 6 triangles from 8 vertices (18 in a list).
const int kFrontFan[8] = int[8](0, 1, 5, 4, 6, 2, 3, 1);

// The front faces of the box as a triangle fan (8 vertices, `vertexIndex` 0..7). Per axis the fan
// takes the face on the viewer's side of the box's `centre`: `viewer` is homogeneous (eye.glsl
// viewerLocal), the eye point (w = 1, same coordinates as `centre`) or an orthographic camera's
// direction towards the viewer (w = 0), so the side is the sign of viewer.xyz - centre * viewer.w.
// Moving the fan's hub to that corner is a reflection on each axis where it is 1 (corner ^ near),
// and an odd number of reflections, or a mirroring model matrix (OBJECT_FLAG_MIRRORED), reverses
// the winding: then one more reflection (swapCornerYZ) restores it. A face whose two planes hold
// the eye between them is a back face whichever of the two is taken, and the pipeline's back-face
// culling drops it.
vec3 frontFanCorner(int vertexIndex, vec4 viewer, vec3 centre, bool mirrored) {
  ivec3 side = ivec3(greaterThan(viewer.xyz, centre * viewer.w));
  int near = side.x | (side.y << 1) | (side.z << 2);
  bool flip = (((side.x + side.y + side.z) & 1) != 0) != mirrored;
  int corner = kFrontFan[vertexIndex];
  return cornerPosition((flip ? swapCornerYZ(corner) : corner) ^ near);
}

// All six faces as one triangle strip of 14 vertices, outward counter-clockwise in Vulkan's strip
// order (triangle i is i, i+1, i+2, odd ones i, i+2, i+1), for boxes drawn by their back faces
// (near-plane boxes): 14 vertex-shader invocations instead of 36.
const int kBoxStrip[14] = int[14](0, 1, 4, 5, 7, 1, 3, 0, 2, 4, 6, 7, 2, 3);

vec3 boxStripCorner(int vertexIndex, bool mirrored) {
  int corner = kBoxStrip[vertexIndex];
  return cornerPosition(mirrored ? swapCornerYZ(corner) : corner);
}

// DEBUG_VIEW_WIREFRAME: the 12 edges of a box as a line list, the corner of each of 24 vertices
// (edges along x, then y, then z).
const int kWireCorners[24] = int[24](0, 1, 2, 3, 4, 5, 6, 7, 0, 2, 1, 3, 4, 6, 5, 7, 0, 4, 1, 5, 2, 6, 3, 7);

vec3 wireCorner(int vertexIndex) { return cornerPosition(kWireCorners[vertexIndex]); }

#endif
