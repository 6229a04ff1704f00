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

#endif
