#version 460
#extension GL_GOOGLE_include_directive : require
// bricks_depth_near.frag with the per-pixel evaluation counters, for frames that count work (hit_depth.glsl).
#define HSDF_COUNT_WORK 1
#include "hermite/bricks_depth.glsl"
