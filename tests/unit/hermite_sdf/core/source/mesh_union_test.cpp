// Distances inside overlapping closed parts baked as one mesh (mesh_union.h): against the analytic
// union of two axis-aligned boxes, min(box A, box B), computed here independently of the mesh.
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "hermite_sdf/core/analytic.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/core/field.h"
#include "hermite_sdf/core/mesh_source.h"
#include "hermite_sdf/core/sparse_bake.h"
#include "mesh_test_meshes.h"

namespace hsdf {
namespace {

using testing::TestMesh;

// Box A: [-1, 1]^3; box B: half extent 0.6 around kCentreB. No two faces coplanar; B's face
// x = 0.4 runs inside A and A's face x = 1 inside B.
const glm::vec3 kCentreB{1.0f, 0.3f, 0.2f};
constexpr float kHalfA = 1.0f;
constexpr float kHalfB = 0.6f;

TestMesh overlappingBoxes() {
  TestMesh m = testing::cube(2, kHalfA);
  const TestMesh b = testing::cube(2, kHalfB);
  const auto offset = std::uint32_t(m.positions.size());
  for (const glm::vec3& p : b.positions) m.positions.push_back(p + kCentreB);
  for (const std::uint32_t i : b.indices) m.indices.push_back(i + offset);
  return m;
}

// The analytic union: outside the exact distance, inside -max of the containing boxes' distances
// to their own surfaces (what a union of parts can know without the intersection curves).
class BoxUnion final : public SdfSource {
 public:
  SdfSample sample(const glm::dvec3& p) const override {
    const SdfSample a = a_.sample(p), b = b_.sample(p);
    return a.value <= b.value ? a : b;
  }
  Aabb bounds() const override {
    const Aabb a = a_.bounds(), b = b_.bounds();
    return {glm::min(a.min, b.min), glm::max(a.max, b.max)};
  }

 private:
  BoxSource a_{glm::dvec3(0.0), glm::dvec3(kHalfA)};
  BoxSource b_{glm::dvec3(kCentreB), glm::dvec3(kHalfB)};
};

std::unique_ptr<MeshSource> makeSource(const TestMesh& m) {
  auto source = MeshSource::create(m.positions, m.indices);
  EXPECT_TRUE(source.ok()) << (source.ok() ? "" : source.error().message);
  return std::move(source.value());
}

// Points within `near` of an internal face: B's face x = 0.4 where it lies inside A, or A's face
// x = 1 where it lies inside B, on either side of it (inside the union either way).
std::vector<glm::dvec3> pointsNearInternalFaces(std::size_t count, double near, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> offset(-near, near), y(-0.15, 0.75), z(-0.25, 0.65);
  std::vector<glm::dvec3> points;
  for (std::size_t i = 0; i < count; ++i) points.push_back({(i % 2 ? 0.4 : 1.0) + offset(rng), y(rng), z(rng)});
  return points;
}

// Tricky: next to a face of one part that runs inside the other, the closest triangle is that face
// and the plain mesh distance goes to zero there without a sign change (a false surface inside
// the solid). The field must stay the union's: far from zero, the same value as the boxes'.
TEST(MeshUnion, InsideNearInternalFacesTheFieldIsTheUnions) {
  const auto source = makeSource(overlappingBoxes());
  ASSERT_TRUE(source->stats().selfIntersecting);
  const BoxUnion reference;
  for (const glm::dvec3& p : pointsNearInternalFaces(400, 0.05, 1)) {
    const double expected = reference.sample(p).value;
    ASSERT_LT(expected, -0.1) << "probe not deep inside the union";
    const double value = source->sample(p).value;
    EXPECT_NEAR(value, expected, 1e-6) << p.x << " " << p.y << " " << p.z;
    EXPECT_LT(value, -0.1) << "a false surface inside the solid at " << p.x << " " << p.y << " " << p.z;
  }
}

// Tricky: the value must be the union's everywhere (outside: the plain closest-triangle distance,
// exact there; inside: the deepest part's), and its sign must flip only on the union's boundary.
TEST(MeshUnion, ValueMatchesTheAnalyticUnionEverywhere) {
  const auto source = makeSource(overlappingBoxes());
  const BoxUnion reference;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> x(-1.4, 2.0), yz(-1.4, 1.4);
  for (int i = 0; i < 2000; ++i) {
    const glm::dvec3 p{x(rng), yz(rng), yz(rng)};
    EXPECT_NEAR(source->sample(p).value, reference.sample(p).value, 1e-6) << p.x << " " << p.y << " " << p.z;
  }
}

// Tricky: Hermite data needs the gradient of the value actually stored, not of the closest triangle
// (inside the overlap they point different ways). Central differences of the field check it
// wherever the field is smooth there (a unit-length difference quotient: not at a medial kink).
TEST(MeshUnion, GradientIsTheDerivativeOfTheValue) {
  const auto source = makeSource(overlappingBoxes());
  const double h = 1e-5;
  int checked = 0;
  for (const glm::dvec3& p : pointsNearInternalFaces(400, 0.2, 3)) {
    glm::dvec3 difference;
    for (int axis = 0; axis < 3; ++axis) {
      glm::dvec3 e(0.0);
      e[axis] = h;
      difference[axis] = (source->sample(p + e).value - source->sample(p - e).value) / (2.0 * h);
    }
    if (std::abs(glm::length(difference) - 1.0) > 1e-6) continue;
    ++checked;
    const glm::dvec3 gradient = source->sample(p).gradient;
    EXPECT_LT(glm::length(gradient - difference), 1e-5) << p.x << " " << p.y << " " << p.z;
  }
  EXPECT_GT(checked, 200) << "too few smooth probes: the test checks little";
}

CellStats denseCellStats(const SdfSource& source, const GridSpec& grid) {
  auto field = bakeHermiteField(source, grid, {});
  EXPECT_TRUE(field.ok()) << field.error().message;
  auto classes = classifyCells(*field, {});
  EXPECT_TRUE(classes.ok());
  return classes->stats;
}

// Tricky: the false zero inside the solid is tangential (the field touches 0 from below), so its
// cells have no sign change and are kept only as ambiguous: the symptom the bake shows. With the
// union's field the mesh keeps the analytic union's cells (its grid, its classification); the
// sparse bake, which relies on the field being 1-Lipschitz, keeps the same.
TEST(MeshUnion, BakeKeepsTheAnalyticUnionsCells) {
  const auto source = makeSource(overlappingBoxes());
  const BoxUnion reference;
  // Bounds shifted off the faces: on a sample plane a face gives corner values of zero, whose sign
  // follows the mesh's float rounding, not the geometry.
  Aabb bounds = reference.bounds();
  bounds.min -= glm::dvec3(0.0123, 0.0234, 0.0345);
  bounds.max += glm::dvec3(0.0317, 0.0, 0.0);
  auto grid = fitGrid(bounds, 33, 1);
  ASSERT_TRUE(grid.ok());
  const CellStats mesh = denseCellStats(*source, *grid);
  const CellStats analytic = denseCellStats(reference, *grid);
  EXPECT_EQ(mesh.crossing, analytic.crossing);
  EXPECT_EQ(mesh.ambiguous, analytic.ambiguous);
  auto sparse = bakeCellsSparse(*source, *grid, {});
  ASSERT_TRUE(sparse.ok()) << sparse.error().message;
  EXPECT_EQ(sparse->stats.crossing, mesh.crossing);
  EXPECT_EQ(sparse->stats.ambiguous, mesh.ambiguous);
}

// Tricky: only parts that contain p count. Near the corners of a ball's bounding box, outside the
// ball but inside box A, the ball's surface is farther than A's: counting the ball there would
// move the surface of A inward (a value below A's own).
TEST(MeshUnion, OnlyPartsContainingThePointCount) {
  TestMesh m = testing::cube(2, kHalfA);
  const TestMesh ball = testing::icosphere(3, 0.5f);
  const glm::dvec3 centre{1.0, 0.0, 0.0};
  const auto offset = std::uint32_t(m.positions.size());
  for (const glm::vec3& p : ball.positions) m.positions.push_back(p + glm::vec3(centre));
  for (const std::uint32_t i : ball.indices) m.indices.push_back(i + offset);
  const auto source = makeSource(m);
  ASSERT_TRUE(source->stats().selfIntersecting);
  const BoxSource a{glm::dvec3(0.0), glm::dvec3(kHalfA)};
  for (const double y : {-0.45, 0.45})
    for (const double z : {-0.45, 0.45}) {
      const glm::dvec3 p{0.95, y, z};
      ASSERT_GT(glm::length(p - centre), 0.5 + 0.1) << "probe not well outside the ball";
      EXPECT_NEAR(source->sample(p).value, a.sample(p).value, 1e-6) << y << " " << z;
    }
}

// Tricky: a part turned inside out is a hole (a hollow's inner wall), which a union of parts cannot
// express: its own winding number is -1 inside it, so no part "contains" the wall between it and
// the outer box on its side, and the union's value there would ignore the cavity (a field that
// jumps sign at the cavity wall). Such a mesh keeps the plain distance, exact in the wall.
TEST(MeshUnion, AHollowPartKeepsThePlainDistance) {
  TestMesh m = overlappingBoxes();
  const TestMesh cavity = testing::cube(2, 0.5f);
  const auto offset = std::uint32_t(m.positions.size());
  m.positions.insert(m.positions.end(), cavity.positions.begin(), cavity.positions.end());
  for (std::size_t t = 0; t < cavity.indices.size(); t += 3)
    m.indices.insert(m.indices.end(), {cavity.indices[t] + offset, cavity.indices[t + 2] + offset,
                                       cavity.indices[t + 1] + offset});
  const auto source = makeSource(m);
  ASSERT_TRUE(source->stats().selfIntersecting);
  EXPECT_GT(source->sample({0.0, 0.0, 0.0}).value, 0.0) << "the cavity is outside the solid";
  // In the wall between the cavity (x = -0.5) and A's face x = -1, nearer the cavity.
  EXPECT_NEAR(source->sample({-0.6, 0.0, 0.0}).value, -0.1, 1e-6);
  EXPECT_NEAR(source->sample({-0.9, 0.0, 0.0}).value, -0.1, 1e-6);
}

}  // namespace
}  // namespace hsdf
