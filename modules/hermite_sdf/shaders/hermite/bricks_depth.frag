#version 460
#extension GL_GOOGLE_include_directive : require
// Production prepass, front faces: no discard, no buffer write (hit_depth.glsl).
#define HSDF_CONSERVATIVE_DEPTH 1
#include "hermite/bricks_depth.glsl"
