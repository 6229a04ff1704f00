// Brick culling tests (issue 20), the twins of hermite_sdf/core/normal_cone.h (read it for the proofs):
// the same float operations in the same order, marked precise so that no contraction into fused
// multiply-adds makes the GPU keep a different set of bricks than the C++ twin.
//
// CellBrickCone::axisCutoff = (axis, w): every gradient direction of the brick's cells is within
// theta of the unit axis (object space), w = sin(theta) = cos(90 deg - theta); w >= 1 never culls.
#ifndef HSDF_NORMAL_CONE_GLSL
#define HSDF_NORMAL_CONE_GLSL

// The box of the grid block at integer coordinate `index` whose side is `side` (a cell: h; a
// brick: 4h), object space.
void gridBlockBox(vec3 index, vec3 gridOrigin, float side, out vec3 lo, out vec3 hi) {
  precise vec3 l = gridOrigin + side * index;
  lo = l;
  hi = l + vec3(side);
}

// The brick's box in object space (CellBrickGpu::xyz, the grid's origin and spacing h).
void brickBox(uint packedXyz, vec3 gridOrigin, float h, out vec3 lo, out vec3 hi) {
  precise vec3 brick = vec3(float(packedXyz & 1023u), float((packedXyz >> 10) & 1023u), float((packedXyz >> 20) & 1023u));
  precise float side = h * float(CELL_BRICK_SIZE);
  gridBlockBox(brick, gridOrigin, side, lo, hi);
}

// True if no ray from `eye` can have its first root in the box [lo, hi]: every gradient n of the
// cone and every point p of the box have n . (p - eye) > 0. That holds when the box lies in the
// open cone {v : axis . v > w |v|} around the eye (directions within 90 deg - theta of the axis);
// that cone is convex, so the box lies in it when its 8 corners do.
bool coneCullsBox(vec4 axisCutoff, vec3 lo, vec3 hi, vec3 eye) {
  for (int corner = 0; corner < 8; ++corner) {
    vec3 p = vec3((corner & 1) != 0 ? hi.x : lo.x, (corner & 2) != 0 ? hi.y : lo.y, (corner & 4) != 0 ? hi.z : lo.z);
    precise vec3 toCorner = p - eye;
    precise float along = dot(axisCutoff.xyz, toCorner);
    precise float bound = axisCutoff.w * length(toCorner);
    if (!(along > bound)) return false;
  }
  return true;
}

// True if the box lies wholly outside one plane of the reverse-Z frustum (-w <= x, y <= w, z <= w;
// no far plane); objectToClip = viewProj * model.
bool boxOutsideFrustum(mat4 objectToClip, vec3 lo, vec3 hi) {
  bool inside[5] = bool[5](false, false, false, false, false);
  for (int corner = 0; corner < 8; ++corner) {
    vec3 p = vec3((corner & 1) != 0 ? hi.x : lo.x, (corner & 2) != 0 ? hi.y : lo.y, (corner & 4) != 0 ? hi.z : lo.z);
    precise vec4 clip = objectToClip * vec4(p, 1.0);
    inside[0] = inside[0] || clip.w + clip.x >= 0.0;
    inside[1] = inside[1] || clip.w - clip.x >= 0.0;
    inside[2] = inside[2] || clip.w + clip.y >= 0.0;
    inside[3] = inside[3] || clip.w - clip.y >= 0.0;
    inside[4] = inside[4] || clip.w - clip.z >= 0.0;
  }
  return !(inside[0] && inside[1] && inside[2] && inside[3] && inside[4]);
}

// Whether a brick stays: inside the frustum and, when the object allows the cone test, not facing
// away from the eye.
bool brickSurvives(mat4 objectToClip, vec3 lo, vec3 hi, vec4 axisCutoff, vec3 eye, bool coneTest,
                   out bool frustumCulled) {
  frustumCulled = boxOutsideFrustum(objectToClip, lo, hi);
  if (frustumCulled) return false;
  return !coneTest || !coneCullsBox(axisCutoff, lo, hi, eye);
}

#endif
