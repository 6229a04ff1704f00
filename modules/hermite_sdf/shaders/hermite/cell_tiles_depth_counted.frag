#version 460
#extension GL_GOOGLE_include_directive : require
// cell_tiles_depth.frag with the per-pixel evaluation counters, for frames that count work (hit_depth.glsl).
#define HSDF_CONSERVATIVE_DEPTH 1
#define HSDF_COUNT_WORK 1
#include "hermite/cell_tiles_depth.glsl"
