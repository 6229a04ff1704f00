#version 460
#extension GL_GOOGLE_include_directive : require
// Production prepass of the thin cell boxes the near plane may cut (back faces): no discard, no buffer write.
#include "hermite/cells_thin_depth.glsl"
