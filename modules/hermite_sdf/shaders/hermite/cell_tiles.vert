#version 460
#extension GL_GOOGLE_include_directive : require
// Tiles as points (cell_tiles_vert.glsl).
#define HSDF_TILE_POINTS 1
#include "hermite/cell_tiles_vert.glsl"
