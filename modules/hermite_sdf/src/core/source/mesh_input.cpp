#include "source/mesh_input.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include <fmt/format.h>

namespace hsdf::mesh {
namespace {

// Relative to its longest edge, a triangle whose height is below this has no usable area: it is
// collinear up to the rounding of its float coordinates.
constexpr double kZeroAreaRelativeHeight = 1e-12;

bool isFinite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

engine::Status checkShape(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& indices) {
  if (indices.empty()) return engine::makeError("mesh has no triangles (empty index list)");
  if (indices.size() % 3 != 0)
    return engine::makeError(fmt::format("mesh index count {} is not a multiple of 3", indices.size()));
  for (std::size_t i = 0; i < indices.size(); ++i) {
    if (indices[i] >= positions.size())
      return engine::makeError(fmt::format("triangle {} uses vertex {} but the mesh has {} vertices", i / 3,
                                           indices[i], positions.size()));
  }
  for (std::size_t v = 0; v < positions.size(); ++v) {
    if (!isFinite(positions[v]))
      return engine::makeError(fmt::format("vertex {} has a non-finite coordinate ({}, {}, {})", v,
                                           positions[v].x, positions[v].y, positions[v].z));
  }
  return {};
}

bool hasZeroArea(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const double longest2 = std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
  const glm::dvec3 n = glm::cross(b - a, c - a);
  // |n| = 2*area = longest edge * height.
  return glm::dot(n, n) <= kZeroAreaRelativeHeight * kZeroAreaRelativeHeight * longest2 * longest2;
}

struct PositionHash {
  std::size_t operator()(const glm::dvec3& p) const {
    const std::hash<double> h;
    return h(p.x) ^ (h(p.y) * 0x9e3779b97f4a7c15ULL) ^ (h(p.z) * 0xc2b2ae3d27d4eb4fULL);
  }
};

}  // namespace

engine::Expected<CleanTriangles> cleanTriangles(const std::vector<glm::vec3>& positions,
                                                const std::vector<std::uint32_t>& indices) {
  ENGINE_TRY(checkShape(positions, indices));
  CleanTriangles clean;
  const std::size_t count = indices.size() / 3;
  clean.corners.reserve(indices.size());
  clean.inputTriangle.reserve(count);
  for (std::size_t t = 0; t < count; ++t) {
    const glm::dvec3 a(positions[indices[3 * t]]);
    const glm::dvec3 b(positions[indices[3 * t + 1]]);
    const glm::dvec3 c(positions[indices[3 * t + 2]]);
    if (hasZeroArea(a, b, c)) {
      ++clean.droppedZeroArea;
      continue;
    }
    clean.corners.insert(clean.corners.end(), {a, b, c});
    clean.inputTriangle.push_back(std::uint32_t(t));
  }
  if (clean.inputTriangle.empty())
    return engine::makeError(fmt::format("all {} triangles of the mesh have zero area", count));
  return clean;
}

std::vector<std::uint32_t> weldVertices(const std::vector<glm::dvec3>& corners) {
  std::unordered_map<glm::dvec3, std::uint32_t, PositionHash> welded;
  std::vector<std::uint32_t> vertexOf(corners.size());
  for (std::size_t i = 0; i < corners.size(); ++i)
    vertexOf[i] = welded.emplace(corners[i], std::uint32_t(welded.size())).first->second;
  return vertexOf;
}

EdgeTopology edgeTopology(const std::vector<std::uint32_t>& vertexOf) {
  auto key = [](std::uint32_t from, std::uint32_t to) { return (std::uint64_t(from) << 32) | to; };
  std::unordered_map<std::uint64_t, int> directedEdges;
  for (std::size_t t = 0; t < vertexOf.size() / 3; ++t) {
    for (std::size_t e = 0; e < 3; ++e)
      ++directedEdges[key(vertexOf[3 * t + e], vertexOf[3 * t + (e + 1) % 3])];
  }
  EdgeTopology topology;
  for (const auto& [edge, count] : directedEdges) {
    const auto twin = directedEdges.find(key(std::uint32_t(edge & 0xffffffffu), std::uint32_t(edge >> 32)));
    const bool paired = count == 1 && twin != directedEdges.end() && twin->second == 1;
    if (!paired) topology.boundaryEdges += std::size_t(count);
  }
  topology.closed = topology.boundaryEdges == 0;
  return topology;
}

}  // namespace hsdf::mesh
