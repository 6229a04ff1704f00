// The record index of a cell box's instance (cells.vert, cells_thin.vert): the instance index itself
// (a command's firstInstance is its range's first record), or, for the front faces of culled cells
// (cell_cull.comp), the index the culling pass wrote beside the kept record the instance reads.
#ifndef HSDF_CELL_INSTANCE_GLSL
#define HSDF_CELL_INSTANCE_GLSL

layout(buffer_reference, scalar) readonly buffer CellRecordIndicesRef { uint indices[]; };

uint instanceRecord(uint64_t cellRecords) {
  return cellRecords != 0ul ? CellRecordIndicesRef(cellRecords).indices[gl_InstanceIndex] : uint(gl_InstanceIndex);
}

#endif
