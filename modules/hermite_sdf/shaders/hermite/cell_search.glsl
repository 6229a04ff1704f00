// One kept cell's search along a pixel's ray, shared by the proxies that walk several cells per
// fragment: the cell runs (runs_depth.glsl) and the cell bricks (bricks_depth.glsl). Records are
// read by buffer device address (HermiteDraw::records, HERMITE_FLAG_HALF_RECORDS).
#ifndef HSDF_CELL_SEARCH_GLSL
#define HSDF_CELL_SEARCH_GLSL

#include "hermite/record_cell.glsl"
#include "hermite/segment_roots.glsl"


void loadCorners(HermiteDraw draw, uint record, out vec4 corners[8]) {
  if ((draw.flags & HERMITE_FLAG_HALF_RECORDS) == 0u) {
    corners = CellRecordsRef(draw.records).records[record].corners;
  } else {
    uvec2 packed[8] = CellRecordsHalfRef(draw.records).records[record].corners;
    for (int i = 0; i < 8; ++i) corners[i] = vec4(unpackHalf2x16(packed[i].x), unpackHalf2x16(packed[i].y));
  }
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
  vec4 corners[8];
  loadCorners(draw, record, corners);
  float coefficients[SEGMENT_COEFFS];
  restrictToSegment(corners, draw.gridOriginSpacing.w, origin + c0 * direction, origin + c1 * direction, coefficients);
  ++evaluations;  // the restriction: the cost of a few tricubic evaluations, counted once
  float s = segmentFirstRoot(coefficients, draw.subdivisions, draw.refineSteps,
                             (draw.flags & HERMITE_FLAG_CERTIFIED) != 0u, evaluations);
  return s >= 0.0 ? mix(c0, c1, s) : -1.0;
}

#endif
