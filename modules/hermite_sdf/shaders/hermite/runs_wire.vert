#version 460
#extension GL_GOOGLE_include_directive : require
// runs.vert drawing the edges of its boxes (DEBUG_VIEW_WIREFRAME).
#define HSDF_WIRE 1
#include "hermite/runs_vertex.glsl"
