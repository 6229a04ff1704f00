// GPU structs of the hermite_sdf module, shared by C++ and GLSL (see shared/host_device.h for the
// conventions). Included after shared/host_device.h.
#ifndef HSDF_HERMITE_HOST_DEVICE_H
#define HSDF_HERMITE_HOST_DEVICE_H

#include "shared/host_device.h"

#ifdef __cplusplus
namespace shader {
#endif

// Render flags (HermiteDraw::flags).
#define HERMITE_FLAG_NORMALS_CENTRAL 1u  // central differences instead of the exact gradient
#define HERMITE_FLAG_NEAR_CELL 2u        // the cell may intersect the near plane: drawn by back faces
#define HERMITE_FLAG_CERTIFIED 4u        // certified first-root search instead of n equidistant samples
#define HERMITE_FLAG_HALF_RECORDS 8u     // cell runs, bricks: the records are CellRecordHalfGpu (else CellRecordGpu)
#define HERMITE_FLAG_WHOLE_CELLS 16u     // cell methods: the paper's proxy, the whole cell, not the record's proxy box

// One per indirect draw command of a Hermite feature: which object, and how to search.
struct HermiteDraw {
  vec4 gridOriginSpacing;  // xyz: grid origin in object space; w: spacing h
  // Cells: where this view's rays are based (pixel_ray.glsl), made per object and view region on
  // the host in double (render/ray_anchor.h, rayAnchorGrid): xyz in grid units (object space / spacing,
  // from the grid origin), w its view depth (world units; 0: the rays start at the eye). A float
  // made on the GPU from an eye ~7.5e6 cells out holds ~0.5 cell; this one holds float's
  // precision near the object, and costs no shader anything.
  vec4 rayAnchor;
  uint object;             // index into ObjectData[]
  uint subdivisions;       // n >= 1
  uint refineSteps;
  uint flags;              // HERMITE_FLAG_*
  uint resolution;         // K samples per axis (sphere tracing: texture size)
  uint firstCell;          // cells: index of the object's first record in the cell buffer
  uint64_t records;        // cell runs, bricks: address of the record buffer they index (0 for cells)
};
HSDF_CHECK_SIZE(HermiteDraw, 2 * 16 + 6 * 4 + 8);

// The frame's draw table, what the shaders' `draws` address points at: this header, then one uint
// per indirect command naming its HermiteDraw in the records. An object's rows are many commands
// (front to back, their culling fallbacks, the wireframe's copies) sharing one record: a record per
// command cost 48 bytes each, 4.9 GB for a million instanced objects.
struct HermiteDrawTableHeader {
  uint64_t records;  // address of HermiteDraw[]
  uint64_t unused;   // keeps the per-command indices 16-byte aligned
};
HSDF_CHECK_SIZE(HermiteDrawTableHeader, 16);

// A kept cell's record as the GPU reads it by address (the resolve pass, the cell runs), the same
// bytes as hsdf::CellRecord / CellRecordHalf (cells.h asserts it): 8 corners (f, fx, fy, fz), corner
// x + 2y + 4z, then the cell coordinate and class as 16-bit pairs (x | y << 16, z | class << 16).
// In the GPU's copies the class halfword also holds the cell's proxy box (hsdf::packProxyBox, cells.h
// "Proxy boxes"): class | code << CELL_PROXY_SHIFT, the code (x pair) + 21 ((y pair) + 21 (z pair)),
// a pair (lo, hi) in CELL_PROXY_STEPS-ths of the cell numbered by s = lo + (STEPS - hi), then
// STEPS - hi, from 0 (the whole axis); code 0 is the whole cell (record_cell.glsl, proxyBox).
#define CELL_PROXY_SHIFT 2u
// How far a proxy box is grown beyond the cells it covers (proxy_dilation.glsl): CELL_DILATION_PIXELS
// of a pixel at the cell's depth, at least CELL_MIN_DILATION cells. The host widens the near cells'
// reach by it (cell_draws.cpp): an eye inside a box's dilation sees only the box's back faces.
#define CELL_DILATION_PIXELS 0.02
#define CELL_MIN_DILATION (1.0 / 4096.0)
// The dilation's cells are measured along the object's most shrunk direction: a Hermite cell
// object's ObjectData::material.z (a feature's slot) holds its model matrix's smallest singular
// value, made on the host in double (hsdf::modelScales, cell_draws.cpp), read by objectMinScale
// (proxy_dilation.glsl). A shear's shortest column is no bound on it.
#define CELL_PROXY_STEPS 6u
struct CellRecordGpu {
  vec4 corners[8];
  uint xy;
  uint zc;
};
HSDF_CHECK_SIZE(CellRecordGpu, 8 * 16 + 8);

struct CellRecordHalfGpu {
  uvec2 corners[8];  // binary16 pairs: (f, fx), (fy, fz)
  uint xy;
  uint zc;
};
HSDF_CHECK_SIZE(CellRecordHalfGpu, 8 * 8 + 8);

// Cell runs (RenderMethod::CellRuns): kept cells that follow each other along x in one row, drawn
// as one box; the vertex stream holds one per run (instance rate).
struct CellRunGpu {
  uint xy;           // x of the first cell | y << 16
  uint zLength;      // z | number of cells << 16
  uint firstRecord;  // index of the first cell's record (the others follow it)
};
HSDF_CHECK_SIZE(CellRunGpu, 12);

// Cell bricks: the grid's cells in blocks of CELL_BRICK_SIZE^3; each block with
// at least one kept cell is one proxy box, walked cell by cell along the ray in the fragment shader
// (records read by address). The kept cells of a brick are listed, in the order of their mask bits,
// in a buffer of record indices starting at firstIndex: the record index of kept cell bit b is
// indices[firstIndex + bitCount(mask below b)].
#define CELL_BRICK_SIZE 4u
struct CellBrickGpu {
  uint xyz;         // the brick's coordinate in bricks: x | y << 10 | z << 20
  uint firstIndex;  // first entry of this brick's kept cells in the record-index buffer
  uint maskLo;      // kept cells, bit (x + 4y + 16z) of the brick's 64 cells: bits 0..31
  uint maskHi;      //   bits 32..63
};
HSDF_CHECK_SIZE(CellBrickGpu, 16);

// A brick's normal cone, for culling bricks that cannot hold a first hit (brick_cull.comp): every
// gradient of the interpolant on the brick's kept cells lies within the cone.
struct CellBrickCone {
  vec4 axisCutoff;  // xyz: unit axis (object space); w: cosine bound, see normal_cone.glsl
};
HSDF_CHECK_SIZE(CellBrickCone, 16);

// Per drawn object of the brick culling pass (brick_cull.comp, hsdf::BrickCuller). The matrix and
// the eye come from the CPU, in float, so that the C++ twin (normal_cone.h) tests with the very
// same numbers the GPU does.
struct BrickCullObject {
  mat4 objectToClip;       // viewProj * model
  vec4 gridOriginSpacing;  // xyz: grid origin in object space; w: spacing h
  vec4 eyeConeTest;        // xyz: the eye in object space; w: 1 cone test allowed (normal_cone.h,
                           //   brickConeCullAllowed), 0 frustum test only
  uint firstBrick;         // the object's first brick (and cone) in the input arrays
  uint brickCount;
  uint outputFirst;        // first entry of its range in the output bricks (= its command's firstInstance)
  uint drawCommand;        // index of its VkDrawIndirectCommand; instanceCount counts the kept bricks
  // The model matrix's smallest singular value, the same float as the object's ObjectData::material.z
  // (hsdf::modelScales): the tiles (cell_tiles.comp) grow a cell's screen rectangle by exactly the
  // proxy's dilation.
  float minScale;
  uint pad0;
  uint pad1;
  uint pad2;
};
HSDF_CHECK_SIZE(BrickCullObject, 64 + 2 * 16 + 4 * 4 + 16);

// Totals of one culling pass, for stats (written by atomics; the CPU zeroes them).
struct BrickCullTotals {
  uint tested;
  uint kept;
  uint frustumCulled;
  uint coneCulled;  // inside the frustum, removed by the normal cone
  // Cell culling, per record precision: the kept-cell streams' append cursor. Its final value is
  // the slots the frame's ranges asked for, whether or not the streams held them (the next frames
  // size the streams by it).
  uint keptSlots[2];
  // Cells of ranges that did not fit in the kept streams, drawn unculled by their fallback commands.
  uint fallbackCells;
  uint pad0;
};
HSDF_CHECK_SIZE(BrickCullTotals, 32);

// Push constants of brick_cull.comp: every array by device address.
struct BrickCullPushConstants {
  uint64_t objects;     // BrickCullObject[objectCount]
  uint64_t bricks;      // CellBrickGpu[]: every object's bricks (input)
  uint64_t cones;       // CellBrickCone[], one per input brick
  uint64_t keptBricks;  // CellBrickGpu[]: the kept bricks, in each object's output range
  uint64_t commands;    // VkDrawIndirectCommand[] (4 uints each)
  uint64_t totals;      // BrickCullTotals
  uint objectCount;
  uint pad;
};
HSDF_CHECK_SIZE(BrickCullPushConstants, 6 * 8 + 2 * 4);
HSDF_CHECK_PUSH_CONSTANTS(BrickCullPushConstants);

// Cell culling (RenderMethod::Cells; cell_cull.comp, hsdf::CellCuller): one per front-face command
// of a culled object (a row of cells, drawn in the order the CPU chose; at most
// CELL_CULL_MAX_RANGE_CELLS). The pass tests every cell of the range as brick_cull.comp tests a
// brick and appends the kept ones, in the range's order and together, to the frame slot's kept-cell
// streams; the command's firstInstance and instanceCount become where and how many. A range whose
// kept cells the streams cannot hold any more is drawn whole and unculled by its fallback command.
struct CellCullRange {
  uint firstCell;    // the range's first record (global index in the record buffer)
  uint cellCount;
  // Index of its fallback VkDrawIndirectCommand (firstInstance = firstCell, instanceCount 0 until
  // the pass sets it to cellCount), drawn from the record buffer; ~0u when the frame's streams hold
  // every cell of every range, so that none can overflow.
  uint fallbackCommand;
  uint drawCommand;  // index of its VkDrawIndirectCommand
  uint object;       // its object's BrickCullObject (only the object fields are read, not the brick range)
  // Occlusion culling: the index of the range's first cell in the visibility history (one uint per
  // cell of each drawn object and view region, 1: visible when last tested), the next cells after it.
  uint historyFirst;
  uint pad1;
  uint pad2;
};
HSDF_CHECK_SIZE(CellCullRange, 8 * 4);

// Push constants of cell_cull.comp (one dispatch per record precision), every array by address.
struct CellCullPushConstants {
  uint64_t objects;      // BrickCullObject[]
  uint64_t ranges;       // CellCullRange[rangeCount]
  uint64_t records;      // the precision's record buffer (input), recordWords uints a record
  uint64_t cones;        // CellBrickCone[], one per record (same index in both precisions)
  uint64_t keptRecords;  // output: copies of the kept records (the draws' instance-rate vertex stream)
  uint64_t keptIndices;  // output: uint record index of each kept record (HermitePushConstants::cellRecords)
  uint64_t commands;     // VkDrawIndirectCommand[] (4 uints each)
  uint64_t totals;       // BrickCullTotals (shared with the brick pass; keptSlots[precision] is the append cursor)
  uint64_t keptRanges;   // output where not 0: uint range index of each kept record (the tiling's)
  uint rangeCount;
  uint recordWords;      // 34 (CellRecordGpu) or 18 (CellRecordHalfGpu)
  uint recordPrecision;  // 0: fp32 records, 1: fp16 (BrickCullTotals::keptSlots)
  uint keptCapacity;     // the records the kept streams hold
  // Two-phase occlusion culling (CELL_CULL_PHASE_*): phase 1 keeps the cells visible when last
  // tested, phase 2 tests every cell against the depth pyramid of what phase 1 drew, updates the
  // history and keeps the visible cells phase 1 did not draw, writing the commands
  // commandOffset further on and appending to the same kept streams (each cell is drawn in at
  // most one phase, so the streams never need more than the ranges' cells).
  uint64_t history;      // uint per cell (CellCullRange::historyFirst)
  uint64_t pyramid;      // engine::render::DepthPyramidView: float[], levels concatenated
  uint pyramidExtent;    // level 0 = the frame (the viewport): width | height << 16
  uint pyramidLevels;    // 0: no pyramid, nothing is occluded
  uint phase;
  uint commandOffset;
  // Relative depth margin of the occlusion test: the draws search (and find hits) up to their
  // proxies' dilation beyond the cell (proxy_dilation.glsl), so a box is occluded only when its
  // nearest depth times (1 + depthMargin) is still behind the pyramid.
  float depthMargin;
  // The workgroups: packs of consecutive ranges (CELL_CULL_PACK_CELLS), whose first ranges follow
  // the ranges in their buffer (uint[packCount + 1], the last one rangeCount).
  uint packCount;
};
// At most this many cells in a pack of ranges (one workgroup, a lane per cell); a longer range is
// a pack of its own, walked 64 cells at a time. Rows hold a few cells each at large K and in small
// objects: a workgroup per range left most lanes idle (lavapipe runs them all).
#define CELL_CULL_PACK_CELLS 64u
// At most this many cells in one range: its workgroup claims the range's slots in the kept streams
// before writing them, so it walks the range twice, keeping each lane's verdicts as the bits of
// one uint (32 chunks of 64 cells). The CPU splits longer rows.
#define CELL_CULL_MAX_RANGE_CELLS 2048u
HSDF_CHECK_SIZE(CellCullPushConstants, 11 * 8 + 10 * 4);
HSDF_CHECK_PUSH_CONSTANTS(CellCullPushConstants);
#define CELL_CULL_PHASE_ALL 0u    // no occlusion culling
#define CELL_CULL_PHASE_EARLY 1u
#define CELL_CULL_PHASE_LATE 2u

// Tiled cells (HermiteCellFeature::Settings::tiles; cell_tiles.comp, hsdf::CellTiler): the kept
// cells of the culling pass are binned into CELL_TILE_SIZE^2-pixel screen tiles by the screen
// rectangle of their (dilated) boxes, and the prepass draws one quad per tile that holds a cell,
// whose fragments search every cell of the tile's list that their ray meets (cell_tiles_depth.glsl).
// One fragment per pixel and object group instead of one per box: on lavapipe, which shades (and
// counts) whole 4x4 blocks, a small box costs 16-64 invocations whatever it covers.
#define CELL_TILE_SIZE 8u       // the default side of a tile in pixels (HermiteCellFeature::Settings::tileSize)
#define CELL_TILE_SIZE_MAX 16u  // the largest (the tiles are points of this size where the device has them)
#define CELL_TILES_COUNT 0u    // per kept cell: add 1 to the count of every tile its rectangle touches
#define CELL_TILES_SCAN 1u     // one workgroup: each tile's first entry, the non-empty tile list, the draw
#define CELL_TILES_SCATTER 2u  // per kept cell: write (draw, record, depth) into every tile's list
#define CELL_TILES_SORT 3u     // per non-empty tile: its list nearest first (tiles of at most CELL_TILE_SORT_MAX)
#define CELL_TILES_MASKS 4u    // per non-empty tile: each pixel's masks of the sorted entries that may cover it
#define CELL_TILE_SORT_MAX 1024u
// A sort workgroup takes consecutive non-empty tiles while they are at most this many and their
// compares per lane at most CELL_TILE_SORT_GROUP_WORK (one list of CELL_TILE_SORT_MAX: 16 x 1024).
#define CELL_TILE_SORT_GROUP_TILES 8u
#define CELL_TILE_SORT_GROUP_WORK 16384u
// The tiles' buffer: CellTile[tiles], then the non-empty tiles (uint[tiles]), then the sort
// workgroups' first list indices (uint[tiles]), then the pixel masks
// (uint[cellTileMaskWords]): for each non-empty tile, chunk c of 32 of its sorted entries and pixel
// p of the tile, bit j of word (masks + c * pixels + p) says that entry 32c + j may cover the
// pixel (its CellTileEntry::pixels hold it). A fragment reads its pixel's words and only the
// entries they name, not the whole list. A tile's masks start at word (first / 32 + its place in
// the non-empty list) * pixels, which leaves room for every tile's ceil(count / 32) chunks.
#define CELL_TILE_MASK_BITS 32u
#define CELL_TILE_MASK_GROUP_ROWS 32u  // mask rows (32 entries of one tile each) per workgroup of the masks phase
// The most tiles one cell's rectangle may span (COUNT walks them in one lane): past it the frame
// draws boxes (CellTileTotals::hugeCells). Below lavapipe's 65,535 loop iterations per invocation
// (cell_tiles.comp); a whole 1920x1080 frame of 8x8 tiles (32,400) fits.
#define CELL_TILE_MAX_CELL_TILES 49152u
// The most tiles a frame may have: the one-workgroup scan walks tiles / 64 per lane twice.
#define CELL_TILE_MAX_TILES (1u << 20)
// Where the non-empty tile list and the masks start in the tiles' buffer, in bytes.
#define CELL_TILE_LIST_OFFSET(tiles) (uint64_t(tiles) * 16u)
#define CELL_TILE_SORT_GROUPS_OFFSET(tiles) (uint64_t(tiles) * 20u)  // each sort workgroup's first list index
#define CELL_TILE_MASKS_OFFSET(tiles) (uint64_t(tiles) * 24u)
// The mask words the tiles' buffer holds for `capacity` entries, `tiles` tiles of `pixels` each.
#define CELL_TILE_MASK_WORDS(capacity, tiles, pixels) \
  ((uint64_t(capacity) / CELL_TILE_MASK_BITS + uint64_t(tiles)) * uint64_t(pixels))
struct CellTile {
  uint first;   // its first entry in the entry list
  uint count;   // its entries (0 in every tile where the lists overflowed: CellTileTotals::boxDrawCount)
  // Scatter: entries written so far; from the masks phase on: its first pixel-mask word.
  uint cursor;
  uint depth;   // the nearest (reverse-Z: largest) depth of its cells' boxes, float bits: the quad's depth
};
HSDF_CHECK_SIZE(CellTile, 16);

struct CellTileEntry {
  uint draw;      // HermiteDraw index (the cell's object, grid, search and record buffer)
  uint record;    // the cell's record in that buffer
  float nearest;  // the nearest depth of the cell's box (reverse-Z, a little nearer for the search margin)
  // The pixels of the tile whose centres the cell's screen rectangle holds, tile-local and
  // inclusive: x0 | y0 << 8 | x1 << 16 | y1 << 24 (cellTileEntryCovers). A fragment outside them
  // skips the entry without its ray-box test.
  uint pixels;
};
HSDF_CHECK_SIZE(CellTileEntry, 16);

// The tile draw's indirect command and what the scan found (read back for the next capacity).
struct CellTileTotals {
  uint vertexCount;    // VkDrawIndirectCommand: 1 (a point per tile) or 6 (two triangles)
  uint instanceCount;  //   the non-empty tiles
  uint firstVertex;
  uint firstInstance;
  uint entriesNeeded;  // the entries every tile needed, capacity or not
  uint sortGroups[3];  // VkDispatchIndirectCommand of the sort: a workgroup per few non-empty tiles
  // The lists' overflow: where the tiles needed more entries than the list holds (its capacity,
  // at most HermiteCellFeature::Settings::maxTileEntries), no tile is drawn and this count buffer
  // of vkCmdDrawIndirectCount draws every box command of the culled cells instead (~0u; else 0).
  uint boxDrawCount;
  // VkDispatchIndirectCommand of the masks: one workgroup per CELL_TILE_MASK_GROUP_ROWS mask rows
  // (a workgroup per row costs software rasterizers more than the work it holds).
  uint maskGroups[3];
  // The kept cells whose rectangle spans more than CELL_TILE_MAX_CELL_TILES tiles: any makes the
  // frame draw boxes (boxDrawCount), as an overflow of the lists does.
  uint hugeCells;
  uint sortGroupCount;  // the sort's workgroups (sortGroups' product may exceed it)
};
HSDF_CHECK_SIZE(CellTileTotals, 56);

// Push constants of cell_tiles.comp. COUNT and SCATTER: a lane per slot of the cell culling pass's
// kept stream (one record precision per dispatch), its kept cells read as the draws would read them.
struct CellTilePushConstants {
  uint64_t ranges;        // CellCullRange[rangeCount]
  uint64_t keptRanges;    // range index of each kept instance (CellCullPushConstants::keptRanges)
  uint64_t keptCount;     // uint: the kept streams' append cursor (BrickCullTotals::keptSlots[precision])
  uint64_t keptIndices;   // record index of each kept instance (CellCullPushConstants::keptIndices)
  uint64_t draws;         // the draw table (HermiteDrawTableHeader; a range's drawCommand indexes it)
  uint64_t objects;       // BrickCullObject[] of the culling pass (CellCullRange::object indexes it)
  uint64_t frameGlobals;  // FrameGlobals
  uint64_t tiles;         // CellTile[tilesX * tilesY], the non-empty tiles (uint[tilesX * tilesY]), the masks
  uint64_t entries;       // CellTileEntry[entryCapacity]: the scatter's lists
  uint64_t sortedEntries; // CellTileEntry[entryCapacity]: the same lists sorted (what the draw reads)
  uint64_t totals;        // CellTileTotals
  uint rangeCount;
  uint tilesX;
  uint tilesY;
  uint entryCapacity;
  uint phase;             // CELL_TILES_*
  uint slotCount;         // COUNT, SCATTER: the slots the kept streams hold (cells past them were not kept there)
  uint tileSize;          // the tiles' side in pixels (4, 8 or 16)
  uint pad0;
};
HSDF_CHECK_SIZE(CellTilePushConstants, 11 * 8 + 8 * 4);
HSDF_CHECK_PUSH_CONSTANTS(CellTilePushConstants);

// Per Hermite-cell object, reached through ObjectData::payload: what the shading pass needs to
// find a visible cell's record from the visibility buffer (x: object, y: record index).
struct HermiteObject {
  vec4 gridOriginSpacing;  // xyz: grid origin in object space; w: spacing h
  uint64_t records;        // address of the record buffer this object's cells are in
  uint halfPrecision;      // 0: CellRecordGpu records, 1: CellRecordHalfGpu records
  uint flags;              // HERMITE_FLAG_*
  // A multi-material asset (hermite_sdf/core/materials.h): the address of its records' corner
  // slots (CellMaterialSlotsGpu, one per record from firstRecord on) and of its palette
  // (HermiteMaterialGpu[]); 0 and 0 for an asset of one material, shaded in the object's colour.
  uint64_t materialSlots;
  uint64_t palette;
  uint firstRecord;        // the record index of the asset's first record (materialSlots' entry 0)
  // The object's HermiteDraw in this view region's draw table (HermitePushConstants::draws): the
  // resolve rebuilds each hit from its rayAnchor (cells_resolve.frag). Objects are uploaded per
  // frame slot, one per view region, as the records are.
  uint drawRecord;
};
HSDF_CHECK_SIZE(HermiteObject, 16 + 8 + 2 * 4 + 2 * 8 + 2 * 4);

// One palette entry of a multi-material asset (SdfAsset::palette): what ObjectData's color and
// material hold for an object of one material. The shading multiplies the object's colour by
// `color` and takes the roughness from material.x (hermite/materials.glsl).
struct HermiteMaterialGpu {
  vec4 color;     // linear base colour, a: alpha (unused)
  vec4 material;  // x: roughness, y: metallic, zw: 0
};
HSDF_CHECK_SIZE(HermiteMaterialGpu, 2 * 16);

// The material slots of one record's 8 corners, one byte each, corner c in byte c % 4 of word c / 4
// (CellMaterialSlots, little-endian).
struct CellMaterialSlotsGpu {
  uint corners0123;
  uint corners4567;
};
HSDF_CHECK_SIZE(CellMaterialSlotsGpu, 2 * 4);

// The sphere tracers' materials of a multi-material asset, reached through ObjectData::payload
// (0: one material): this header, then paletteSize HermiteMaterialGpu entries, then, at byte
// slotsOffset of the block, one slot byte per dense sample (sample i in byte i % 4 of word i / 4),
// padded to whole words.
struct FieldMaterialsHeader {
  uint paletteSize;
  uint slotsOffset;
  uint pad0;
  uint pad1;
};
HSDF_CHECK_SIZE(FieldMaterialsHeader, 16);

// Feature ids in ObjectData::feature (engine features use small numbers; see their headers).
#define HERMITE_CELLS_FEATURE_ID 2u

// Push constants of the Hermite pipelines: the engine's DrawPushConstants plus the draw table.
struct HermitePushConstants {
  DrawPushConstants draw;
  uint64_t draws;          // address of the draw table (HermiteDrawTableHeader), indexed by drawBase + gl_DrawID
  uint64_t hitDepths;      // address of a uint per pixel: the cells' nearest hit depth (hit_depth.glsl), 0 when unused
  uint64_t counters;       // address of a uint per pixel (evaluation heat map), 0 when off
  // Cell bricks: the CellBrickGpu[] the draws' instances index (the bound vertex buffer; the
  // fragment shader reads its brick there), and the uint record indices of the bricks' kept cells.
  uint64_t bricks;
  uint64_t brickCells;
  // Culled cells (CellCullPushConstants::keptIndices): the record index of each instance of the
  // kept-cell stream the draws read; 0 when the instances are the records themselves.
  uint64_t cellRecords;
  // Tiled cells: CellTile[], the non-empty tile list and the pixel masks (CellTilePushConstants::tiles),
  // and the tiles' sorted CellTileEntry[].
  uint64_t tiles;
  uint64_t tileEntries;
  uint drawBase;
  uint tileSize;           // tiled cells: the tiles' side in pixels (CellTilePushConstants::tileSize)
  // Shading pass: the rectangle (NDC x0, y0, x1, y1) that covers every drawn cell object on screen;
  // the resolve shades only its pixels (cells_resolve.vert).
  vec4 screenRect;
  // The frame's WorkTotals (FrameContext::workTotals) in frames that count work, else 0.
  uint64_t workTotals;
};
// 128 bytes: every Vulkan device's least maxPushConstantsSize.
HSDF_CHECK_SIZE(HermitePushConstants, 32 + 8 * 8 + 8 + 16 + 8);
HSDF_CHECK_PUSH_CONSTANTS(HermitePushConstants);

// ---- Sphere-tracing baselines (hsdf::SphereTraceFeature) ----------------------------------------
#define SPHERE_TRACE_FEATURE_ID 3u
// The prepass's visibility is (1 + object, field evaluations | this bit when the pixel's ray started
// inside the surface): the shading pass lights the hit as the side the ray came from without
// evaluating the field again.
#define SPHERE_TRACE_STARTED_INSIDE 0x80000000u
// The largest dense grid the tracers draw: the march keys its cell as one int, x + K (y + K z)
// (fieldCellKey), below 2^31 while K^3 is. Far past any field a dense texture holds in practice
// (K = 1290 is 2.1e9 samples, 34 GB of Hermite texels), but refused by name rather than wrapped.
#define SPHERE_TRACE_MAX_RESOLUTION 1290u

// One per drawn object of the sphere-tracing feature, indexed by gl_InstanceIndex. The field is a
// dense 3D texture of K^3 samples; "grid units" are object-space lengths divided by h, so sample
// (i,j,k) lies at grid position (i,j,k) and the trilinear texture coordinate of grid position g is
// (g + 0.5) / K.
struct SphereTraceDraw {
  vec4 gridOriginSpacing;  // xyz: grid origin in object space; w: spacing h
  // Where this view's rays are based (pixel_ray.glsl), as HermiteDraw::rayAnchor: made per object
  // and view region on the host in double (render/ray_anchor.h), xyz in grid units, w its view
  // depth (0: the rays start at the eye). From the eye a far camera's rays start a float ~1e7
  // cells out, ~0.5 cell off in every axis, and march and shade from there.
  vec4 rayAnchor;
  uint object;             // index into ObjectData[]
  uint resolution;         // K samples per axis
  uint flags;              // HERMITE_FLAG_NORMALS_CENTRAL
  uint texture;            // slot in the bindless texture table (unused with per-object sets)
  uint maxSteps;           // sphere-tracing step limit
  float epsilon;           // stop when |f| < epsilon * h (epsilon in grid units)
  float centralStep;       // central-difference offset, grid units
  uint filterBits;         // trilinear: 0 = the hardware filter; b > 0 = filtered in the shader with
                           // weights rounded to b fractional bits, as GPU filter units do (tests
                           // reproduce a GPU's quantized filter on lavapipe, which filters in float)
  float exactBelow;        // trilinear: |f| (grid units) below which a step evaluates the exact
                           // interpolant instead of the filter (SphereTraceFeature::exactBelowCells)
  uint pad0;
  uint pad1;
  uint pad2;
};
HSDF_CHECK_SIZE(SphereTraceDraw, 2 * 16 + 12 * 4);

// Push constants of the sphere-tracing pipelines.
struct SphereTracePushConstants {
  DrawPushConstants draw;
  uint64_t draws;          // address of SphereTraceDraw[]
  uint64_t counters;       // address of a uint per pixel (renderer work counters), 0 when off
  uint64_t workTotals;     // address of the frame's WorkTotals, 0 when off
};
HSDF_CHECK_SIZE(SphereTracePushConstants, 32 + 3 * 8);
HSDF_CHECK_PUSH_CONSTANTS(SphereTracePushConstants);

#ifdef __cplusplus
}  // namespace shader
#else
// The GLSL views of the buffers above that several shaders read, declared once here.
layout(buffer_reference, scalar) readonly buffer HermiteDrawsRef { HermiteDraw draws[]; };
layout(buffer_reference, scalar) readonly buffer HermiteDrawTableRef {
  HermiteDrawTableHeader header;
  uint recordOf[];
};
// The record of indirect command `command` in the draw table at `table` (the box vertex shaders
// hand it to their fragments, which then read the record with one load, as before the table).
uint hermiteDrawRecord(uint64_t table, uint command) { return HermiteDrawTableRef(table).recordOf[command]; }
HermiteDraw hermiteDrawAt(uint64_t table, uint record) {
  return HermiteDrawsRef(HermiteDrawTableRef(table).header.records).draws[record];
}
// The HermiteDraw of indirect command `command`.
HermiteDraw hermiteDraw(uint64_t table, uint command) { return hermiteDrawAt(table, hermiteDrawRecord(table, command)); }
layout(buffer_reference, scalar) readonly buffer SphereTraceDrawsRef { SphereTraceDraw draws[]; };
layout(buffer_reference, scalar) readonly buffer CellRecordsRef { CellRecordGpu records[]; };
layout(buffer_reference, scalar) readonly buffer CellRecordsHalfRef { CellRecordHalfGpu records[]; };
layout(buffer_reference, scalar) readonly buffer CullObjectsRef { BrickCullObject objects[]; };
layout(buffer_reference, scalar) readonly buffer ConesRef { CellBrickCone cones[]; };
layout(buffer_reference, scalar) readonly buffer PaletteRef { HermiteMaterialGpu entries[]; };
layout(buffer_reference, scalar) readonly buffer CellMaterialSlotsRef { CellMaterialSlotsGpu records[]; };
layout(buffer_reference, scalar) readonly buffer FieldMaterialsRef {
  FieldMaterialsHeader header;
  HermiteMaterialGpu palette[];
};
layout(buffer_reference, scalar) readonly buffer SlotWordsRef { uint words[]; };
#endif

#endif
