// The consumer's own GPU struct, shared by its C++ and GLSL as the engine's are
// (shared/host_device.h: HSDF_CHECK_SIZE, glm types in C++).
#ifndef CORNER_HOST_DEVICE_H
#define CORNER_HOST_DEVICE_H
#include "shared/host_device.h"

#ifdef __cplusplus
namespace shader {
#endif

struct CornerPushConstants {
  vec4 color;  // linear RGBA of the corner triangle
};
HSDF_CHECK_SIZE(CornerPushConstants, 16);

#ifdef __cplusplus
}  // namespace shader
#endif
#endif
