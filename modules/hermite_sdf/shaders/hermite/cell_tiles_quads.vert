#version 460
#extension GL_GOOGLE_include_directive : require
// Tiles as two triangles, where the device has no large points (cell_tiles_vert.glsl).
#include "hermite/cell_tiles_vert.glsl"
