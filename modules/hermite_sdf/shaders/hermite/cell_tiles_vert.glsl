// Tiled cells (HermiteCellFeature::Settings::tiles): one instance per non-empty screen tile of
// cell_tiles.comp, at the nearest depth of the tile's cell boxes, so the hits (never nearer) are
// written as conservative depth. The vertex shader hands on 4 bytes: the tile, whose list the
// fragment shader walks (cell_tiles_depth.glsl). Two primitives, one per .vert:
//  - cell_tiles.vert (HSDF_TILE_POINTS): one point of pc.tileSize pixels, one vertex-shader
//    invocation: it covers exactly the tile's pixels, so each 2x2 quad (GPUs) or 4x4 block
//    (lavapipe) of the tile is shaded once;
//  - cell_tiles_quads.vert, where the device has no large points: two triangles (6 invocations),
//    whose shared diagonal has the quads or blocks it crosses shaded once per triangle.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"

layout(push_constant, scalar) uniform Push { HermitePushConstants pc; };
layout(buffer_reference, scalar) readonly buffer TilesRef { CellTile tiles[]; };
layout(buffer_reference, scalar) readonly buffer TileListRef { uint tiles[]; };

layout(location = 0) flat out uint outTile;

const int kQuadCorners[6] = int[6](0, 1, 2, 2, 1, 3);

void main() {
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;
  uvec2 tiles = (uvec2(frame.viewport.xy) + pc.tileSize - 1u) / pc.tileSize;
  uint tile = TileListRef(pc.tiles + CELL_TILE_LIST_OFFSET(tiles.x * tiles.y)).tiles[gl_InstanceIndex];
  vec2 origin = vec2(tile % tiles.x, tile / tiles.x) * float(pc.tileSize);
#ifdef HSDF_TILE_POINTS
  // The centre, kept inside the frame for a tile the frame's edge cuts (a point whose centre lies
  // outside the view volume is dropped); the point then also covers a pixel row or column of its
  // neighbour, whose fragments find no nearer hit there than the neighbour's own (they search a
  // subset of the cells the pixel's ray meets) and lose the depth test.
  vec2 pixel = min(origin + 0.5 * float(pc.tileSize), frame.viewport.xy - 0.25);
  gl_PointSize = float(pc.tileSize);
#else
  int corner = kQuadCorners[gl_VertexIndex];
  vec2 pixel = min(origin + vec2(corner & 1, corner >> 1) * float(pc.tileSize), frame.viewport.xy);
#endif
  outTile = tile;
  gl_Position = vec4(pixel * frame.viewport.zw * 2.0 - 1.0, uintBitsToFloat(TilesRef(pc.tiles).tiles[tile].depth), 1.0);
}
