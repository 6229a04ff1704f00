#version 460
// Brick culling (issue 20): one invocation per brick of each drawn object (workgroup y = object).
// A brick outside the frustum, or whose normal cone faces away from the eye where the object allows
// the cone test (normal_cone.glsl), is dropped; every other brick is appended to its object's range
// of the output brick stream and counted in the object's indirect draw command, which the CPU wrote
// with instanceCount 0 and firstInstance = the range's start. The order within a range is
// arbitrary (atomic append); the cell prepass does not depend on it.
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/normal_cone.glsl"

layout(local_size_x = 64) in;

layout(buffer_reference, scalar) readonly buffer BricksRef { CellBrickGpu bricks[]; };
layout(buffer_reference, scalar) writeonly buffer KeptBricksRef { CellBrickGpu bricks[]; };
// VkDrawIndirectCommand[] as uints: vertexCount, instanceCount, firstVertex, firstInstance.
layout(buffer_reference, scalar) buffer CommandsRef { uint words[]; };
layout(buffer_reference, scalar) buffer TotalsRef { BrickCullTotals totals; };

layout(push_constant, scalar) uniform Push { BrickCullPushConstants pc; };

void main() {
  uint objectIndex = gl_WorkGroupID.y;
  if (objectIndex >= pc.objectCount) return;
  BrickCullObject object = CullObjectsRef(pc.objects).objects[objectIndex];
  if (gl_GlobalInvocationID.x >= object.brickCount) return;
  uint brickIndex = object.firstBrick + gl_GlobalInvocationID.x;
  CellBrickGpu brick = BricksRef(pc.bricks).bricks[brickIndex];
  vec3 lo, hi;
  brickBox(brick.xyz, object.gridOriginSpacing.xyz, object.gridOriginSpacing.w, lo, hi);
  bool frustumCulled;
  bool kept = brickSurvives(object.objectToClip, lo, hi, ConesRef(pc.cones).cones[brickIndex].axisCutoff,
                            object.eyeConeTest.xyz, object.eyeConeTest.w != 0.0, frustumCulled);
  TotalsRef totals = TotalsRef(pc.totals);
  atomicAdd(totals.totals.tested, 1u);
  if (!kept) {
    if (frustumCulled) atomicAdd(totals.totals.frustumCulled, 1u);
    else atomicAdd(totals.totals.coneCulled, 1u);
    return;
  }
  atomicAdd(totals.totals.kept, 1u);
  uint slot = atomicAdd(CommandsRef(pc.commands).words[object.drawCommand * 4u + 1u], 1u);
  KeptBricksRef(pc.keptBricks).bricks[object.outputFirst + slot] = brick;
}
