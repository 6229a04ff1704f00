// Depth prepass of the tiled cells (cell_tiles.vert): the fragment walks the entries of its tile's
// list of kept cells (cell_tiles.comp) that its pixel's masks name (those whose screen rectangle
// holds the pixel: the rest of the list, which grows with K, is never read), and searches every
// one whose dilated box its ray meets, exactly as that
// cell's own box would have (cells_thin_depth.glsl: the box dilated as the proxy, the search over
// the search margin, cell_search.glsl; docs/root-finding.md); the nearest root wins, as the depth
// test would have chosen among the boxes. A cell whose box the ray enters only behind the nearest
// root found so far cannot hold a nearer one and is skipped; in a sorted list (cell_tiles.comp:
// nearest box first, lists of at most CELL_TILE_SORT_MAX) the walk stops at the first entry whose
// box lies wholly behind the hit. Compiled as
// cell_tiles_depth{,_counted}.frag; no early depth variant.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "hermite/hermite_host_device.h"
#include "hermite/proxy_dilation.glsl"
#include "hermite/pixel_ray.glsl"
#include "hermite/record_cell.glsl"

layout(push_constant, scalar) uniform Push { HermitePushConstants pc; };
layout(buffer_reference, scalar) readonly buffer TilesRef { CellTile tiles[]; };
layout(buffer_reference, scalar) readonly buffer TileEntriesRef { CellTileEntry entries[]; };
layout(buffer_reference, scalar) readonly buffer TileMasksRef { uint word; };
#include "hermite/cell_search.glsl"

layout(location = 0) flat in uint inTile;

layout(location = 0) out uvec2 outVisibility;  // (1 + object, cell record)
layout(location = 1) out float outHitOffset;  // where along the ray: pixelRayHitOffset (pixel_ray.glsl)
#if defined(HSDF_CONSERVATIVE_DEPTH)
layout(depth_less) out float gl_FragDepth;  // reverse-Z: the hit is never nearer than the tile's quad
#endif
#include "hermite/hit_depth.glsl"

void main() {
  FrameGlobals frame = FrameGlobalsRef(pc.draw.frameGlobals).globals;
  CellTile tile = TilesRef(pc.tiles).tiles[inTile];
  uint evaluations = 0u;
  float best = 3.0e38;
  uvec2 visibility = uvec2(0u);
  float hitT = 0.0;  // the best hit in its own object's t, unconverted: what the resolve rebuilds it from
  bool sorted = tile.count <= CELL_TILE_SORT_MAX;
  // The ray of the entry's object, rebuilt only when the object changes, based near that object
  // (pixel_ray.glsl): t is an offset from the object's base, the camera's t less `base`. The near
  // plane's t and the best hit's are kept in the current object's t (converted when the object
  // changes: the camera's t is the same view-linear parameter for every object, so hits of
  // different objects compare), at float's precision among the object's cells. Only the
  // ray is kept from one entry to the next, never the object's or the draw's record: they are read
  // again where needed (cached loads), since whatever lives through the walk adds to the registers
  // of the search below, which set how many fragments a GPU keeps in flight.
  uint lastObject = 0xffffffffu;
  vec3 originGrid, direction;  // the ray in grid units
  float base = 0.0;
  float tNear = 0.0;
  uint walked = 0u, tested = 0u, maskWords = 0u;  // entries and mask words read, entries ray-box tested
  // This pixel's masks (cell_tiles.comp, CELL_TILE_MASK_BITS): word c names the entries 32c..32c+31
  // whose screen rectangle holds the pixel; the others are never read.
  uvec2 local = uvec2(gl_FragCoord.xy) % pc.tileSize;  // tiles start at multiples of the size
  uvec2 tiles = (uvec2(frame.viewport.xy) + pc.tileSize - 1u) / pc.tileSize;
  uint pixels = pc.tileSize * pc.tileSize;
  uint64_t masks = pc.tiles + CELL_TILE_MASKS_OFFSET(tiles.x * tiles.y) + uint64_t(tile.cursor + local.y * pc.tileSize + local.x) * 4ul;
  uint chunks = (tile.count + CELL_TILE_MASK_BITS - 1u) / CELL_TILE_MASK_BITS;
  uint chunk = 0u, mask = 0u;
  for (;;) {
    // The next entry this fragment must search, by cheap tests only: the search below has one call
    // site, so the lanes of a SIMD group (a GPU's warp, lavapipe's 4x4 block, which runs a loop's
    // whole body whatever its lanes need) share its iterations instead of running it once per
    // entry of the list (as bricks_depth.glsl does for a brick's cells).
    bool pending = false;
    uint drawCommand = 0u, record = 0u;
    // Set afresh in every pass: left unset, the last pass's values would have to live through its
    // search (the compiler cannot see that they are never read before being set again).
    vec3 origin = vec3(0.0), lo = vec3(0.0), hi = vec3(0.0);  // the ray in cell-local coordinates, the proxy box
    float margin = 0.0;
    while (!pending) {
      if (mask == 0u) {
        if (chunk == chunks) break;
        mask = TileMasksRef(masks + uint64_t(chunk * pixels) * 4ul).word;
        ++chunk;
        ++maskWords;
        continue;
      }
      uint i = (chunk - 1u) * CELL_TILE_MASK_BITS + uint(findLSB(mask));
      mask &= mask - 1u;
      CellTileEntry entry = TileEntriesRef(pc.tileEntries).entries[tile.first + i];
      ++walked;
      if (sorted && visibility.x != 0u && entry.nearest < pixelRayDepth(frame, base + best)) {
        chunk = chunks;  // this box and the rest lie behind the hit
        mask = 0u;
        break;
      }
      ++tested;
      HermiteDraw draw = hermiteDraw(pc.draws, entry.draw);
      if (draw.object != lastObject) {
        lastObject = draw.object;
        mat4 invModel = ObjectsRef(pc.draw.objects).objects[draw.object].invModel;
        float h = draw.gridOriginSpacing.w;
        PixelRay ray = pixelRay(frame, invModel, h, draw.rayAnchor);
        originGrid = ray.origin;
        direction = ray.direction;
        best += base - ray.base;  // none yet: 3e38 stays
        base = ray.base;
        tNear = pixelRayNearT(frame) - base;
      }
      vec3 cell = recordCellBox(draw, entry.record, lo, hi);
      origin = originGrid - cell;
      float h = draw.gridOriginSpacing.w;
      float dilation = proxyDilation(frame, ObjectsRef(pc.draw.objects).objects[draw.object],
                                     draw.gridOriginSpacing.xyz + h * (cell + 0.5), h);
      // Would the cell's own proxy have covered this pixel? And can its search (over the proxy, the
      // search margin is the dilation) begin in front of what was found already?
      vec2 box = intersectBox(origin, direction, lo - dilation, hi + dilation);
      margin = dilation;
      pending = max(box.x, tNear) < box.y && max(box.x, tNear) < best;
      record = entry.record;
      drawCommand = entry.draw;
    }
    if (!pending) break;
    HermiteDraw draw = hermiteDraw(pc.draws, drawCommand);
    float t = searchCell(draw, record, lo, hi, origin, direction, margin, tNear, 3.0e38, evaluations);
    if (t >= 0.0 && t < best) {
      best = t;
      hitT = t;
      visibility = uvec2(draw.object + 1u, record);
    }
  }
  countWork(evaluations);
  countTileWalk(walked, tested, maskWords);
  if (visibility.x == 0u) {
    writeMiss();  // no discard: see hit_depth.glsl
  } else {
    writeHitDepth(pixelRayHitDepth(frame, base, best));  // at the quad if in front of it (cells_depth.glsl)
  }
  outVisibility = visibility;  // kept only where the depth test passes
  outHitOffset = pixelRayHitOffset(frame, hitT);
}
