// How the cells' and runs' prepass fragments hand on their hit, or their miss (cells_depth.glsl,
// runs_depth.glsl). Each row of the variant table (the module's shaders/CMakeLists.txt) picks one
// by its defines; the feature picks the pipeline (modules/hermite_sdf/src/render/cell_feature.cpp):
// - production (no define): the hit's depth as gl_FragDepth (the depth test orders the hits), a
//   miss as depth 0, the far plane under reverse-Z, which fails the GREATER test, so neither depth
//   nor visibility is written. No `discard` and no buffer write anywhere in the shader: on a GPU a
//   fragment shader that merely contains either loses early (and hierarchical) depth rejection,
//   which halved the prepass on an H100 (../shared/gpu/h100-b505968/README.md §3b;
//   tests/unit/hermite_sdf/render/prepass_spirv_test.cpp keeps it so).
// - HSDF_COUNT_WORK (*_counted.frag): the same, plus the per-pixel evaluation counters (the
//   renderer's work counters or the heat map), used only in frames that count.
// - HSDF_EARLY_DEPTH (*_early.frag, front faces): the early depth stage, for in-order software
//   rasterizers (lavapipe shades 4x4 blocks in submission order: a box behind an already found hit
//   fails an early depth test and its search never runs, 40-60 % of the prepass there; nothing on
//   the H100). The hit is not written as depth: the box's own face depth stays the fragment's
//   depth. Within one object the boxes are disjoint cells of one grid: along a ray, the box
//   entered first holds the first hit, so the nearest face with a hit is the face of the box with
//   the nearest hit, and the test keeps the right visibility id. A miss must be discarded here
//   (its face depth would read as a hit). The hit's true depth goes to a per-pixel buffer (the
//   nearest one, by atomicMax: reverse-Z, positive floats order as their bits), and the fix-up pass
//   (cells_depth_early_fixup.frag) writes it into the depth buffer before any other prepass draw
//   tests against it.
// - HSDF_RECORD_HIT_DEPTHS (implied by HSDF_EARLY_DEPTH; *_near_early.frag): also record the hit
//   in that buffer, so that cells drawn by depth (the near-plane cells) and by face in the same
//   frame end up with the nearest of both.
// The early variants count work too when pc.counters is set: they hold buffer writes anyway.
#ifndef HSDF_HIT_DEPTH_GLSL
#define HSDF_HIT_DEPTH_GLSL

#ifdef HSDF_EARLY_DEPTH
#define HSDF_RECORD_HIT_DEPTHS 1
#define HSDF_COUNT_WORK 1
#endif
#ifdef HSDF_RECORD_HIT_DEPTHS
#define HSDF_COUNT_WORK 1
layout(buffer_reference, scalar) buffer HitDepthsRef { uint depths[]; };
#endif
#ifdef HSDF_COUNT_WORK
layout(buffer_reference, scalar) buffer CountersRef { uint counts[]; };
layout(buffer_reference, scalar) buffer WorkTotalsRef { WorkTotals totals; };
#endif

uint pixelIndex() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;
  return uint(pixel.y * int(frame.viewport.x) + pixel.x);
}

// The root-search evaluations of this fragment, when the variant counts them.
void countWork(uint evaluations) {
#ifdef HSDF_COUNT_WORK
  if (pc.counters != 0ul) atomicAdd(CountersRef(pc.counters).counts[pixelIndex()], evaluations);
#endif
}

// The tile-list entries this fragment read and ray-box tested, and the words of its pixel masks it
// read (WorkTotals), when the variant counts.
void countTileWalk(uint walked, uint tested, uint maskWords) {
#ifdef HSDF_COUNT_WORK
  if (pc.workTotals != 0ul) {
    atomicAdd(WorkTotalsRef(pc.workTotals).totals.tileEntriesWalked, walked);
    atomicAdd(WorkTotalsRef(pc.workTotals).totals.tileEntriesTested, tested);
    atomicAdd(WorkTotalsRef(pc.workTotals).totals.tileMaskWordsRead, maskWords);
  }
#endif
}

void writeHitDepth(float depth) {
#ifndef HSDF_EARLY_DEPTH
  gl_FragDepth = depth;
#endif
#ifdef HSDF_RECORD_HIT_DEPTHS
  if (pc.hitDepths != 0ul) atomicMax(HitDepthsRef(pc.hitDepths).depths[pixelIndex()], floatBitsToUint(depth));
#endif
}

// No root along this fragment's ray: nothing may be written. Depth 0 is the far plane (reverse-Z)
// and never passes the prepass's GREATER test; with conservative depth (depth_less) it is allowed,
// being below every face depth.
void writeMiss() {
#ifdef HSDF_EARLY_DEPTH
  discard;
#else
  gl_FragDepth = 0.0;
#endif
}

#endif
