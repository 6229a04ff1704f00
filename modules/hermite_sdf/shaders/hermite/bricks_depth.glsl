// Depth prepass of the Hermite cell bricks (RenderMethod::CellBricks). Compiled as
// bricks_depth.frag (front faces, conservative depth) and bricks_depth_near.frag (back faces of
// bricks the near plane may cut), and by their counting variants (hit_depth.glsl); bricks have no
// early depth variant: a frame that draws bricks keeps the early depth stage off.
// The ray walks the brick's cells in the order it meets them (3D DDA over the kept cells' box),
// searching each kept cell exactly as the cells do (cell_search.glsl: its own box dilated by the
// search margin, docs/root-finding.md), and stops at the first root. A ray that passes within the
// margin of a kept cell it does not enter (near an edge or corner of the walk) searches that cell
// too, in the step where it comes that close, so every kept cell whose dilated box the ray meets is
// searched, as the cells' own proxies would be.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/proxy_dilation.glsl"
#include "hermite/brick.glsl"
#include "hermite/pixel_ray.glsl"

layout(push_constant, scalar) uniform Push { HermitePushConstants pc; };
layout(buffer_reference, scalar) readonly buffer CellBricksRef { CellBrickGpu bricks[]; };
layout(buffer_reference, scalar) readonly buffer BrickCellsRef { uint records[]; };
#include "hermite/cell_search.glsl"

// 12 bytes from the vertex shader (bricks.vert): the brick is read by address, the ray rebuilt here.
layout(location = 0) flat in uint inBrick;
layout(location = 1) flat in uint inDraw;
layout(location = 2) flat in float inDilation;  // the proxy: the kept cells' box grown by this, cells

layout(location = 0) out uvec2 outVisibility;  // (1 + object, cell record)
layout(location = 1) out float outHitOffset;  // where along the ray: pixelRayHitOffset (pixel_ray.glsl)
#if defined(HSDF_CONSERVATIVE_DEPTH)
layout(depth_less) out float gl_FragDepth;  // reverse-Z: the hit is never nearer than the front face
#endif
#include "hermite/hit_depth.glsl"

// The pixel's ray in brick-local coordinates (cells; `start` is the brick's first cell in grid
// units), u(t) = origin + t * direction, based near the object (pixel_ray.glsl: camera t = base + t).
PixelRay brickRay(FrameGlobals frame, HermiteDraw draw, vec3 start) {
  mat4 invModel = ObjectsRef(pc.draw.objects).objects[draw.object].invModel;
  float h = draw.gridOriginSpacing.w;
  return pixelRay(frame, invModel, h, draw.rayAnchor - vec4(start, 0.0));
}

bool keptBit(CellBrickGpu brick, uint bit) {
  return ((bit < 32u ? brick.maskLo >> bit : brick.maskHi >> (bit - 32u)) & 1u) != 0u;
}

// The record of kept cell `bit`: its rank among the brick's kept cells indexes the brick's list.
uint brickCellRecord(CellBrickGpu brick, uint bit) {
  uint rank = bit < 32u ? bitCount(brick.maskLo & ((1u << bit) - 1u))
                        : bitCount(brick.maskLo) + bitCount(brick.maskHi & ((1u << (bit - 32u)) - 1u));
  return BrickCellsRef(pc.brickCells).records[brick.firstIndex + rank];
}

struct BrickHit {
  float t;  // -1: none yet
  uint record;
};

// The walk's state: the DDA cell, its stretch of the ray [tEnter, tExit], and which of the up to
// 27 cells around it (the cell itself and the neighbours across faces the ray comes within the
// margin of) is considered next.
struct BrickWalk {
  uint cell;  // 3 bits per axis, the cell plus one (the DDA steps one past the bounds to stop): cellAt
  vec3 tMax;  // each axis' step (sign, length) is taken from the ray where used: not held through searches
  float tEnter, tExit;
  // The neighbour offsets near [tEnter, tExit] not considered yet, bit (dx + 1) + 3 (dy + 1) + 9 (dz + 1)
  // of offset (dx, dy, dz). The walk's state lives through every search of the fragment, so it is
  // packed: this one register replaces the offsets' ranges and the next offset (seven), the cell's
  // three ints are one (above), and the bounds are one (packCellBounds).
  uint pending;
  bool stop;  // a root was found in this step: finish the step, then stop
};

ivec3 cellAt(BrickWalk w) { return ivec3(w.cell & 7u, (w.cell >> 3) & 7u, w.cell >> 6) - 1; }

void enterCell(inout BrickWalk w, vec3 origin, vec3 direction, float margin, float t1) {
  int axis = w.tMax.x < w.tMax.y ? (w.tMax.x < w.tMax.z ? 0 : 2) : (w.tMax.y < w.tMax.z ? 1 : 2);
  w.tExit = min(max(w.tMax[axis], w.tEnter), t1);
  vec3 cell = vec3(cellAt(w));
  vec3 a = origin + w.tEnter * direction - cell, b = origin + w.tExit * direction - cell;
  // Per axis, bit d + 1 for each offset d the stretch comes near: 0 always, -1 and +1 within the margin.
  uvec3 near = 2u | uvec3(lessThan(min(a, b), vec3(margin))) | (uvec3(greaterThan(max(a, b), vec3(1.0 - margin))) << 2);
  uint plane = (near.y & 1u) * near.x | (near.x << 3) | ((near.y >> 2) * near.x << 6);
  w.pending = (near.z & 1u) * plane | (plane << 9) | ((near.z >> 2) * plane << 18);
}

// The kept cells' bounds (brickCellBounds) packed in one register, 2 bits per bound: lo.x, lo.y,
// lo.z, hi.x, hi.y, hi.z from bit 0 up, unpacked per axis where the walk steps (stepCell): as six
// ints they lived through every search.
uint packCellBounds(uvec3 lo, uvec3 hi) {
  return lo.x | (lo.y << 2) | (lo.z << 4) | (hi.x << 6) | (hi.y << 8) | (hi.z << 10);
}

// Moves the DDA to the next cell; false when the walk leaves the box or the ray's stretch.
bool stepCell(inout BrickWalk w, uint bounds, vec3 origin, vec3 direction, float margin, float t1) {
  if (w.stop || w.tExit >= t1) return false;
  int axis = w.tMax.x < w.tMax.y ? (w.tMax.x < w.tMax.z ? 0 : 2) : (w.tMax.y < w.tMax.z ? 1 : 2);
  w.cell = direction[axis] >= 0.0 ? w.cell + (1u << (3 * axis)) : w.cell - (1u << (3 * axis));
  int cell = int(bitfieldExtract(w.cell, 3 * axis, 3)) - 1;
  int lo = int(bitfieldExtract(bounds, 2 * axis, 2)), hi = int(bitfieldExtract(bounds, 6 + 2 * axis, 2));
  if (cell < lo || cell > hi) return false;
  w.tEnter = w.tExit;
  // The axis stepped along always moves: a still axis keeps tMax = 3e38 and is never the nearest.
  w.tMax[axis] += abs(1.0 / direction[axis]);
  enterCell(w, origin, direction, margin, t1);
  return true;
}

// The next kept cell to search, not searched before (`done`), cheap tests only: the fragment
// shader runs the expensive search at one place, once per loop iteration, so lanes of one SIMD
// group that walk different cells share the iterations instead of adding them up.
bool nextCandidate(inout BrickWalk w, CellBrickGpu brick, uint bounds, vec3 origin, vec3 direction,
                   float margin, vec2 ray, inout uvec2 done, out ivec3 n) {
  n = ivec3(0);  // set on every path: an unset out value would live on from the last call
  for (int guard = 0; guard < 27 * 3 * int(CELL_BRICK_SIZE); ++guard) {  // a walk meets at most 10 cells
    if (w.pending == 0u && !stepCell(w, bounds, origin, direction, margin, ray.y)) return false;
    int next = findLSB(w.pending);  // lowest bit first: dz, then dy, then dx ascending, the order of a loop over 27
    w.pending &= w.pending - 1u;
    n = cellAt(w) + ivec3(next % 3, (next / 3) % 3, next / 9) - 1;
    // Outside the brick; a cell of the brick outside the kept cells' bounds is not kept (below).
    if (any(lessThan(n, ivec3(0))) || any(greaterThan(n, ivec3(CELL_BRICK_SIZE - 1u)))) continue;
    uint bit = uint(n.x + 4 * n.y + 16 * n.z);
    uvec2 flag = bit < 32u ? uvec2(1u << bit, 0u) : uvec2(0u, 1u << (bit - 32u));
    if (!keptBit(brick, bit) || any(notEqual(done & flag, uvec2(0u)))) continue;
    done |= flag;
    // The cell's dilated box must meet the ray (searchCell's own test, done here while it is cheap).
    vec2 segment = intersectBox(origin - vec3(n), direction, vec3(-margin), vec3(1.0 + margin));
    if (max(segment.x, ray.x) < min(segment.y, ray.y)) return true;
  }
  return false;
}

// 3D DDA from the cell at t0 to t1 over the kept cells' box [lo, hi] (cells, inclusive); in each
// step the cell and the kept neighbours the ray comes within the margin of are searched, and the
// nearest root of the first step with one is the hit.
BrickHit walkBrick(HermiteDraw draw, CellBrickGpu brick, ivec3 lo, ivec3 hi, uint bounds, vec3 origin, vec3 direction,
                   float margin, float t0, float t1, inout uint evaluations) {
  BrickWalk w;
  ivec3 cell = clamp(ivec3(floor(origin + t0 * direction)), lo, hi);
  w.cell = uint(cell.x + 1) | (uint(cell.y + 1) << 3) | (uint(cell.z + 1) << 6);
  for (int axis = 0; axis < 3; ++axis) {
    bool moves = direction[axis] != 0.0;
    float boundary = float(cell[axis] + (direction[axis] >= 0.0 ? 1 : 0));
    // (boundary - origin) / direction with both terms negated, the same value: the searches' ray-box
    // tests take 1 / direction in every step, and the compiler would hold this one's through the walk.
    w.tMax[axis] = moves ? (origin[axis] - boundary) / -direction[axis] : 3.0e38;
  }
  w.tEnter = t0;
  w.stop = false;
  enterCell(w, origin, direction, margin, t1);
  BrickHit hit = BrickHit(-1.0, 0u);
  uvec2 done = uvec2(0u);
  ivec3 n;
  while (nextCandidate(w, brick, bounds, origin, direction, margin, vec2(t0, t1), done, n)) {
    uint record = brickCellRecord(brick, uint(n.x + 4 * n.y + 16 * n.z));
    vec3 proxyLo, proxyHi;
    recordProxyBox(draw, record, proxyLo, proxyHi);
    float t = searchCell(draw, record, proxyLo, proxyHi, origin - vec3(n), direction, margin, t0, t1, evaluations);
    if (t >= 0.0 && (hit.t < 0.0 || t < hit.t)) hit = BrickHit(t, record);
    w.stop = hit.t >= 0.0;
  }
  return hit;
}

void main() {
  HermiteDraw draw = hermiteDrawAt(pc.draws, inDraw);  // inDraw: the record (the vertex shader looked it up)
  CellBrickGpu brick = CellBricksRef(pc.bricks).bricks[inBrick];
  uvec3 lo, hi;
  brickCellBounds(brick, lo, hi);
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;
  PixelRay ray = brickRay(frame, draw, vec3(brickCoordinate(brick) * CELL_BRICK_SIZE));
  vec3 origin = ray.origin;
  vec3 direction = ray.direction;
  float margin = inDilation;  // the search margin: the proxy's dilation (docs/root-finding.md)
  // The box mirrored through the origin, the same interval: 1 / -direction shares nothing with the
  // searches' 1 / direction, which the compiler would otherwise hold from here through the walk.
  vec2 box = intersectBox(-origin, -direction, -(vec3(hi + 1u) + margin), -(vec3(lo) - margin));
  float t0 = max(box.x, pixelRayNearT(frame) - ray.base);  // never before the near plane
  float t1 = box.y;
  uint evaluations = 0u;
  BrickHit hit = BrickHit(-1.0, 0u);
  if (t0 < t1) hit = walkBrick(draw, brick, ivec3(lo), ivec3(hi), packCellBounds(lo, hi), origin, direction, margin, t0, t1, evaluations);
  countWork(evaluations);
  if (hit.t < 0.0) {
    writeMiss();  // no discard: see hit_depth.glsl
  } else {
    writeHitDepth(pixelRayHitDepth(frame, ray.base, hit.t));  // at the brick's face if in front of it (front faces)
  }
  outVisibility = uvec2(draw.object + 1u, hit.record);  // kept only where the depth test passes
  outHitOffset = pixelRayHitOffset(frame, hit.t);
}
