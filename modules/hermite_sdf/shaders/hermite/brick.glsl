// A cell brick (CellBrickGpu, RenderMethod::CellBricks) decoded: its coordinate and the bounds of
// its kept cells, shared by the vertex shader that draws the brick's box (bricks.vert) and the
// fragment shader that walks its cells (bricks_depth.glsl); the CPU twin is src/core/cells/cell_bricks.cpp.
#ifndef HSDF_BRICK_GLSL
#define HSDF_BRICK_GLSL

uvec3 brickCoordinate(CellBrickGpu brick) { return uvec3(brick.xyz & 0x3ffu, (brick.xyz >> 10) & 0x3ffu, brick.xyz >> 20); }

// 4 bits: which of the 4 nibbles of a 16-bit value are non-zero.
uint occupiedNibbles(uint bits16) {
  return ((bits16 & 0xfu) != 0u ? 1u : 0u) | ((bits16 & 0xf0u) != 0u ? 2u : 0u) |
         ((bits16 & 0xf00u) != 0u ? 4u : 0u) | ((bits16 & 0xf000u) != 0u ? 8u : 0u);
}

// The kept cells' bounds within the brick (cells, inclusive): the proxy covers only them. Bit
// x + 4y + 16z: the z slices are the mask's 16-bit quarters, their OR is a 4x4 (x, y) plane whose
// nibbles are the y rows, and the OR of the rows gives x.
void brickCellBounds(CellBrickGpu brick, out uvec3 lo, out uvec3 hi) {
  uint zBits = ((brick.maskLo & 0xffffu) != 0u ? 1u : 0u) | ((brick.maskLo >> 16) != 0u ? 2u : 0u) |
               ((brick.maskHi & 0xffffu) != 0u ? 4u : 0u) | ((brick.maskHi >> 16) != 0u ? 8u : 0u);
  uint plane = (brick.maskLo | (brick.maskLo >> 16) | brick.maskHi | (brick.maskHi >> 16)) & 0xffffu;
  uint yBits = occupiedNibbles(plane);
  uint xBits = (plane | (plane >> 4) | (plane >> 8) | (plane >> 12)) & 0xfu;
  lo = uvec3(findLSB(xBits), findLSB(yBits), findLSB(zBits));
  hi = uvec3(findMSB(xBits), findMSB(yBits), findMSB(zBits));
}

#endif
