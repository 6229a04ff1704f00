#version 460
#extension GL_GOOGLE_include_directive : require
#define SPHERE_TRACE_CONSERVATIVE_DEPTH 1
#include "hermite/sphere_trace_depth.glsl"
