// GPU structs shared by C++ and GLSL: the one place where their layouts are declared.
// Buffers are reached by buffer device address and use the scalar block layout, which matches
// C++'s natural alignment of these members; the static_asserts pin every size.
#ifndef HSDF_HOST_DEVICE_H
#define HSDF_HOST_DEVICE_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace shader {
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using uvec2 = glm::uvec2;
using uvec4 = glm::uvec4;
using mat4 = glm::mat4;
using uint = std::uint32_t;
using uint64_t = std::uint64_t;
#define HSDF_CHECK_SIZE(type, bytes) static_assert(sizeof(type) == (bytes), #type " layout changed")
// Push constants fit the 128 bytes every Vulkan device offers (the least maxPushConstantsSize the
// specification allows): no device is asked for more.
#define HSDF_CHECK_PUSH_CONSTANTS(type) \
  static_assert(sizeof(type) <= 128, #type " is larger than the 128 bytes of push constants every device has")
#else
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#define HSDF_CHECK_SIZE(type, bytes)
#define HSDF_CHECK_PUSH_CONSTANTS(type)
#endif

// Debug views (DrawPushConstants::debugView); the same numbers in the UI and on the command line.
#define DEBUG_VIEW_NONE 0
#define DEBUG_VIEW_NORMALS 1
#define DEBUG_VIEW_DEPTH 2
#define DEBUG_VIEW_CELLS 3
#define DEBUG_VIEW_EVALS 4
#define DEBUG_VIEW_WIREFRAME 5  // shaded, with the boxes of drawn cells outlined
#ifdef __cplusplus
// Their names, indexed by value (the samples' --debug-view, settings files and scripts): a view added
// above gets its name here, the one other place it is spelled.
inline constexpr const char* kDebugViewNames[] = {"none", "normals", "depth", "cells", "evals", "wireframe"};
static_assert(sizeof(kDebugViewNames) / sizeof(kDebugViewNames[0]) == DEBUG_VIEW_WIREFRAME + 1,
              "a name per DEBUG_VIEW_*");
#endif

// Per frame: camera and light. One record per frame in flight.
struct FrameGlobals {
  mat4 view;
  mat4 proj;              // reverse-Z infinite perspective (depth = znear / view distance)
  mat4 viewProj;
  mat4 invView;
  mat4 invProj;
  vec4 cameraPosition;    // the homogeneous eye (CameraView::eye). Perspective, w = 1: xyz is the eye
                          // in the frame's world space, which is shifted so that the eye lies near
                          // its origin (camera-relative: world - GpuScene::origin()). Orthographic,
                          // w = 0: xyz is the unit direction towards the viewer. The ray leaving a
                          // point p towards the viewer: xyz - p * w (lighting.glsl towardViewer)
  vec4 lightDirection;    // xyz: unit vector towards the light; w: intensity
  vec4 lightColor;        // rgb; a: ambient intensity
  vec4 viewport;          // width, height, 1/width, 1/height
};
HSDF_CHECK_SIZE(FrameGlobals, 5 * 64 + 4 * 16);

// The bindings of a mesh material's descriptor set (set 0 of the mesh pipelines; engine::render::
// MeshTextures), one texture kind each (glTF's material textures, read through TEXCOORD_0).
#define MESH_TEXTURE_BASE_COLOR 0          // sRGB: rgba times ObjectData::color
#define MESH_TEXTURE_METALLIC_ROUGHNESS 1  // linear: g times the roughness, b times the metallic
#define MESH_TEXTURE_OCCLUSION 2           // linear: r, the ambient light reaching the surface
#define MESH_TEXTURE_EMISSIVE 3            // sRGB: rgb times ObjectData::emission
#define MESH_TEXTURE_NORMAL 4              // linear: the normal in the tangent frame, xy times emission.a
#define MESH_TEXTURE_COUNT 5

// ObjectData::flags.
#define OBJECT_FLAG_MIRRORED 1u  // the model matrix has a negative determinant: it reverses winding

// Per object, in the GPU scene buffer; drawn instances find theirs by index.
struct ObjectData {
  mat4 model;
  mat4 invModel;          // normals use transpose(mat3(invModel))
  vec4 color;             // base colour (linear); a: its alpha (glTF baseColorFactor), read by
                          // meshes with alphaMode MASK or BLEND
  vec4 material;          // x: roughness, y: metallic, zw: feature-specific (meshes: z alpha cutoff,
                          // w occlusion strength)
  uint64_t payload;       // feature-specific data reached by device address (0: none)
  uint feature;           // which RenderFeature owns the object (for debugging)
  uint flags;             // OBJECT_FLAG_*
  vec4 emission;          // rgb: linear light the surface gives off, added to its lit colour; a: meshes'
                          // normal texture scale (0: none read)
};
HSDF_CHECK_SIZE(ObjectData, 2 * 64 + 3 * 16 + 8 + 2 * 4);

// Push constants of every scene draw: where this frame's globals and objects live.
struct DrawPushConstants {
  uint64_t frameGlobals;  // address of FrameGlobals
  uint64_t objects;       // address of ObjectData[]
  uint debugView;         // DEBUG_VIEW_*
  uint flags;
  uint pad0;
  uint pad1;
};
HSDF_CHECK_SIZE(DrawPushConstants, 32);
HSDF_CHECK_PUSH_CONSTANTS(DrawPushConstants);

// Frame-wide work totals of a counting frame (FrameSettings::countWork), in the work-counter buffer
// right after its one uint per pixel: what a feature gave up on, counted so that it is never
// silently dropped.
struct WorkTotals {
  uint raysOutOfSteps;     // sphere-tracing rays that reached the step limit (drawn as misses)
  // Tiled cells (cell_tiles_depth.glsl), summed over the prepass fragments: the tile-list entries
  // they read, and those that got the ray-box test. The walk
  // over the lists is the tiles' per-fragment cost beside the root search (the evaluations).
  uint tileEntriesWalked;
  uint tileEntriesTested;
  uint tileMaskWordsRead;  // the words of their pixel's masks they read (CELL_TILES_MASKS)
};
HSDF_CHECK_SIZE(WorkTotals, 16);

// Push constants of depth_pyramid.comp (engine::render::DepthPyramid): one level of the pyramid
// from the one before it, both in the same buffer (levels concatenated, level 0 = the frame's
// depth), each texel the FARTHEST depth (reverse-Z: the minimum) of the up to 2x2 texels below it.
struct DepthPyramidPushConstants {
  uint64_t pyramid;  // address of float[]: every level, row-major, level 0 first
  uint srcOffset;    // first float of the source level
  uint dstOffset;    // first float of the level written
  uint srcWidth;
  uint srcHeight;
  uint dstWidth;
  uint dstHeight;
};
HSDF_CHECK_SIZE(DepthPyramidPushConstants, 8 + 6 * 4);
HSDF_CHECK_PUSH_CONSTANTS(DepthPyramidPushConstants);

#ifdef __cplusplus
}  // namespace shader
#else
layout(buffer_reference, scalar) readonly buffer FrameGlobalsRef { FrameGlobals globals; };
layout(buffer_reference, scalar) readonly buffer ObjectsRef { ObjectData objects[]; };
#endif

#endif  // HSDF_HOST_DEVICE_H
