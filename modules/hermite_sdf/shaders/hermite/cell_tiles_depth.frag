#version 460
#extension GL_GOOGLE_include_directive : require
// Production prepass of the tiled cells: no discard, no buffer write (hit_depth.glsl).
#define HSDF_CONSERVATIVE_DEPTH 1
#include "hermite/cell_tiles_depth.glsl"
