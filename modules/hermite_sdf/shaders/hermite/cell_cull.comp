#version 460
// Cell culling (issue 20; RenderMethod::Cells, hsdf::CellCuller): one workgroup per pack of ranges
// of cells (a range: one front-face command of a culled object, a row, in the order the CPU sorted
// the rows; a pack: consecutive ranges of at most CELL_CULL_PACK_CELLS cells together, a lane per
// cell, or one longer range of at most CELL_CULL_MAX_RANGE_CELLS). Each
// cell is tested as brick_cull.comp tests a brick (normal_cone.glsl brickSurvives: the frustum,
// then the normal cone where the object allows it); the kept cells of a range are appended to the
// kept-cell streams together and in their order within the range (the records whole, so the draws
// still read them as instance-rate vertex attributes, and each one's record index): one atomic per
// workgroup claims its ranges' slots, and each command's firstInstance and instanceCount say where
// and how many.
// Within a range the order is kept (a prefix sum) so that boxes whose hits tie at one depth resolve
// as without culling, and the commands keep the rows' order: same image. The streams are sized from
// what earlier frames kept, not from every cell of every object (10,000 bunnies at K = 32 would
// need 5.9 GB): a range whose kept cells no longer fit is drawn whole and unculled by its fallback
// command instead, and the cursor's final value tells the CPU how much the next frames need.
// Two-phase occlusion culling (pc.phase, the scheme of zeux/niagara): phase 1 keeps only the cells
// that were visible when last tested (the history); phase 2, after the renderer built the depth
// pyramid of what phase 1 drew, tests every surviving cell's box against it, records the result
// as the history and keeps the visible cells phase 1 did not draw. A cell that may be visible is
// drawn in one of the two phases whatever the history says: a stale history only costs work.
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/normal_cone.glsl"

layout(local_size_x = 64) in;

layout(buffer_reference, scalar) readonly buffer RangesRef { CellCullRange ranges[]; };
layout(buffer_reference, scalar) readonly buffer PackFirstRef { uint first[]; };
layout(buffer_reference, scalar) readonly buffer RecordWordsRef { uint words[]; };
layout(buffer_reference, scalar) writeonly buffer KeptWordsRef { uint words[]; };
layout(buffer_reference, scalar) writeonly buffer KeptIndicesRef { uint indices[]; };
layout(buffer_reference, scalar) writeonly buffer KeptRangesRef { uint ranges[]; };
// VkDrawIndirectCommand[] as uints: vertexCount, instanceCount, firstVertex, firstInstance.
layout(buffer_reference, scalar) writeonly buffer CommandsRef { uint words[]; };
layout(buffer_reference, scalar) buffer TotalsRef { BrickCullTotals totals; };
layout(buffer_reference, scalar) buffer HistoryRef { uint visible[]; };
layout(buffer_reference, scalar) readonly buffer PyramidRef { float depth[]; };

layout(push_constant, scalar) uniform Push { CellCullPushConstants pc; };

shared uint keptUpTo[64];  // inclusive prefix sum of the kept flags of one chunk of 64 cells
shared uint groupFirst;       // the workgroup's first slot in the kept streams
shared uint rangeKept[64];   // per range of a pack: its kept cells

const uint kNoRange = 0xffffffffu;  // keptRanges of a hole (cell_tiles.comp skips it)

// The box of cell `record` in object space.
void cellBox(BrickCullObject object, uint record, out vec3 lo, out vec3 hi) {
  RecordWordsRef words = RecordWordsRef(pc.records);
  uint xy = words.words[record * pc.recordWords + pc.recordWords - 2u];
  uint zc = words.words[record * pc.recordWords + pc.recordWords - 1u];
  gridBlockBox(vec3(float(xy & 0xffffu), float(xy >> 16), float(zc & 0xffffu)), object.gridOriginSpacing.xyz,
               object.gridOriginSpacing.w, lo, hi);
}

// Whether cell `record` stays; counts a culled one in `frustum` or `cone`.
bool cellKept(BrickCullObject object, uint record, inout uint frustum, inout uint cone) {
  vec3 lo, hi;
  cellBox(object, record, lo, hi);
  bool frustumCulled;
  bool kept = brickSurvives(object.objectToClip, lo, hi, ConesRef(pc.cones).cones[record].axisCutoff,
                            object.eyeConeTest.xyz, object.eyeConeTest.w != 0.0, frustumCulled);
  if (!kept && frustumCulled) frustum++;
  if (!kept && !frustumCulled) cone++;
  return kept;
}

// The farthest pyramid depth over the pixels [lo, hi] (inclusive, inside the frame): the level
// where the rectangle spans at most 2x2 texels (a texel of level k covers 2^k pixels per axis).
float pyramidFarthest(uvec2 lo, uvec2 hi) {
  // n pixels from any x cover at most 2 texels of a level whose texels are >= n - 1 pixels wide.
  uint span = max(hi.x - lo.x, hi.y - lo.y) + 1u;
  uint level = span <= 2u ? 0u : min(uint(findMSB(span - 2u)) + 1u, pc.pyramidLevels - 1u);
  uint offset = 0u;
  uvec2 size = uvec2(pc.pyramidExtent & 0xffffu, pc.pyramidExtent >> 16);
  for (uint k = 0u; k < level; ++k) {
    offset += size.x * size.y;
    size = (size + 1u) / 2u;
  }
  uvec2 a = lo >> level, b = min(hi >> level, size - 1u);
  float farthest = 1.0;
  for (uint y = a.y; y <= b.y; ++y)
    for (uint x = a.x; x <= b.x; ++x) farthest = min(farthest, PyramidRef(pc.pyramid).depth[offset + y * size.x + x]);
  return farthest;
}

// Whether everything the cell can draw is behind what phase 1 drew: its box's nearest depth
// (reverse-Z: the largest z/w of its corners; a box's points lie between its corners' depths) is
// farther than the pyramid's farthest depth over the pixels whose centres its corners' rectangle
// may hold (one pixel wider each side: the proxies' dilation and rounding), the depth with
// pc.depthMargin. A box reaching the near plane, or behind the eye, is never occluded.
bool cellOccluded(BrickCullObject object, uint record) {
  if (pc.pyramidLevels == 0u) return false;
  vec3 lo, hi;
  cellBox(object, record, lo, hi);
  vec2 minNdc = vec2(1.0), maxNdc = vec2(-1.0);
  float nearest = 0.0;
  for (uint c = 0u; c < 8u; ++c) {
    vec3 corner = vec3((c & 1u) != 0u ? hi.x : lo.x, (c & 2u) != 0u ? hi.y : lo.y, (c & 4u) != 0u ? hi.z : lo.z);
    vec4 clip = object.objectToClip * vec4(corner, 1.0);
    if (clip.w <= 0.0 || clip.z >= clip.w) return false;
    vec3 ndc = clip.xyz / clip.w;
    minNdc = min(minNdc, ndc.xy);
    maxNdc = max(maxNdc, ndc.xy);
    nearest = max(nearest, ndc.z);
  }
  vec2 frame = vec2(pc.pyramidExtent & 0xffffu, pc.pyramidExtent >> 16);
  vec2 loPixel = clamp(floor((minNdc * 0.5 + 0.5) * frame) - 1.0, vec2(0.0), frame - 1.0);
  vec2 hiPixel = clamp(floor((maxNdc * 0.5 + 0.5) * frame) + 1.0, vec2(0.0), frame - 1.0);
  return nearest * (1.0 + pc.depthMargin) < pyramidFarthest(uvec2(loPixel), uvec2(hiPixel));
}

// Phases 1 and 2 of occlusion culling for a cell that passed the frustum and cone tests: whether
// this phase draws it (phase 2 also records whether it is visible).
bool keptInPhase(BrickCullObject object, uint record, uint historyIndex, bool survives) {
  if (pc.phase == CELL_CULL_PHASE_ALL) return survives;
  HistoryRef history = HistoryRef(pc.history);
  bool wasVisible = history.visible[historyIndex] != 0u;
  if (pc.phase == CELL_CULL_PHASE_EARLY) return survives && wasVisible;
  bool visible = survives && !cellOccluded(object, record);
  history.visible[historyIndex] = visible ? 1u : 0u;
  return visible && !wasVisible;
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

// Kept cell `record` of range `rangeIndex` into the slot `first + k` of its range's claim: copied
// where the claim fits; where it does not, the slots it reached below the streams' end stay holes,
// which the tiling must skip (marked in keptRanges: no range).
void keepCell(uint record, uint rangeIndex, uint first, uint kept, uint k) {
  uint slot = first + k;
  if (first + kept <= pc.keptCapacity) {
    for (uint w = 0u; w < pc.recordWords; ++w)
      KeptWordsRef(pc.keptRecords).words[slot * pc.recordWords + w] = RecordWordsRef(pc.records).words[record * pc.recordWords + w];
    KeptIndicesRef(pc.keptIndices).indices[slot] = record;
  }
  if (pc.keptRanges != 0ul && slot < pc.keptCapacity)
    KeptRangesRef(pc.keptRanges).ranges[slot] = first + kept <= pc.keptCapacity ? rangeIndex : kNoRange;
}

// The first of `kept` consecutive slots in the kept streams for one range (past the streams' end
// when they do not fit any more: the cursor still advances, so that its final value is what the
// frame wanted). Both at most the frame's culled cells, which the CPU keeps below 2^32.
uint claimSlots(uint kept) {
  return kept == 0u ? 0u : atomicAdd(TotalsRef(pc.totals).totals.keptSlots[pc.recordPrecision], kept);
}

// The command of a culled range: its kept cells from `first` on, or (the streams full) none, and
// its fallback command draws the whole range from the record buffer. Then the pass's totals: each
// cell is counted as tested, frustum- or cone-culled once (not again in phase 2); kept counts the
// cells the tests kept, both phases together.
void finishRange(CellCullRange range, uint kept, uint first) {
  CommandsRef commands = CommandsRef(pc.commands);
  uint command = (range.drawCommand + pc.commandOffset) * 4u;
  bool full = kept > 0u && first + kept > pc.keptCapacity;  // a range with none needs no slot
  commands.words[command + 1u] = full ? 0u : kept;
  commands.words[command + 3u] = full ? 0u : first;
  TotalsRef totals = TotalsRef(pc.totals);
  if (full) {
    commands.words[range.fallbackCommand * 4u + 1u] = range.cellCount;
    atomicAdd(totals.totals.fallbackCells, range.cellCount);
  }
  if (pc.phase != CELL_CULL_PHASE_LATE) atomicAdd(totals.totals.tested, range.cellCount);
  atomicAdd(totals.totals.kept, kept);
}

void countCulled(uint frustum, uint cone) {
  TotalsRef totals = TotalsRef(pc.totals);
  bool counts = pc.phase != CELL_CULL_PHASE_LATE;
  if (counts && frustum > 0u) atomicAdd(totals.totals.frustumCulled, frustum);
  if (counts && cone > 0u) atomicAdd(totals.totals.coneCulled, cone);
}

// A pack of short ranges (at most CELL_CULL_PACK_CELLS cells together): a lane per cell, one
// prefix sum over the pack; the pack claims its slots, and each range's kept cells keep their order.
void cullPack(uint firstRange, uint endRange) {
  uint lane = gl_LocalInvocationID.x;
  uint r = firstRange, start = 0u;
  for (; r < endRange; ++r) {
    uint cells = RangesRef(pc.ranges).ranges[r].cellCount;
    if (lane < start + cells) break;
    start += cells;
  }
  bool inRange = r < endRange;
  CellCullRange range;
  uint i = lane - start, frustum = 0u, cone = 0u;
  bool kept = false;
  if (inRange) {
    range = RangesRef(pc.ranges).ranges[r];
    BrickCullObject object = CullObjectsRef(pc.objects).objects[range.object];
    kept = keptInPhase(object, range.firstCell + i, range.historyFirst + i, cellKept(object, range.firstCell + i, frustum, cone));
  }
  uint upTo = inclusivePrefix(kept ? 1u : 0u);  // every lane: the barriers stay uniform
  uint before = inRange && start > 0u ? keptUpTo[start - 1u] : 0u;
  bool last = inRange && i + 1u == range.cellCount;  // the range's last lane: its count is known
  // One claim for the whole pack (its ranges are consecutive, so each range's cells stay together
  // and in order): a global atomic per workgroup rather than per range.
  if (lane == 0u) groupFirst = claimSlots(keptUpTo[63]);
  if (last) rangeKept[r - firstRange] = upTo - before;  // a pack's ranges hold >= 1 cell each: at most 64
  barrier();
  uint first = groupFirst + before;
  if (kept) keepCell(range.firstCell + i, r, first, rangeKept[r - firstRange], upTo - before - 1u);
  countCulled(frustum, cone);
  if (last) finishRange(range, upTo - before, first);
}

// A range of its own (at most CELL_CULL_MAX_RANGE_CELLS cells), 64 cells at a time, twice: the
// first walk tests the cells (each lane keeps its verdicts as bits) and counts the kept ones, so
// that the range claims its slots; the second writes them in order.
void cullRange(uint rangeIndex) {
  CellCullRange range = RangesRef(pc.ranges).ranges[rangeIndex];
  BrickCullObject object = CullObjectsRef(pc.objects).objects[range.object];
  uint lane = gl_LocalInvocationID.x;
  uint verdicts = 0u, frustum = 0u, cone = 0u;
  if (lane == 0u) rangeKept[0] = 0u;
  barrier();
  uint chunks = min((range.cellCount + 63u) / 64u, CELL_CULL_MAX_RANGE_CELLS / 64u);
  for (uint chunk = 0u; chunk < chunks; ++chunk) {
    uint i = chunk * 64u + lane;
    if (i < range.cellCount &&
        keptInPhase(object, range.firstCell + i, range.historyFirst + i, cellKept(object, range.firstCell + i, frustum, cone)))
      verdicts |= 1u << chunk;
  }
  if (verdicts != 0u) atomicAdd(rangeKept[0], uint(bitCount(verdicts)));
  barrier();
  if (lane == 0u) groupFirst = claimSlots(rangeKept[0]);
  barrier();
  uint first = groupFirst, kept = rangeKept[0], written = 0u;
  for (uint chunk = 0u; chunk < chunks; ++chunk) {
    bool keptHere = (verdicts & (1u << chunk)) != 0u;
    uint upTo = inclusivePrefix(keptHere ? 1u : 0u);
    uint chunkKept = keptUpTo[63];
    barrier();  // every lane has read the sums before the next chunk writes them
    if (keptHere) keepCell(range.firstCell + chunk * 64u + lane, rangeIndex, first, kept, written + upTo - 1u);
    written += chunkKept;
  }
  countCulled(frustum, cone);
  if (lane == 0u) finishRange(range, kept, first);
}

void main() {
  // Packs beyond 65535 continue on the next workgroup row (maxComputeWorkGroupCount[0]).
  uint pack = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  if (pack >= pc.packCount) return;  // the whole workgroup: the barriers below stay uniform
  PackFirstRef packs = PackFirstRef(pc.ranges + uint64_t(pc.rangeCount) * 32u);
  uint firstRange = packs.first[pack], endRange = packs.first[pack + 1u];
  if (endRange - firstRange == 1u) {
    cullRange(firstRange);
  } else {
    cullPack(firstRange, endRange);
  }
}
