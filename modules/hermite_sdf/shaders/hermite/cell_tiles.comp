#version 460
// Tiled cells (issue 20; HermiteCellFeature::Settings::tiles, hsdf::CellTiler): the kept cells of
// the cell culling pass binned into screen tiles of pc.tileSize^2 pixels, so that the prepass
// draws one quad per tile holding a cell instead of one box per cell (cell_tiles.vert,
// cell_tiles_depth.glsl). Five phases (pc.phase), recorded in this order with barriers:
//  - COUNT: a lane per kept cell (per slot of the culling pass's kept stream): the screen rectangle of the
//    cell's proxy box (record_cell.glsl), grown by its dilation (below); every
//    tile it touches counts the cell and keeps the nearest depth of the boxes;
//  - SCAN (one workgroup): each tile's first entry (a prefix sum of the counts), the list of
//    non-empty tiles and the tile draw's instance count; where the lists would not fit in the
//    entry list's capacity, no tile at all and the boxes' fallback count (CellTileTotals::boxDrawCount);
//  - SCATTER: the same rectangles, each cell's (draw, record, depth, the tile's pixels it may cover)
//    written into the lists of its tiles;
//  - SORT: a workgroup per few non-empty tiles (the scan's groups, an indirect dispatch): each list copied
//    to the sorted entries nearest first (depth, then draw and record: the same order whatever
//    order the atomics wrote), so that a fragment stops at the first cell behind its hit. Longer
//    lists keep the scatter's order and are walked whole (the fragment shader knows them by their
//    length);
//  - MASKS: a workgroup per CELL_TILE_MASK_GROUP_ROWS rows of masks (a row: 32 sorted entries of
//    one tile): each pixel's bit masks of the sorted entries whose pixels hold it (the layout at
//    CELL_TILE_MASK_BITS), so that a fragment reads only the entries that may cover it (the list's
//    length grows with K, those entries do not).
// Every invocation's loops are bounded whatever the lists' lengths: lavapipe (Mesa's gallivm) ends
// all loops of an invocation, silently, once it has run 65,535 loop iterations in all
// (LP_MAX_TGSI_LOOP_ITERATIONS). Masks walked per tile, 8 tiles a workgroup, drew 16x16-pixel holes
// in a scene whose lists held thousands of entries; a sort of 8 tiles a workgroup left lists of
// ~900 entries unsorted. Hence sort workgroups of at most 16 x 1024 compares a lane, a few rows
// for the masks, and no tiles for a cell whose rectangle spans more than
// CELL_TILE_MAX_CELL_TILES tiles (COUNT, below).
// The rectangle only has to hold every pixel whose ray meets the dilated box: the fragment shader
// tests each listed box against its own ray, as the rasterizer would have. The objects' matrices
// come from the culling pass's BrickCullObjects (written before this pass; the scene's ObjectData
// are uploaded only after the features' prepare), with the smallest scale (objectMinScale's) that the proxy's
// dilation (0.02 pixel at the cell's centre, at least kMinDilation cells) is computed from.
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/proxy_dilation.glsl"
#include "hermite/record_cell.glsl"

layout(local_size_x = 64) in;

layout(buffer_reference, scalar) readonly buffer RangesRef { CellCullRange ranges[]; };
layout(buffer_reference, scalar) readonly buffer UintsRef { uint words[]; };
layout(buffer_reference, scalar) buffer TilesRef { CellTile tiles[]; };
layout(buffer_reference, scalar) buffer TileListRef { uint tiles[]; };
layout(buffer_reference, scalar) writeonly buffer EntriesRef { CellTileEntry entries[]; };
layout(buffer_reference, scalar) readonly buffer ReadEntriesRef { CellTileEntry entries[]; };
layout(buffer_reference, scalar) buffer TotalsRef { CellTileTotals totals; };

layout(push_constant, scalar) uniform Push { CellTilePushConstants pc; };

shared uint groupSums[64];
shared uint groupTiles[64];
shared uint groupSorts[64];  // the sort's workgroups that start in each lane's tiles

// The pixels [lo, hi] (inclusive, frame coordinates) whose centres may see the cell's dilated proxy box,
// and the nearest depth of the box (1, the near plane, when a corner lies at or behind the eye:
// the box then spans the screen). False when no pixel centre of the frame does.
bool cellPixelRect(HermiteDraw draw, uint object, uint record, out ivec2 lo, out ivec2 hi, out float nearest) {
  FrameGlobals frame = FrameGlobalsRef(pc.frameGlobals).globals;
  BrickCullObject cullObject = CullObjectsRef(pc.objects).objects[object];
  mat4 toClip = cullObject.objectToClip;
  vec3 boxLo, boxHi;  // the cell's proxy box (record_cell.glsl)
  vec3 cell = recordCellBox(draw, record, boxLo, boxHi);
  float h = draw.gridOriginSpacing.w;
  // The proxy's dilation (as proxyDilation; clip w is the view depth -z), a percent more for the
  // rounding of the two computations.
  float centreDepth = (toClip * vec4(draw.gridOriginSpacing.xyz + h * (cell + 0.5), 1.0)).w;
  float dilation = 1.01 * proxyDilationAt(frame, centreDepth, h, cullObject.minScale);
  vec2 pmin = vec2(3.0e38), pmax = vec2(-3.0e38);
  nearest = 0.0;
  bool behind = false;
  for (int c = 0; c < 8; ++c) {
    vec3 corner = mix(boxLo - dilation, boxHi + dilation, vec3(c & 1, (c >> 1) & 1, c >> 2));
    vec4 clip = toClip * vec4(draw.gridOriginSpacing.xyz + h * (cell + corner), 1.0);
    if (clip.w <= 1.0e-6 * abs(clip.z) || clip.w <= 0.0) {
      behind = true;
      continue;
    }
    vec2 pixel = (clip.xy / clip.w * 0.5 + 0.5) * frame.viewport.xy;
    pmin = min(pmin, pixel);
    pmax = max(pmax, pixel);
    nearest = max(nearest, clip.z / clip.w);
  }
  if (behind) {
    pmin = vec2(0.0);
    pmax = frame.viewport.xy;
    nearest = 1.0;
  }
  // A hit may lie up to the search margin (the dilation, well under 1e-4 of the distance) in front of
  // the box: the entry's depth is taken that much nearer, so sorting by it never skips a hit.
  nearest = clamp(nearest * 1.0002, 0.0, 1.0);
  // The rectangle holds the projection of the dilated box, in which lies the centre of every pixel
  // whose ray meets it (the fragment's test); 1/16 pixel more for the rounding of this projection
  // and of the fragment's ray (a few thousandths of a pixel). No rasterizer is involved: the tile's
  // quad covers its pixels whole.
  pmin -= 0.0625;
  pmax += 0.0625;
  // The pixel centres (x + 0.5) inside [pmin, pmax], clamped to the frame first (a corner near the
  // eye's plane projects arbitrarily far).
  vec2 size = frame.viewport.xy;
  lo = ivec2(ceil(clamp(pmin, vec2(-1.0), size + 1.0) - 0.5));
  hi = ivec2(floor(clamp(pmax, vec2(-1.0), size + 1.0) - 0.5));
  lo = max(lo, ivec2(0));
  hi = min(hi, ivec2(size) - 1);
  return all(lessThanEqual(lo, hi));
}

// The tile-local pixels of `rect` in tile (x, y), packed as CellTileEntry::pixels.
uint tilePixels(ivec2 lo, ivec2 hi, uint x, uint y) {
  ivec2 origin = ivec2(x, y) * int(pc.tileSize);
  uvec2 a = uvec2(clamp(lo - origin, ivec2(0), ivec2(pc.tileSize - 1u)));
  uvec2 b = uvec2(clamp(hi - origin, ivec2(0), ivec2(pc.tileSize - 1u)));
  return a.x | (a.y << 8) | (b.x << 16) | (b.y << 24);
}

// One lane per slot of the kept streams that the culling pass filled (its cursor, at most the
// slots they hold): a lane per cell rather than a workgroup per range, whose rows hold a few cells
// each at large K. Each kept cell's range says its draw and object; a hole (a range whose claim did
// not fit: its fallback command draws it as boxes) has none.
void binCells() {
  uint slot = (gl_WorkGroupID.x + gl_NumWorkGroups.x * gl_WorkGroupID.y) * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
  if (slot >= min(pc.slotCount, UintsRef(pc.keptCount).words[0])) return;
  uint rangeIndex = UintsRef(pc.keptRanges).words[slot];
  if (rangeIndex >= pc.rangeCount) return;
  CellCullRange range = RangesRef(pc.ranges).ranges[rangeIndex];
  HermiteDraw draw = hermiteDraw(pc.draws, range.drawCommand);
  TilesRef tiles = TilesRef(pc.tiles);
  {
    uint record = UintsRef(pc.keptIndices).words[slot];
    ivec2 pixelLo, pixelHi;
    float nearest;
    if (!cellPixelRect(draw, range.object, record, pixelLo, pixelHi, nearest)) return;
    uvec2 lo = uvec2(pixelLo) / pc.tileSize, hi = uvec2(pixelHi) / pc.tileSize;
    // A rectangle of more tiles than one lane may walk (the eye near or inside the cell): the frame
    // draws its boxes instead (the scan's overflow), as it does where the lists would not fit.
    uvec2 span = hi - lo + 1u;
    if (span.x * span.y > CELL_TILE_MAX_CELL_TILES) {
      if (pc.phase == CELL_TILES_COUNT) atomicAdd(TotalsRef(pc.totals).totals.hugeCells, 1u);
      return;
    }
    for (uint y = lo.y; y <= hi.y; ++y)
      for (uint x = lo.x; x <= hi.x; ++x) {
        uint tile = y * pc.tilesX + x;
        if (pc.phase == CELL_TILES_COUNT) {
          atomicAdd(tiles.tiles[tile].count, 1u);
          atomicMax(tiles.tiles[tile].depth, floatBitsToUint(nearest));
        } else {
          uint slot = atomicAdd(tiles.tiles[tile].cursor, 1u);
          if (slot < tiles.tiles[tile].count) {
            uint at = tiles.tiles[tile].first + slot;
            EntriesRef(pc.entries).entries[at].draw = range.drawCommand;
            EntriesRef(pc.entries).entries[at].record = record;
            EntriesRef(pc.entries).entries[at].nearest = nearest;
            EntriesRef(pc.entries).entries[at].pixels = tilePixels(pixelLo, pixelHi, x, y);
          }
        }
      }
  }
}

// The compares one lane makes sorting a list of `count` entries in a workgroup (sortList).
uint sortWork(uint count) {
  uint rounds = (count + 63u) / 64u;
  return count <= CELL_TILE_SORT_MAX ? rounds * count : rounds;
}

// The sort's workgroups, formed in list order while the scan walks its tiles: a workgroup takes the
// next non-empty tile, and the ones after it while they are at most CELL_TILE_SORT_GROUP_TILES and
// their compares per lane at most CELL_TILE_SORT_GROUP_WORK (one list of CELL_TILE_SORT_MAX
// entries: 16 x 1024). Whether tile `count` starts a workgroup; `tiles` and `work` are the open one's.
bool startsSortGroup(uint count, inout uint tiles, inout uint work) {
  uint w = sortWork(count);
  if (tiles > 0u && tiles < CELL_TILE_SORT_GROUP_TILES && work + w <= CELL_TILE_SORT_GROUP_WORK) {
    ++tiles;
    work += w;
    return false;
  }
  tiles = 1u;
  work = w;
  return true;
}

// One workgroup: lane l takes a contiguous chunk of tiles; the chunks' sums are prefix-summed in
// shared memory, then each lane writes its tiles' first entries and its part of the tile list.
void scanTiles() {
  uint tileCount = pc.tilesX * pc.tilesY;
  uint lane = gl_LocalInvocationID.x;
  uint chunk = (tileCount + 63u) / 64u;
  uint begin = min(lane * chunk, tileCount), end = min(begin + chunk, tileCount);
  TilesRef tiles = TilesRef(pc.tiles);
  uint sum = 0u, nonEmpty = 0u, sorts = 0u, openTiles = 0u, openWork = 0u;  // the open sort workgroup
  for (uint t = begin; t < end; ++t) {
    uint count = tiles.tiles[t].count;
    sum += count;
    nonEmpty += count > 0u ? 1u : 0u;
    if (count > 0u && startsSortGroup(count, openTiles, openWork)) ++sorts;  // a lane's groups end with its chunk
  }
  groupSums[lane] = sum;
  groupTiles[lane] = nonEmpty;
  groupSorts[lane] = sorts;
  barrier();
  uint first = 0u, listed = 0u, needed = 0u, sortFirst = 0u, sortCount = 0u;
  for (uint l = 0u; l < 64u; ++l) {
    if (l < lane) {
      first += groupSums[l];
      listed += groupTiles[l];
      sortFirst += groupSorts[l];
    }
    needed += groupSums[l];
    sortCount += groupSorts[l];
  }
  // Lists that do not fit whole would lose cells (holes), as would a cell COUNT left out for its
  // size (hugeCells): then every tile is left empty (nothing scattered, sorted or drawn) and the
  // culled cells' boxes are drawn instead (boxDrawCount).
  bool overflow = needed > pc.entryCapacity || TotalsRef(pc.totals).totals.hugeCells > 0u;
  TileListRef list = TileListRef(pc.tiles + CELL_TILE_LIST_OFFSET(tileCount));
  TileListRef sortStarts = TileListRef(pc.tiles + CELL_TILE_SORT_GROUPS_OFFSET(tileCount));
  openTiles = 0u;  // the same groups again, written this time
  openWork = 0u;
  for (uint t = begin; t < end; ++t) {
    uint count = tiles.tiles[t].count;
    tiles.tiles[t].first = first;
    tiles.tiles[t].count = overflow ? 0u : count;
    tiles.tiles[t].cursor = 0u;
    if (count > 0u && !overflow) {
      if (startsSortGroup(count, openTiles, openWork)) sortStarts.tiles[sortFirst++] = listed;
      list.tiles[listed++] = t;
    }
    first += count;
  }
  if (lane == 63u) {
    if (overflow) listed = 0u;
    TotalsRef(pc.totals).totals.instanceCount = listed;
    TotalsRef(pc.totals).totals.entriesNeeded = needed;
    TotalsRef(pc.totals).totals.boxDrawCount = overflow ? 0xffffffffu : 0u;
    if (overflow) sortCount = 0u;
    TotalsRef(pc.totals).totals.sortGroupCount = sortCount;
    uint groupsX = min(sortCount, 65535u);  // the least maxComputeWorkGroupCount[0] Vulkan allows
    TotalsRef(pc.totals).totals.sortGroups[0] = groupsX;
    TotalsRef(pc.totals).totals.sortGroups[1] = groupsX == 0u ? 0u : (sortCount + groupsX - 1u) / groupsX;
    TotalsRef(pc.totals).totals.sortGroups[2] = 1u;
    // The mask rows (a chunk of 32 entries of one tile each) lie below needed / 32 + listed + 1.
    uint maskRows = listed == 0u ? 0u : needed / CELL_TILE_MASK_BITS + listed + 1u;
    uint maskGroups = (maskRows + CELL_TILE_MASK_GROUP_ROWS - 1u) / CELL_TILE_MASK_GROUP_ROWS;
    uint maskGroupsX = min(maskGroups, 65535u);
    TotalsRef(pc.totals).totals.maskGroups[0] = maskGroupsX;
    TotalsRef(pc.totals).totals.maskGroups[1] = maskGroupsX == 0u ? 0u : (maskGroups + maskGroupsX - 1u) / maskGroupsX;
    TotalsRef(pc.totals).totals.maskGroups[2] = 1u;
  }
}

// Whether entry a comes before entry b: nearer first (reverse-Z: larger depth), ties by draw and
// record (a total order: no two entries of one tile are the same cell).
bool before(CellTileEntry a, CellTileEntry b) {
  if (a.nearest != b.nearest) return a.nearest > b.nearest;
  if (a.draw != b.draw) return a.draw < b.draw;
  return a.record < b.record;
}

// One tile's list, copied from the scatter's entries to the sorted ones: each entry goes to its
// rank, the number of entries before it (a rank sort: quadratic, but without barriers, which cost
// software rasterizers' compute dearly; lists are short). Lists longer than CELL_TILE_SORT_MAX are
// copied as they are.
void sortList(uint first, uint count) {
  ReadEntriesRef source = ReadEntriesRef(pc.entries);
  EntriesRef target = EntriesRef(pc.sortedEntries);
  for (uint i = gl_LocalInvocationID.x; i < count; i += gl_WorkGroupSize.x) {
    CellTileEntry entry = source.entries[first + i];
    uint rank = i;
    if (count <= CELL_TILE_SORT_MAX) {
      rank = 0u;
      for (uint j = 0u; j < count; ++j) rank += before(source.entries[first + j], entry) ? 1u : 0u;
    }
    target.entries[first + rank].draw = entry.draw;
    target.entries[first + rank].record = entry.record;
    target.entries[first + rank].nearest = entry.nearest;
    target.entries[first + rank].pixels = entry.pixels;
  }
}

// One of the scan's sort workgroups (startsSortGroup): its tiles' lists one after the other. A
// workgroup per tile cost software rasterizers ~3 us for lists of a few entries; the bound on the
// compares keeps every lane far below lavapipe's 65,535 loop iterations per invocation (above: 8
// tiles per workgroup whatever their lengths left a list of 889 entries unsorted).
void sortTiles() {
  uint group = gl_WorkGroupID.x + gl_NumWorkGroups.x * gl_WorkGroupID.y;
  uint groups = TotalsRef(pc.totals).totals.sortGroupCount;
  if (group >= groups) return;
  uint tileCount = pc.tilesX * pc.tilesY;
  TileListRef list = TileListRef(pc.tiles + CELL_TILE_LIST_OFFSET(tileCount));
  TileListRef sortStarts = TileListRef(pc.tiles + CELL_TILE_SORT_GROUPS_OFFSET(tileCount));
  uint begin = sortStarts.tiles[group];
  uint end = group + 1u < groups ? sortStarts.tiles[group + 1u] : TotalsRef(pc.totals).totals.instanceCount;
  for (uint listIndex = begin; listIndex < end; ++listIndex) {
    CellTile tile = TilesRef(pc.tiles).tiles[list.tiles[listIndex]];
    sortList(tile.first, tile.count);
  }
}

// Whether the tile-local pixel `local` is among an entry's pixels (CellTileEntry::pixels).
bool entryCovers(uint pixels, uvec2 local) {
  uvec2 lo = uvec2(pixels & 0xffu, (pixels >> 8) & 0xffu);
  uvec2 hi = uvec2((pixels >> 16) & 0xffu, pixels >> 24);
  return all(greaterThanEqual(local, lo)) && all(lessThanEqual(local, hi));
}

// The first mask row of listed tile i: (first / 32 + i), in units of a tile's pixels (the layout
// at CELL_TILE_MASK_BITS); rows increase with i.
uint maskRow(uint listIndex, TileListRef list) {
  return TilesRef(pc.tiles).tiles[list.tiles[listIndex]].first / CELL_TILE_MASK_BITS + listIndex;
}

// CELL_TILE_MASK_GROUP_ROWS mask rows per workgroup (a row: one chunk of 32 sorted entries of one
// tile, a word per pixel), a lane per pixel of each: bounded work per invocation whatever the lists'
// lengths, no atomics and no barrier. Each row's tile is the last listed tile whose first row is at
// or before it (a binary search for the group's first row, then steps); rows between two tiles'
// rows hold no chunk and are skipped. The row of a tile's first chunk also writes the tile's first
// mask word to its cursor, which the scatter no longer needs.
void maskRows() {
  uint group = gl_WorkGroupID.x + gl_NumWorkGroups.x * gl_WorkGroupID.y;
  uint listed = TotalsRef(pc.totals).totals.instanceCount;
  if (listed == 0u) return;
  uint tileCount = pc.tilesX * pc.tilesY;
  TileListRef list = TileListRef(pc.tiles + CELL_TILE_LIST_OFFSET(tileCount));
  TileListRef masks = TileListRef(pc.tiles + CELL_TILE_MASKS_OFFSET(tileCount));
  ReadEntriesRef sorted = ReadEntriesRef(pc.sortedEntries);
  uint pixels = pc.tileSize * pc.tileSize;
  uint firstRow = group * CELL_TILE_MASK_GROUP_ROWS;
  uint lo = 0u, hi = listed - 1u;
  while (lo < hi) {
    uint mid = (lo + hi + 1u) / 2u;
    if (maskRow(mid, list) <= firstRow) lo = mid; else hi = mid - 1u;
  }
  for (uint row = firstRow; row < firstRow + CELL_TILE_MASK_GROUP_ROWS; ++row) {
    // Each tile has a row at least: the next rows' tiles are at most a row's worth of steps on.
    while (lo + 1u < listed && maskRow(lo + 1u, list) <= row) ++lo;
    uint tile = list.tiles[lo];
    uint first = TilesRef(pc.tiles).tiles[tile].first, count = TilesRef(pc.tiles).tiles[tile].count;
    uint tileRow = first / CELL_TILE_MASK_BITS + lo;
    uint chunk = row - tileRow;
    if (row < tileRow || chunk * CELL_TILE_MASK_BITS >= count) continue;  // between two tiles' rows
    if (chunk == 0u && gl_LocalInvocationID.x == 0u) TilesRef(pc.tiles).tiles[tile].cursor = tileRow * pixels;
    uint begin = first + chunk * CELL_TILE_MASK_BITS, end = min(count - chunk * CELL_TILE_MASK_BITS, CELL_TILE_MASK_BITS);
    for (uint p = gl_LocalInvocationID.x; p < pixels; p += gl_WorkGroupSize.x) {
      uvec2 local = uvec2(p % pc.tileSize, p / pc.tileSize);
      uint mask = 0u;
      for (uint j = 0u; j < end; ++j)
        if (entryCovers(sorted.entries[begin + j].pixels, local)) mask |= 1u << j;
      masks.tiles[row * pixels + p] = mask;
    }
  }
}

void main() {
  if (pc.phase == CELL_TILES_SCAN) {
    scanTiles();
  } else if (pc.phase == CELL_TILES_SORT) {
    sortTiles();
  } else if (pc.phase == CELL_TILES_MASKS) {
    maskRows();
  } else {
    binCells();
  }
}
