#include "source/mesh_input.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <unordered_map>

#include <fmt/format.h>
#include <glm/ext/vector_int3_sized.hpp>

namespace hsdf::mesh {
namespace {

// Relative to its longest edge, a triangle whose height is below this has no usable area: it is
// collinear up to the rounding of its float coordinates.
constexpr double kZeroAreaRelativeHeight = 1e-12;
// Positions closer than this many float ulps of the mesh's size (its bounding box's longest side)
// are one vertex: generators that compute a seam or a pole twice with trigonometry (sin 2 pi =
// -2.4e-16, as three.js's do) leave copies a rounding apart, which made a closed sphere open and
// exposed it to the rules for open meshes. Vertices of a real mesh lie far farther apart (a
// million-triangle scan: about 1e-3 of its size; 4 float ulps are 4.8e-7 of it).
constexpr double kWeldUlps = 4.0;

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

std::optional<std::vector<std::uint32_t>> weldBoundaryWithinRounding(const std::vector<glm::dvec3>& corners,
                                                                     const std::vector<std::uint32_t>& vertexOf,
                                                                     const std::vector<std::uint32_t>& boundaryVertices) {
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  std::unordered_map<std::uint32_t, glm::dvec3> position;  // of each boundary vertex
  for (const std::uint32_t v : boundaryVertices) position.emplace(v, glm::dvec3(0.0));
  for (std::size_t i = 0; i < corners.size(); ++i) {
    lo = glm::min(lo, corners[i]);
    hi = glm::max(hi, corners[i]);
    if (const auto found = position.find(vertexOf[i]); found != position.end()) found->second = corners[i];
  }
  const glm::dvec3 size = hi - lo;
  const double tolerance = kWeldUlps * double(std::numeric_limits<float>::epsilon()) * std::max({size.x, size.y, size.z});
  if (!(tolerance > 0.0)) return std::nullopt;

  // Each boundary vertex joins the first (in the order given) within reach, found among the 27
  // grid cells of the tolerance's size around it: deterministic, and only the few vertices of
  // unpaired edges are hashed (a closed mesh never gets here).
  struct CellHash {
    std::size_t operator()(const glm::i64vec3& c) const {
      return std::size_t(c.x) * 0x9e3779b97f4a7c15ULL ^ std::size_t(c.y) * 0xc2b2ae3d27d4eb4fULL ^ std::size_t(c.z);
    }
  };
  std::unordered_map<glm::i64vec3, std::vector<std::uint32_t>, CellHash> cells;
  std::unordered_map<std::uint32_t, std::uint32_t> joins;
  for (std::size_t order = 0; order < boundaryVertices.size(); ++order) {
    const std::uint32_t v = boundaryVertices[order];
    const glm::dvec3 p = position.at(v);
    const glm::i64vec3 cell(glm::floor((p - lo) / tolerance));
    std::size_t firstOrder = SIZE_MAX;
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto found = cells.find(cell + glm::i64vec3(dx, dy, dz));
          if (found == cells.end()) continue;
          for (const std::uint32_t other : found->second)
            if (other < firstOrder && glm::length(position.at(boundaryVertices[other]) - p) <= tolerance) firstOrder = other;
        }
    if (firstOrder == SIZE_MAX) cells[cell].push_back(std::uint32_t(order));
    else joins[v] = boundaryVertices[firstOrder];
  }
  if (joins.empty()) return std::nullopt;
  std::vector<std::uint32_t> welded = vertexOf;
  for (std::uint32_t& id : welded)
    if (const auto found = joins.find(id); found != joins.end()) id = found->second;
  // A triangle with two corners so close that they weld would lose an edge (a sliver of nonzero
  // area, kept by cleanTriangles): the edge pairing and the pseudonormals assume three distinct
  // vertices, so such a mesh keeps the weld of equal positions.
  for (std::size_t t = 0; t + 2 < welded.size(); t += 3)
    if (welded[t] == welded[t + 1] || welded[t + 1] == welded[t + 2] || welded[t + 2] == welded[t]) return std::nullopt;
  return welded;
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
    if (!paired) {
      topology.boundaryEdges += std::size_t(count);
      topology.boundaryVertices.push_back(std::uint32_t(edge >> 32));
      topology.boundaryVertices.push_back(std::uint32_t(edge & 0xffffffffu));
    }
  }
  // Ascending and unique: independent of the hash map's order.
  std::sort(topology.boundaryVertices.begin(), topology.boundaryVertices.end());
  topology.boundaryVertices.erase(std::unique(topology.boundaryVertices.begin(), topology.boundaryVertices.end()),
                                  topology.boundaryVertices.end());
  topology.closed = topology.boundaryEdges == 0;
  return topology;
}

}  // namespace hsdf::mesh
