#pragma once
// glTF 2.0 schema ranges, checked on the document's JSON before tinygltf parses it (gltf_document.cpp).
//
// Why the JSON and not tinygltf's Model: tinygltf 2.7 drops or rewrites many out-of-range values
// without a word, so its Model no longer shows what the file said and a check there would pass a
// broken file:
//  - unsigned fields it does not require (accessor and bufferView byteOffset, byteStride) are read
//    only when the JSON holds a non-negative integer; -4 or 4.0 is skipped as if absent, i.e. 0;
//  - int fields (every index: node.mesh, children, primitive indices and attributes, sparse count
//    and offsets, mode) are cast from 64 bits, so 4294967296 becomes 0;
//  - an unknown bufferView target becomes 0, a `matrix` holding a non-number is dropped (and the
//    TRS used instead), non-numbers in min/max are dropped;
//  - it accepts count 0, byteLength 0, byteStride 0, componentType 5124 (INT) and 5130 (DOUBLE),
//    any mode, any normalized component type, any length of min/max/rotation/scale/translation.
// It does refuse a few cases itself (byteStride above 252 or not a multiple of 4, a negative
// required count or byteLength, an unknown accessor type), but checking here first gives every
// field the same kind of message.
#include <nlohmann/json_fwd.hpp>

#include "engine/core/expected.h"

namespace engine::scene {

// Every field the loader reads from accessors (with their sparse parts), bufferViews, buffers,
// meshes and their primitives, nodes, scenes, the top-level `scene` and the material factors,
// against the glTF 2.0 JSON schema: integer or number, minimum/maximum, enums, array lengths,
// unique lists; every index against the size of the array it points into; and the rules the
// specification states beside the schema for the same fields (accessor offsets aligned to the
// component size, min/max with one entry per component, normalized only on 8/16-bit integers, a
// sparse count no larger than its accessor's).
// Returns the first violation, naming the field by its JSON path and the rule, e.g.
//   "accessors[3].byteOffset: -4 is negative (schema: minimum 0)".
// Objects the loader never reads (images, textures, samplers, skins, animations, camera
// parameters beyond what the loader checks itself) are not examined.
Status checkGltfSchema(const nlohmann::json& document);

}  // namespace engine::scene
