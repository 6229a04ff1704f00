#version 460
#extension GL_GOOGLE_include_directive : require
// cells_depth_near.frag in frames with the early depth stage: also records its hits in the
// per-pixel hit depths, so the fix-up keeps the nearer of these and the face-tested boxes' hits
// (hit_depth.glsl; chosen on software rasterizers only).
#define HSDF_RECORD_HIT_DEPTHS 1
#include "hermite/cells_depth.glsl"
