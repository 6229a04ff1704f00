// A kept cell's grid coordinate from its record, read by address (HermiteDraw::records, fp32 or
// fp16 by HERMITE_FLAG_HALF_RECORDS): the record's xy / zc words, as cells_resolve.frag reads them.
// Shared by the thin boxes, the tiles' binning and the tiles' prepass.
#ifndef HSDF_RECORD_CELL_GLSL
#define HSDF_RECORD_CELL_GLSL

vec3 recordCell(HermiteDraw draw, uint record) {
  uint xy, zc;
  if ((draw.flags & HERMITE_FLAG_HALF_RECORDS) == 0u) {
    xy = CellRecordsRef(draw.records).records[record].xy;
    zc = CellRecordsRef(draw.records).records[record].zc;
  } else {
    xy = CellRecordsHalfRef(draw.records).records[record].xy;
    zc = CellRecordsHalfRef(draw.records).records[record].zc;
  }
  return vec3(uvec3(xy & 0xffffu, xy >> 16, zc & 0xffffu));
}

// The proxy box [lo, hi] (cell-local, within [0, 1]^3) of a record from its class halfword (the
// record's zc >> 16; the attribute boxes' inCell.w): the part of the cell that can hold its zero set
// (hermite_host_device.h, CELL_PROXY_*), or the whole cell where `flags` ask for the paper's proxy
// (HERMITE_FLAG_WHOLE_CELLS). Every root of the cell's interpolant lies in it, so drawing and
// searching it instead of the cell loses none (cells.h, "Proxy boxes"), and fewer rays meet it.
void proxyBox(uint classWord, uint flags, out vec3 lo, out vec3 hi) {
  uint code = (flags & HERMITE_FLAG_WHOLE_CELLS) != 0u ? 0u : classWord >> CELL_PROXY_SHIFT;
  const float step = 1.0 / float(CELL_PROXY_STEPS);
  for (int axis = 0; axis < 3; ++axis) {
    uint pair = code % 21u;
    code /= 21u;
    uint s = 0u;  // steps cut from both ends; pair = s (s + 1) / 2 + (steps cut above)
    while ((s + 1u) * (s + 2u) / 2u <= pair) ++s;
    uint above = pair - s * (s + 1u) / 2u;
    lo[axis] = float(s - above) * step;
    hi[axis] = float(CELL_PROXY_STEPS - above) * step;
  }
}

void recordProxyBox(HermiteDraw draw, uint record, out vec3 lo, out vec3 hi) {
  uint zc = (draw.flags & HERMITE_FLAG_HALF_RECORDS) == 0u ? CellRecordsRef(draw.records).records[record].zc
                                                          : CellRecordsHalfRef(draw.records).records[record].zc;
  proxyBox(zc >> 16, draw.flags, lo, hi);
}

#endif
