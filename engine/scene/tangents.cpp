#include "engine/scene/tangents.h"

#include <array>
#include <cmath>
#include <cstddef>

#include <fmt/format.h>

namespace engine::scene {

namespace {

// `v` with its component along the unit `n` removed.
glm::vec3 inPlane(glm::vec3 v, glm::vec3 n) { return v - n * glm::dot(n, v); }

glm::vec3 normalizedOrZero(glm::vec3 v) {
  const float length = glm::length(v);
  return length > 0.0f && std::isfinite(length) ? v / length : glm::vec3(0.0f);
}

// The angle of the triangle's corner at `p` between the edges to `a` and `b`.
float cornerAngle(glm::vec3 p, glm::vec3 a, glm::vec3 b) {
  const glm::vec3 u = normalizedOrZero(a - p);
  const glm::vec3 v = normalizedOrZero(b - p);
  return std::acos(glm::clamp(glm::dot(u, v), -1.0f, 1.0f));
}

struct Sums {
  std::vector<glm::vec3> tangent;
  std::vector<glm::vec3> bitangent;
};

// Adds one triangle's directions of +u and +v (dP/du, dP/dv) to its three corners. A triangle
// whose texcoords span no area has no such directions and adds nothing.
void addTriangle(const MeshPrimitiveData& p, std::array<std::uint32_t, 3> v, Sums& sums) {
  const glm::vec3 e1 = p.positions[v[1]] - p.positions[v[0]];
  const glm::vec3 e2 = p.positions[v[2]] - p.positions[v[0]];
  const glm::vec2 d1 = p.texcoords[v[1]] - p.texcoords[v[0]];
  const glm::vec2 d2 = p.texcoords[v[2]] - p.texcoords[v[0]];
  const float det = d1.x * d2.y - d2.x * d1.y;
  if (!(std::abs(det) > 0.0f) || !std::isfinite(det)) return;
  const glm::vec3 dPdu = (e1 * d2.y - e2 * d1.y) / det;
  const glm::vec3 dPdv = (e2 * d1.x - e1 * d2.x) / det;
  for (int c = 0; c < 3; ++c) {
    const std::uint32_t i = v[std::size_t(c)];
    const glm::vec3 n = p.normals[i];
    const float angle = cornerAngle(p.positions[i], p.positions[v[std::size_t((c + 1) % 3)]],
                                    p.positions[v[std::size_t((c + 2) % 3)]]);
    sums.tangent[i] += angle * normalizedOrZero(inPlane(dPdu, n));
    sums.bitangent[i] += angle * normalizedOrZero(inPlane(dPdv, n));
  }
}

}  // namespace

Expected<std::vector<glm::vec4>> generateTangents(const MeshPrimitiveData& primitive) {
  const std::size_t count = primitive.positions.size();
  if (primitive.texcoords.size() != count || primitive.normals.size() != count)
    return makeError(fmt::format("{} texcoords and {} normals for {} positions", primitive.texcoords.size(),
                                 primitive.normals.size(), count));
  Sums sums{std::vector<glm::vec3>(count, glm::vec3(0.0f)), std::vector<glm::vec3>(count, glm::vec3(0.0f))};
  std::vector<bool> used(count, false);
  for (std::size_t t = 0; t + 2 < primitive.indices.size(); t += 3) {
    const std::array<std::uint32_t, 3> v{primitive.indices[t], primitive.indices[t + 1], primitive.indices[t + 2]};
    if (v[0] >= count || v[1] >= count || v[2] >= count) return makeError(fmt::format("triangle {}: index out of range", t / 3));
    for (const std::uint32_t i : v) used[i] = true;
    addTriangle(primitive, v, sums);
  }
  std::vector<glm::vec4> tangents(count, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));  // unused vertices: any frame
  std::size_t without = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (!used[i]) continue;
    const glm::vec3 n = primitive.normals[i];
    const glm::vec3 t = normalizedOrZero(inPlane(sums.tangent[i], n));
    if (t == glm::vec3(0.0f)) {
      ++without;
      continue;
    }
    // glTF's bitangent, cross(n, t) * w, points toward -v (its v runs down the image, its normal
    // maps' green up): w = 1 where -v lies on the side of cross(n, t), -1 where the texture is mirrored.
    const float w = glm::dot(glm::cross(n, t), sums.bitangent[i]) > 0.0f ? -1.0f : 1.0f;
    tangents[i] = glm::vec4(t, w);
  }
  if (without > 0)
    return makeError(fmt::format("{} of {} vertices have no texture direction (texcoords of zero area around them)",
                                 without, count));
  return tangents;
}

}  // namespace engine::scene
