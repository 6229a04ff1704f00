#pragma once
// Tangents for a normal texture when a file gives none. glTF: "When tangents are not specified,
// client implementations SHOULD calculate tangents using default MikkTSpace algorithms with the
// specified vertex positions, normals, and texture coordinates". This is our own version of that
// scheme's core (no MikkTSpace source): each triangle's texture-space directions, projected into
// every corner's tangent plane and weighted by the corner's angle, summed per vertex; the
// handedness from the summed bitangent. Bakers that use MikkTSpace split vertices where the
// handedness flips; a glTF file's vertices are already split at UV seams, so this does not.
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "engine/core/expected.h"
#include "engine/scene/scene_data.h"

namespace engine::scene {

// One tangent per position (xyz toward +u in the normal's plane, w = +-1 with bitangent =
// cross(normal, xyz) * w toward -v: glTF's v runs down the image, its normal maps' green up), from `primitive`'s positions, normals, texcoords and triangles.
// Refused, naming why, where a used vertex has no texture direction (every triangle around it has
// texcoords of zero area or a zero-area corner): the caller keeps the derivative frame there.
Expected<std::vector<glm::vec4>> generateTangents(const MeshPrimitiveData& primitive);

}  // namespace engine::scene
