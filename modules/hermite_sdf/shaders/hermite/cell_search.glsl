// One kept cell's search along a pixel's ray, shared by the proxies that walk several cells per
// fragment: the cell runs (runs_depth.glsl) and the cell bricks (bricks_depth.glsl). Records are
// read by buffer device address (HermiteDraw::records, HERMITE_FLAG_HALF_RECORDS).
#ifndef HSDF_CELL_SEARCH_GLSL
#define HSDF_CELL_SEARCH_GLSL

#include "hermite/record_cell.glsl"
#include "hermite/segment_roots.glsl"


// The four corners of z side `sz` of a record (side[x + 2y] = corner x + 2y + 4 sz), fp32 or fp16 by
// HERMITE_FLAG_HALF_RECORDS. The restriction reads one side just before it sums it, so the two
// sides' 32 floats are never live at once (register pressure: segment_roots.glsl, restrictToSegment).
void loadZSide(HermiteDraw draw, uint record, int sz, out vec4 side[4]) {
  if ((draw.flags & HERMITE_FLAG_HALF_RECORDS) == 0u) {
    for (int i = 0; i < 4; ++i) side[i] = CellRecordsRef(draw.records).records[record].corners[4 * sz + i];
  } else {
    for (int i = 0; i < 4; ++i) {
      uvec2 packed = CellRecordsHalfRef(draw.records).records[record].corners[4 * sz + i];
      side[i] = vec4(unpackHalf2x16(packed.x), unpackHalf2x16(packed.y));
    }
  }
}

// restrictToSegment (segment_roots.glsl) of the record's cell, read side by side.
void restrictRecordToSegment(HermiteDraw draw, uint record, vec3 u0, vec3 u1, out float b[SEGMENT_COEFFS]) {
  for (int k = 0; k < SEGMENT_COEFFS; ++k) b[k] = 0.0;
  vec4 side[4];
  loadZSide(draw, record, 0, side);
  addZSide(side, 0, draw.gridOriginSpacing.w, u0, u1, b);
  loadZSide(draw, record, 1, side);
  addZSide(side, 1, draw.gridOriginSpacing.w, u0, u1, b);
  fromScaledBernstein(b);
}

// The first root of cell `record` along origin + t * direction (cell-local: the cell spans
// [0, 1]^3), searched over the cell's proxy box [lo, hi] (recordProxyBox, record_cell.glsl: every
// root of the cell lies in it) dilated by `margin` on every side and clipped to [t0, t1], as each
// cell searches its own proxy (cells_depth.glsl; docs/root-finding.md): a root on a face two cells
// share is then inside the searched segment of both. Returns t, or -1.
float searchCell(HermiteDraw draw, uint record, vec3 lo, vec3 hi, vec3 origin, vec3 direction, float margin,
                 float t0, float t1, inout uint evaluations) {
  vec2 segment = intersectBox(origin, direction, lo - margin, hi + margin);
  float c0 = max(segment.x, t0), c1 = min(segment.y, t1);
  if (!(c0 < c1)) return -1.0;
  float coefficients[SEGMENT_COEFFS];
  restrictRecordToSegment(draw, record, origin + c0 * direction, origin + c1 * direction, coefficients);
  ++evaluations;  // the restriction: the cost of a few tricubic evaluations, counted once
  float s = segmentFirstRoot(coefficients, draw.subdivisions, draw.refineSteps,
                             (draw.flags & HERMITE_FLAG_CERTIFIED) != 0u, evaluations);
  return s >= 0.0 ? mix(c0, c1, s) : -1.0;
}

#endif
