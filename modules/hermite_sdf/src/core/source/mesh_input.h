#pragma once
// Validation and clean-up of raw triangle lists before they become a MeshSource.
#include <cstddef>
#include <cstdint>
#include <optional>
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

// Vertex ids of the corners (three per triangle) with equal positions welded: glTF files often
// split vertices along normal or UV seams, which must not make a closed mesh look open.
std::vector<std::uint32_t> weldVertices(const std::vector<glm::dvec3>& corners);

// vertexOf with the boundaryVertices (of edges left unpaired by it: EdgeTopology) also welded
// where they lie within 4 float ulps of the mesh's size of one another: a seam or a pole computed
// twice with trigonometry. Nothing when none weld, or when that would weld two corners of one
// triangle.
std::optional<std::vector<std::uint32_t>> weldBoundaryWithinRounding(const std::vector<glm::dvec3>& corners,
                                                                     const std::vector<std::uint32_t>& vertexOf,
                                                                     const std::vector<std::uint32_t>& boundaryVertices);

struct EdgeTopology {
  std::size_t boundaryEdges = 0;  // directed edges without exactly one opposite twin
  std::vector<std::uint32_t> boundaryVertices;  // their ends, ascending, once each
  bool closed = false;
};

// Edge pairing of triangles given by welded vertex ids (three per triangle).
EdgeTopology edgeTopology(const std::vector<std::uint32_t>& vertexOf);

}  // namespace hsdf::mesh
