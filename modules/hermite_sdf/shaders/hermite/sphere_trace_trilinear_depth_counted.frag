#version 460
#extension GL_GOOGLE_include_directive : require
// sphere_trace_trilinear_depth.frag with the work counters, for frames that count work (sphere_trace_depth.glsl).
#define HSDF_COUNT_WORK 1
#define SPHERE_TRACE_CONSERVATIVE_DEPTH 1
#include "hermite/sphere_trace_depth.glsl"
