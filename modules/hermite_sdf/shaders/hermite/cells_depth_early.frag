#version 460
#extension GL_GOOGLE_include_directive : require
// Front faces tested at their own depth: hidden boxes fail an early depth test (hit_depth.glsl;
// chosen on software rasterizers only).
#define HSDF_CONSERVATIVE_DEPTH 1
#define HSDF_EARLY_DEPTH 1
#include "hermite/cells_depth.glsl"
