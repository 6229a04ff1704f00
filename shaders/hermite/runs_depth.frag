#version 460
#extension GL_GOOGLE_include_directive : require
#define HSDF_CONSERVATIVE_DEPTH 1
#include "hermite/runs_depth.glsl"
