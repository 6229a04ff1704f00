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

// The faces of the box [lo, hi] (local coordinates) that face an eye at `eye` (same coordinates):
// at most one per axis, the one on the eye's side, and none for an axis whose two face planes the
// eye lies between (both face away from it). Front faces are all a box shows, so 18 vertices
// instead of 36: vertex `vertexIndex` (0..17) belongs to axis vertexIndex / 6. Returns its corner as
// a 0/1 position, or -1 in every component for a vertex of an axis without a front face (the
// caller collapses those triangles). The test is per instance, the same in every vertex.
vec3 frontFaceCorner(int vertexIndex, vec3 eye, vec3 lo, vec3 hi, bool mirrored) {
  int axis = vertexIndex / 6;
  float e = eye[axis];
  if (e >= lo[axis] && e <= hi[axis]) return vec3(-1.0);
  int face = 2 * axis + (e > hi[axis] ? 1 : 0);  // kBoxCorners lists -x, +x, -y, +y, -z, +z
  return boxCorner(6 * face + vertexIndex % 6, mirrored);
}

#endif
