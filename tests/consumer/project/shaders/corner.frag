#version 460
#extension GL_GOOGLE_include_directive : require
#include "corner_host_device.h"

layout(push_constant, scalar) uniform Push { CornerPushConstants pc; };
layout(location = 0) out vec4 outColor;

void main() { outColor = pc.color; }
