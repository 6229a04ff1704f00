// MeshSource construction: bad input is refused with an error naming the problem; zero-area
// triangles are dropped without changing the field.
#include <cmath>
#include <limits>
#include <numbers>
#include <set>

#include <gtest/gtest.h>

#include "hermite_sdf/core/mesh_source.h"
#include "mesh_test_meshes.h"
#include "source/mesh_input.h"

namespace hsdf {
namespace {

using testing::TestMesh;

std::string errorOf(std::vector<glm::vec3> positions, std::vector<std::uint32_t> indices) {
  auto source = MeshSource::create(std::move(positions), std::move(indices));
  return source.ok() ? std::string("(accepted)") : source.error().message;
}

// Tricky: each malformed input must fail at construction (not crash in a later query), with a
// message a user can act on: which triangle/vertex and what is wrong with it.
TEST(MeshInput, MalformedMeshesAreRefusedWithTheProblemNamed) {
  const std::vector<glm::vec3> triangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_NE(errorOf({}, {}).find("no triangles"), std::string::npos);
  EXPECT_NE(errorOf(triangle, {}).find("no triangles"), std::string::npos);
  EXPECT_NE(errorOf(triangle, {0, 1}).find("not a multiple of 3"), std::string::npos);
  const std::string outOfRange = errorOf(triangle, {0, 1, 2, 0, 2, 7});
  EXPECT_NE(outOfRange.find("triangle 1 uses vertex 7"), std::string::npos) << outOfRange;
  EXPECT_NE(outOfRange.find("3 vertices"), std::string::npos) << outOfRange;

  auto withNan = triangle;
  withNan[2].y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(errorOf(withNan, {0, 1, 2}).find("vertex 2 has a non-finite coordinate"), std::string::npos);
  auto withInf = triangle;
  withInf[0].z = -std::numeric_limits<float>::infinity();
  EXPECT_NE(errorOf(withInf, {0, 1, 2}).find("vertex 0 has a non-finite coordinate"), std::string::npos);

  // Unused vertices are checked too: a NaN anywhere in the buffer is a sign of a broken import.
  auto unusedNan = triangle;
  unusedNan.push_back({std::nanf(""), 0, 0});
  EXPECT_NE(errorOf(unusedNan, {0, 1, 2}).find("vertex 3"), std::string::npos);

  const std::string allDegenerate = errorOf({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}, {0, 1, 2, 0, 0, 1});
  EXPECT_NE(allDegenerate.find("all 2 triangles of the mesh have zero area"), std::string::npos) << allDegenerate;
}

TEST(MeshInput, InvalidOptionsAreRefused) {
  const TestMesh cube = testing::cube(1);
  MeshSourceOptions options;
  options.windingBeta = 0.0;
  auto source = MeshSource::create(cube.positions, cube.indices, options);
  ASSERT_FALSE(source.ok());
  EXPECT_NE(source.error().message.find("windingBeta"), std::string::npos);
}

// Tricky: zero-area triangles (a repeated index, three collinear corners on an existing edge)
// have no normal; kept, they would poison winding numbers and closest-point barycentrics. Dropped,
// the closed cube must stay closed and give exactly the same samples.
TEST(MeshInput, ZeroAreaTrianglesAreDroppedWithoutChangingTheField) {
  const TestMesh cube = testing::cube(2);
  TestMesh noisy = cube;
  noisy.indices.insert(noisy.indices.end(), {0, 0, 1});  // repeated vertex
  noisy.indices.insert(noisy.indices.end(), {0, 1, 2});  // collinear: along one edge row of a face
  auto clean = MeshSource::create(cube.positions, cube.indices);
  auto withDegenerate = MeshSource::create(noisy.positions, noisy.indices);
  ASSERT_TRUE(clean.ok() && withDegenerate.ok());
  const MeshSourceStats& stats = (*withDegenerate)->stats();
  EXPECT_EQ(stats.inputTriangles, cube.triangleCount() + 2);
  EXPECT_EQ(stats.droppedZeroArea, 2u);
  EXPECT_EQ(stats.triangles, cube.triangleCount());
  EXPECT_TRUE(stats.closed);
  for (const glm::dvec3 p : {glm::dvec3(0.2, 0.3, 0.1), glm::dvec3(-1.2, 0.9, 1.3), glm::dvec3(-0.99, -0.99, -0.5)}) {
    EXPECT_EQ((*clean)->sample(p).value, (*withDegenerate)->sample(p).value);
    EXPECT_EQ((*clean)->sample(p).gradient, (*withDegenerate)->sample(p).gradient);
  }
}

// Tricky: glTF files split vertices along seams; the same closed surface with every triangle
// owning its own three vertices must still be recognised as closed (edges welded by position),
// and closest-point triangle ids must refer to the input triangle numbering.
TEST(MeshInput, SoupWithSplitVerticesIsClosedAndKeepsTriangleIds) {
  const TestMesh cube = testing::cube(2);
  engine::scene::TriangleSoup soup;
  for (std::uint32_t index : cube.indices) {
    soup.indices.push_back(std::uint32_t(soup.positions.size()));
    soup.positions.push_back(cube.positions[index]);
  }
  auto source = MeshSource::create(soup);
  ASSERT_TRUE(source.ok());
  EXPECT_TRUE((*source)->stats().closed);
  EXPECT_EQ((*source)->stats().boundaryEdges, 0u);
  const Aabb box = (*source)->bounds();
  EXPECT_EQ(box.min, glm::dvec3(-1.0));
  EXPECT_EQ(box.max, glm::dvec3(1.0));
  // Point above the centre of the +z face: the closest triangle must be one of that face's.
  const MeshClosestPoint c = (*source)->closestPoint({0.25, 0.3, 2.0});
  EXPECT_NEAR(testing::centroid(cube, c.triangle).z, 1.0, 1e-6);
  EXPECT_NEAR(c.distance, 1.0, 1e-12);
}

// A UV sphere as three.js's SphereGeometry makes it: (w + 1) x (h + 1) vertices computed with
// trigonometry in double, stored in float; the seam column (phi = 2 pi) and the pole rows are
// computed again, not shared, and no pole triangle has two pole corners.
TestMesh threeJsSphere(int w, int h, double radius) {
  TestMesh m;
  for (int iy = 0; iy <= h; ++iy)
    for (int ix = 0; ix <= w; ++ix) {
      const double phi = 2.0 * std::numbers::pi * double(ix) / double(w), theta = std::numbers::pi * double(iy) / double(h);
      m.positions.push_back(glm::vec3(glm::dvec3(-radius * std::cos(phi) * std::sin(theta), radius * std::cos(theta),
                                                 radius * std::sin(phi) * std::sin(theta))));
    }
  const auto at = [w](int ix, int iy) { return std::uint32_t(iy * (w + 1) + ix); };
  for (int iy = 0; iy < h; ++iy)
    for (int ix = 0; ix < w; ++ix) {
      const std::uint32_t a = at(ix + 1, iy), b = at(ix, iy), c = at(ix, iy + 1), d = at(ix + 1, iy + 1);
      if (iy != 0) m.indices.insert(m.indices.end(), {a, b, d});
      if (iy != h - 1) m.indices.insert(m.indices.end(), {b, c, d});
    }
  return m;
}

// Tricky: the seam's copies differ from the first column by sin(2 pi) * r = -2.4e-16 * r and the
// south pole's copies by sin(pi) * r, so welding equal positions alone left the sphere open
// (boundary edges along the seam and around a pole), signed by the winding number and exposed to
// the rules for open parts (an explorer's finding). Positions within 4 float ulps of the mesh's
// size weld: the sphere is closed and signed by pseudonormals, the same as the analytic sphere.
TEST(MeshInput, ATrigRoundedSeamIsWelded) {
  const TestMesh sphere = threeJsSphere(24, 12, 1.5);
  // The premise: the seam's copies are not equal to the first column (row 6: the equator).
  EXPECT_NE(sphere.positions[6 * 25], sphere.positions[6 * 25 + 24]);
  auto source = MeshSource::create(sphere.positions, sphere.indices);
  ASSERT_TRUE(source.ok()) << source.error().message;
  const MeshSourceStats& stats = (*source)->stats();
  EXPECT_TRUE(stats.closed) << stats.boundaryEdges << " boundary edges";
  EXPECT_TRUE(stats.pseudoNormalSign);
  EXPECT_EQ(stats.triangles, sphere.triangleCount());
  // 24 x 12 facets lie within r (1 - cos(pi / 12)) = 0.052 of the sphere.
  for (const glm::dvec3& p : {glm::dvec3(0.0), glm::dvec3(1.4, 0.0, 0.0), glm::dvec3(0.0, -1.4, 0.0),
                              glm::dvec3(-1.0, 0.5, 0.01), glm::dvec3(1.6, 0.0, 0.0), glm::dvec3(0.0, -1.6, 0.0),
                              glm::dvec3(1.2, 1.2, 0.0)})
    EXPECT_EQ((*source)->sample(p).value < 0.0, glm::length(p) < 1.5) << p.x << " " << p.y << " " << p.z;
}

// Tricky: the tolerance must not weld distinct vertices: a slab 1e-5 of its size thick keeps its
// top and bottom apart (20 float ulps of its size), copies 1e-9 apart weld whatever their order.
TEST(MeshInput, WeldingKeepsDistinctVerticesApart) {
  // Two triangles: every edge is a boundary edge, every vertex a candidate.
  const std::vector<glm::dvec3> corners = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1e-5}, {1, 0, 1e-5}, {1e-9, 1, 0}};
  const std::vector<std::uint32_t> equal = mesh::weldVertices(corners);
  const auto welded = mesh::weldBoundaryWithinRounding(corners, equal, mesh::edgeTopology(equal).boundaryVertices);
  ASSERT_TRUE(welded.has_value());
  const std::vector<std::uint32_t>& ids = *welded;
  EXPECT_NE(ids[0], ids[3]);
  EXPECT_NE(ids[1], ids[4]);
  EXPECT_EQ(ids[2], ids[5]);
  EXPECT_EQ(std::set<std::uint32_t>(ids.begin(), ids.end()).size(), 5u);
}

}  // namespace
}  // namespace hsdf
