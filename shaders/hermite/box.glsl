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

#endif
