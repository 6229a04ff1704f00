#pragma once
// Validation and clean-up of raw triangle lists before they become a MeshSource.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/expected.h"

namespace hsdf::mesh {

struct CleanTriangles {
  std::vector<glm::dvec3> corners;           // three per kept triangle
  std::vector<std::uint32_t> inputTriangle;  // input index of each kept triangle
  std::size_t droppedZeroArea = 0;
};

// Checks the mesh (non-empty, index count a multiple of 3, indices in range, finite coordinates)
// and drops zero-area triangles; an error names the offending triangle or vertex.
engine::Expected<CleanTriangles> cleanTriangles(const std::vector<glm::vec3>& positions,
                                                const std::vector<std::uint32_t>& indices);

struct EdgeTopology {
  std::size_t boundaryEdges = 0;  // directed edges without exactly one opposite twin
  bool closed = false;
};

// Edge pairing of the kept triangles, with vertices welded by exact position (glTF files often
// split vertices along normal or UV seams, which must not make a closed mesh look open).
EdgeTopology edgeTopology(const std::vector<glm::dvec3>& corners);

}  // namespace hsdf::mesh
