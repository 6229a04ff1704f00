#version 460
#extension GL_GOOGLE_include_directive : require
// Production prepass, back faces of boxes the near plane may cut: no discard, no buffer write.
#include "hermite/cells_depth.glsl"
