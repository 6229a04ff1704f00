#version 460
// Cell culling (issue 20; RenderMethod::Cells, hsdf::CellCuller): one workgroup per range of cells
// (one front-face command of a culled object: a row, in the order the CPU sorted the rows). Each
// cell is tested as brick_cull.comp tests a brick (normal_cone.glsl brickSurvives: the frustum,
// then the normal cone where the object allows it); the kept cells are copied, in their order
// within the range, to the range's part of the kept-cell stream (the records whole, so the draws
// still read them as instance-rate vertex attributes, and each one's record index), and their
// count becomes the command's instanceCount. The order is kept (a prefix sum, not an atomic
// append) so that boxes whose hits tie at one depth resolve as without culling: same image.
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/normal_cone.glsl"

layout(local_size_x = 64) in;

layout(buffer_reference, scalar) readonly buffer RangesRef { CellCullRange ranges[]; };
layout(buffer_reference, scalar) readonly buffer RecordWordsRef { uint words[]; };
layout(buffer_reference, scalar) writeonly buffer KeptWordsRef { uint words[]; };
layout(buffer_reference, scalar) writeonly buffer KeptIndicesRef { uint indices[]; };
// VkDrawIndirectCommand[] as uints: vertexCount, instanceCount, firstVertex, firstInstance.
layout(buffer_reference, scalar) writeonly buffer CommandsRef { uint words[]; };
layout(buffer_reference, scalar) buffer TotalsRef { BrickCullTotals totals; };

layout(push_constant, scalar) uniform Push { CellCullPushConstants pc; };

shared uint keptUpTo[64];  // inclusive prefix sum of the kept flags of one chunk of 64 cells

// Whether cell `record` stays; counts a culled one in `frustum` or `cone`.
bool cellKept(BrickCullObject object, uint record, inout uint frustum, inout uint cone) {
  RecordWordsRef words = RecordWordsRef(pc.records);
  uint xy = words.words[record * pc.recordWords + pc.recordWords - 2u];
  uint zc = words.words[record * pc.recordWords + pc.recordWords - 1u];
  vec3 lo, hi;
  gridBlockBox(vec3(float(xy & 0xffffu), float(xy >> 16), float(zc & 0xffffu)), object.gridOriginSpacing.xyz,
               object.gridOriginSpacing.w, lo, hi);
  bool frustumCulled;
  bool kept = brickSurvives(object.objectToClip, lo, hi, ConesRef(pc.cones).cones[record].axisCutoff,
                            object.eyeConeTest.xyz, object.eyeConeTest.w != 0.0, frustumCulled);
  if (!kept && frustumCulled) frustum++;
  if (!kept && !frustumCulled) cone++;
  return kept;
}

// The inclusive prefix sum of `flag` over the workgroup (Hillis-Steele in shared memory).
uint inclusivePrefix(uint flag) {
  uint lane = gl_LocalInvocationID.x;
  keptUpTo[lane] = flag;
  barrier();
  for (uint step = 1u; step < 64u; step <<= 1) {
    uint add = lane >= step ? keptUpTo[lane - step] : 0u;
    barrier();
    keptUpTo[lane] += add;
    barrier();
  }
  return keptUpTo[lane];
}

void copyRecord(uint record, uint slot) {
  for (uint w = 0u; w < pc.recordWords; ++w)
    KeptWordsRef(pc.keptRecords).words[slot * pc.recordWords + w] = RecordWordsRef(pc.records).words[record * pc.recordWords + w];
  KeptIndicesRef(pc.keptIndices).indices[slot] = record;
}

void main() {
  // Ranges beyond 65535 continue on the next workgroup row (maxComputeWorkGroupCount[0]).
  uint rangeIndex = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  if (rangeIndex >= pc.rangeCount) return;  // the whole workgroup: the barriers below stay uniform
  CellCullRange range = RangesRef(pc.ranges).ranges[rangeIndex];
  BrickCullObject object = CullObjectsRef(pc.objects).objects[range.object];
  uint lane = gl_LocalInvocationID.x;
  uint written = 0u, frustum = 0u, cone = 0u;
  for (uint base = 0u; base < range.cellCount; base += 64u) {
    uint i = base + lane;
    bool kept = i < range.cellCount && cellKept(object, range.firstCell + i, frustum, cone);
    uint upTo = inclusivePrefix(kept ? 1u : 0u);
    uint chunkKept = keptUpTo[63];
    barrier();  // every lane has read the sums before the next chunk writes them
    if (kept) copyRecord(range.firstCell + i, range.outputFirst + written + upTo - 1u);
    written += chunkKept;
  }
  TotalsRef totals = TotalsRef(pc.totals);
  if (frustum > 0u) atomicAdd(totals.totals.frustumCulled, frustum);
  if (cone > 0u) atomicAdd(totals.totals.coneCulled, cone);
  if (lane != 0u) return;
  CommandsRef(pc.commands).words[range.drawCommand * 4u + 1u] = written;
  atomicAdd(totals.totals.tested, range.cellCount);
  atomicAdd(totals.totals.kept, written);
}
