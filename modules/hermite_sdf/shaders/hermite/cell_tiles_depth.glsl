// Depth prepass of the tiled cells (cell_tiles.vert): the fragment walks its tile's list of kept
// cells (cell_tiles.comp), skips those whose screen rectangle misses its pixel (the entry's
// pixels: one load and a compare, where the ray-box test below costs the cell's record, the
// dilation and two slab tests), and searches every one whose dilated box its ray meets, exactly as that
// cell's own box would have (cells_thin_depth.glsl: the box dilated as the proxy, the search over
// the search margin, cell_search.glsl; docs/root-finding.md); the nearest root wins, as the depth
// test would have chosen among the boxes. A cell whose box the ray enters only behind the nearest
// root found so far cannot hold a nearer one and is skipped; in a sorted list (cell_tiles.comp:
// nearest box first, lists of at most CELL_TILE_SORT_MAX) the walk stops at the first entry whose
// box lies wholly behind the hit. Included by
// cell_tiles_depth{,_counted}.frag; no early depth variant.
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/proxy_dilation.glsl"
#include "hermite/pixel_ray.glsl"
#include "hermite/record_cell.glsl"

layout(push_constant, scalar) uniform Push { HermitePushConstants pc; };
layout(buffer_reference, scalar) readonly buffer TilesRef { CellTile tiles[]; };
layout(buffer_reference, scalar) readonly buffer TileEntriesRef { CellTileEntry entries[]; };
#include "hermite/cell_search.glsl"

layout(location = 0) flat in uint inTile;

layout(location = 0) out uvec2 outVisibility;  // (1 + object, cell record)
#if defined(HSDF_CONSERVATIVE_DEPTH)
layout(depth_less) out float gl_FragDepth;  // reverse-Z: the hit is never nearer than the tile's quad
#endif
#include "hermite/hit_depth.glsl"

// Whether the pixel at `local` (in its tile) is among an entry's pixels (CellTileEntry::pixels).
bool cellTileEntryCovers(uint pixels, uvec2 local) {
  uvec2 lo = uvec2(pixels & 0xffu, (pixels >> 8) & 0xffu);
  uvec2 hi = uvec2((pixels >> 16) & 0xffu, pixels >> 24);
  return all(greaterThanEqual(local, lo)) && all(lessThanEqual(local, hi));
}

void main() {
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;
  CellTile tile = TilesRef(pc.tiles).tiles[inTile];
  uint evaluations = 0u;
  float best = 3.0e38;
  uvec2 visibility = uvec2(0u);
  bool sorted = tile.count <= CELL_TILE_SORT_MAX;
  // The ray of the entry's object, rebuilt only when the object changes (pixel_ray.glsl: t is the
  // same view-linear parameter for every object, so hits of different objects compare).
  uint lastObject = 0xffffffffu;
  ObjectData object;
  vec3 eyeGrid, direction;
  uint i = 0u;
  uint walked = 0u, tested = 0u;  // the list entries read and ray-box tested (countTileWalk)
  uvec2 local = uvec2(gl_FragCoord.xy) % pc.tileSize;  // tiles start at multiples of the size
  for (;;) {
    // The next entry this fragment must search, by cheap tests only: the search below has one call
    // site, so the lanes of a SIMD group (a GPU's warp, lavapipe's 4x4 block, which runs a loop's
    // whole body whatever its lanes need) share its iterations instead of running it once per
    // entry of the list (as bricks_depth.glsl does for a brick's cells).
    bool pending = false;
    HermiteDraw draw;
    uint record = 0u;
    vec3 origin;
    float margin = 0.0;
    for (; i < tile.count && !pending; ++i) {
      CellTileEntry entry = TileEntriesRef(pc.tileEntries).entries[tile.first + i];
      ++walked;
      if (sorted && visibility.x != 0u && entry.nearest < gl_FragCoord.z / best) {
        i = tile.count;  // this box and the rest lie behind the hit
        break;
      }
      if (!cellTileEntryCovers(entry.pixels, local)) continue;  // its box cannot meet this ray
      ++tested;
      draw = HermiteDrawsRef(pc.draws).draws[entry.draw];
      if (draw.object != lastObject) {
        lastObject = draw.object;
        object = ObjectsRef(pc.draw.objects).objects[draw.object];
        float h = draw.gridOriginSpacing.w;
        eyeGrid = ((object.invModel * vec4(frame.cameraPosition.xyz, 1.0)).xyz - draw.gridOriginSpacing.xyz) / h;
        direction = pixelRayDirection(frame, object.invModel, h);
      }
      vec3 cell = recordCell(draw, entry.record);
      origin = eyeGrid - cell;
      float h = draw.gridOriginSpacing.w;
      float dilation = proxyDilation(frame, object, draw.gridOriginSpacing.xyz + h * (cell + 0.5), h);
      // Would the cell's own proxy have covered this pixel? And can its search (over the margin,
      // at least the dilation) begin in front of what was found already?
      vec2 box = intersectBox(origin, direction, vec3(-dilation), vec3(1.0 + dilation));
      margin = searchMargin(origin, dilation);
      vec2 searched = intersectBox(origin, direction, vec3(-margin), vec3(1.0 + margin));
      pending = max(box.x, gl_FragCoord.z) < box.y && max(searched.x, gl_FragCoord.z) < best;
      record = entry.record;
    }
    if (!pending) break;
    float t = searchCell(draw, record, origin, direction, margin, gl_FragCoord.z, 3.0e38, evaluations);
    if (t >= 0.0 && t < best) {
      best = t;
      visibility = uvec2(draw.object + 1u, record);
    }
  }
  countWork(evaluations);
  countTileWalk(walked, tested);
  if (visibility.x == 0u) {
    writeMiss();  // no discard: see hit_depth.glsl
  } else {
#ifdef HSDF_CONSERVATIVE_DEPTH
    best = max(best, 1.0);  // a root in the margin before the quad is drawn at the quad (cells_depth.glsl)
#endif
    writeHitDepth(gl_FragCoord.z / best);
  }
  outVisibility = visibility;  // kept only where the depth test passes
}
