#pragma once
// glTF 2.0 import (.gltf with external or data: buffers, and .glb) into plain CPU scene data.
//
// The importer treats every file as untrusted: every numeric field it reads is first checked against
// the glTF 2.0 schema's ranges (gltf_validate.h), then each index, offset, stride and count is
// checked against the data before a byte is read, and the node hierarchy for cycles and shared
// children. A malformed file yields an error naming the file and the problem, e.g.
//   "bad.gltf: accessors[2].byteOffset: -4 is negative (schema: minimum 0)"
//   "bad.gltf: mesh 0 'Cube' primitive 0: POSITION: accessor 2: count 9 with stride 12 runs past the end of bufferView 0 ..."
// It never crashes, hangs or allocates in proportion to a count it has not checked against the data.
//
// What is imported (for GltfLoadOptions::scene, else the default scene, else scene 0, else every
// root node when there are no scenes; nodes outside that scene are dropped; a file with several
// scenes gets a warning naming the one loaded):
//  - meshes: TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN primitives as triangle lists; POSITION is
//    required, NORMAL is optional (smooth area-weighted normals are generated when absent), indices
//    are optional (0..n-1 when absent) and may be of any glTF index type. Points and lines, and
//    strips or fans of fewer than 3 vertices, are skipped with a warning. Vertex attributes may be
//    float or normalized/integer (KHR_mesh_quantization); accessors may be sparse, and an accessor
//    without a bufferView is zeros (plus its sparse values), as glTF defines it. Morph targets
//    are applied with the mesh's default `weights` (POSITION and NORMAL offsets; a count unlike the
//    targets' is an error); a node's own `weights`, a Draco primitive's targets and skins are not
//    applied (a warning each: a skinned mesh is drawn in its file pose, placed by its node).
//  - compression: KHR_draco_mesh_compression primitives (libdraco) and EXT_meshopt_compression
//    bufferViews (libmeshoptimizer, every mode and filter) are decoded; decoded counts must match
//    the accessors, and decoded bytes count against the same budget as other decoded geometry. A
//    Draco primitive's NORMAL or TEXCOORD_0 that its extension's `attributes` do not name is read
//    from its accessor, as the extension has it.
//  - extensions: a required extension other than those three and the ones that only concern
//    materials, textures and lights (KHR_materials_*, KHR_texture_*, EXT_texture_*,
//    KHR_lights_punctual, ...) is an error naming it; used extensions that are ignored get a
//    warning each.
//  - materials: pbrMetallicRoughness baseColorFactor, metallicFactor, roughnessFactor; doubleSided;
//    emissiveFactor times KHR_materials_emissive_strength's emissiveStrength; alphaMode (MASK: its
//    alphaCutoff; BLEND: MaterialData::alphaBlend, the alpha being the factor's times the
//    texture's); baseColorTexture, metallicRoughnessTexture, occlusionTexture (and its strength)
//    and emissiveTexture read through TEXCOORD_0 (gltf_textures.h: PNG or JPEG from a bufferView,
//    a data: URI or a file beside the .gltf, at most kMaxTextureSide texels a side, with its
//    sampler), and normalTexture (and its scale) in the primitive's TANGENT frame (made at load
//    when the file has none: engine/scene/tangents.h), else in a frame from screen-space
//    derivatives; one KHR_texture_transform per material, its first texture's. A
//    texture that cannot be read (bad index, undecodable or missing image, too large, texCoord
//    other than 0, a transform unlike the material's first, a primitive without TEXCOORD_0) is a
//    warning naming the material: drawn without it (in its factor).
//  - TANGENT: VEC4 (w the handedness), one per position, on a primitive with NORMAL; another
//    type or count is dropped with a warning, as is a Draco primitive's (not decoded); then made
//    from the texcoords if a normal texture reads them.
//  - cameras: perspective (yfov, znear; zfar and aspectRatio kept but the projection is infinite and
//    the viewport's aspect wins) and orthographic (xmag, ymag, znear, zfar: xmag and ymag positive,
//    zfar > znear >= 0; a bad value is an error naming the camera and the field); another type is
//    refused by the parser.
//  - nodes: local matrix (from `matrix` or translation/rotation/scale; `matrix` wins when a node
//    has both, which glTF forbids) and world matrix. A `matrix` that shears or projects (glTF
//    forbids both) is replaced by its translation, rotation and scale with a warning, so that the
//    triangles (entities hold TRS transforms) and the baked SDF place the node alike.
// Only the images of textures that a material reads are decoded. A file without meshes is valid and
// gives a SceneData with empty meshes.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>

#include "engine/core/expected.h"
#include "engine/scene/scene_data.h"

namespace engine::scene {

struct GltfLoadOptions {
  // Files (the .gltf/.glb and each external buffer) larger than this are refused before reading.
  std::uint64_t maxFileBytes = std::uint64_t(1) << 30;
  // The scene to load; -1: the file's default scene, else scene 0. Out of range is an error.
  int scene = -1;
};

// Loads a .gltf or .glb file (told apart by content, not by extension). External buffer URIs are
// resolved relative to the file's folder; a missing one, or one that climbs out of the folder with
// "..", is an error.
Expected<SceneData> loadGltf(const std::filesystem::path& path, const GltfLoadOptions& options = {});

// Loads glTF JSON or GLB bytes. `nameForErrors` prefixes every error and warning. External buffer
// URIs are resolved relative to `baseDir`; with an empty `baseDir` external files are not allowed
// (only data: URIs and the GLB BIN chunk), which is what a caller holding untrusted bytes wants.
Expected<SceneData> loadGltfFromMemory(std::span<const std::uint8_t> bytes,
                                       std::string_view nameForErrors,
                                       const std::filesystem::path& baseDir,
                                       const GltfLoadOptions& options = {});

// Flattening copies each mesh once per node that places it, so a small file can ask for any number
// of vertices; callers holding untrusted scenes check this first. The default limit is far above
// any mesh worth baking (2^26 vertices: 0.8 GB of positions before indices).
inline constexpr std::uint64_t kMaxFlattenedVertices = std::uint64_t(1) << 26;
Status checkFlattenable(const SceneData& scene, std::uint64_t maxVertices = kMaxFlattenedVertices);

// World-space positions and triangle indices of every mesh instance (node with a mesh) in `scene`.
// Instances whose world matrix mirrors (negative determinant) get their triangles re-wound so that
// every triangle stays counter-clockwise seen from outside. Instances that would push the vertex
// count past 2^32-1 are left out with an error in the log. Each triangle's node is in triangleNodes.
// `origin` is subtracted from every position in double before it is rounded to float: a scene far
// from the world origin (1e6 units away, where float holds 0.06) keeps its shape about it.
TriangleSoup flattenTriangles(const SceneData& scene, const glm::dvec3& origin = glm::dvec3(0.0));

}  // namespace engine::scene
