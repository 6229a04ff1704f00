// A kept cell's grid coordinate and proxy box from its record, read by address (HermiteDraw::records,
// fp32 or fp16 by HERMITE_FLAG_HALF_RECORDS): the record's xy / zc words, as cells_resolve.frag
// reads them. Shared by the thin boxes, the runs, the bricks, the tiles' binning and prepass.
#ifndef HSDF_RECORD_CELL_GLSL
#define HSDF_RECORD_CELL_GLSL

// The record's last two words: x | y << 16, z | class word << 16 (hermite_host_device.h).
uvec2 recordWords(HermiteDraw draw, uint record) {
  if ((draw.flags & HERMITE_FLAG_HALF_RECORDS) == 0u)
    return uvec2(CellRecordsRef(draw.records).records[record].xy, CellRecordsRef(draw.records).records[record].zc);
  return uvec2(CellRecordsHalfRef(draw.records).records[record].xy, CellRecordsHalfRef(draw.records).records[record].zc);
}

// The proxy box [lo, hi] (cell-local, within [0, 1]^3) of a record from its class halfword (the
// record's zc >> 16; the attribute boxes' inCell.w): the part of the cell that can hold its zero set
// (hermite_host_device.h, CELL_PROXY_*), or the whole cell where `flags` ask for the paper's proxy
// (HERMITE_FLAG_WHOLE_CELLS). Every root of the cell's interpolant lies in it, so drawing and
// searching it instead of the cell loses none (cells.h, "Proxy boxes"), and fewer rays meet it.
void proxyBox(uint classWord, uint flags, out vec3 lo, out vec3 hi) {
  uint code = (flags & HERMITE_FLAG_WHOLE_CELLS) != 0u ? 0u : classWord >> CELL_PROXY_SHIFT;
  const float step = 1.0 / float(CELL_PROXY_STEPS);
  // Set whole before the axes are (the loop may stay a loop, writing one component at a time):
  // otherwise the caller's last box would live on through a fragment's walk of several cells.
  lo = vec3(0.0);
  hi = vec3(1.0);
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
  proxyBox(recordWords(draw, record).y >> 16, draw.flags, lo, hi);
}

// The record's grid coordinate, and its proxy box, from one read of its words.
vec3 recordCellBox(HermiteDraw draw, uint record, out vec3 lo, out vec3 hi) {
  uvec2 words = recordWords(draw, record);
  proxyBox(words.y >> 16, draw.flags, lo, hi);
  return vec3(uvec3(words.x & 0xffffu, words.x >> 16, words.y & 0xffffu));
}

#endif
