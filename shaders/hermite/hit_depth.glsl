// How the cells' and runs' prepass fragments hand on the depth of their hit (cells_depth.glsl,
// runs_depth.glsl). Two ways, chosen per pipeline:
// - as gl_FragDepth (the depth test then orders the hits: the shader runs for every box fragment,
//   since a shader that writes depth is tested after it runs);
// - HSDF_EARLY_DEPTH: not as depth. The box's own face depth stays the fragment's depth, so a box
//   whose face lies behind an already found hit fails an early depth test and its search never
//   runs. Within one object the boxes are disjoint cells of one grid: along a ray, the box entered
//   first holds the first hit, so the nearest face with a hit is the face of the box with the
//   nearest hit, and the test keeps the right visibility id. The hit's true depth goes to a
//   per-pixel buffer (the nearest one, by atomicMax: reverse-Z, positive floats order as their
//   bits), and the fix-up pass (cells_depth_fixup.frag) writes it into the depth buffer before
//   any other prepass draw tests against it.
// Every pipeline also records its hit in the buffer when pc.hitDepths is set, so that cells drawn
// by depth (the near-plane cells) and by face in the same frame end up with the nearest of both.
#ifndef HSDF_HIT_DEPTH_GLSL
#define HSDF_HIT_DEPTH_GLSL

layout(buffer_reference, scalar) buffer HitDepthsRef { uint depths[]; };

void writeHitDepth(float depth) {
#ifndef HSDF_EARLY_DEPTH
  gl_FragDepth = depth;
#endif
  if (pc.hitDepths != 0ul) {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;
    atomicMax(HitDepthsRef(pc.hitDepths).depths[pixel.y * int(frame.viewport.x) + pixel.x], floatBitsToUint(depth));
  }
}

#endif
