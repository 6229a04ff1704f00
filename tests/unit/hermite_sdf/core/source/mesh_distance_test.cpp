// Distance and gradient of MeshSource against brute force and finite differences.
#include <algorithm>
#include <random>
#include <thread>

#include <gtest/gtest.h>

#include "hermite_sdf/core/mesh_source.h"
#include "mesh_test_meshes.h"

namespace hsdf {
namespace {

using testing::TestMesh;

std::unique_ptr<MeshSource> makeSource(const TestMesh& m, MeshSourceOptions options = {}) {
  auto source = MeshSource::create(m.positions, m.indices, options);
  EXPECT_TRUE(source.ok()) << (source.ok() ? "" : source.error().message);
  return std::move(source.value());
}

std::vector<glm::dvec3> randomPoints(std::size_t count, double extent, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-extent, extent);
  std::vector<glm::dvec3> points(count);
  for (auto& p : points) p = {u(rng), u(rng), u(rng)};
  return points;
}

// Tricky: a non-convex mesh has many triangles at similar distances from a far point and
// concave pockets near points close to it; a BVH that prunes too eagerly (wrong box bound, wrong
// near/far order, stale seed bound from the previous query) returns a farther triangle.
TEST(MeshDistance, MatchesBruteForceOnNonConvexMesh) {
  const TestMesh mesh = testing::bumpySphere(3);
  const auto source = makeSource(mesh);
  for (const glm::dvec3& p : randomPoints(400, 1.8, 7)) {
    const double expected = testing::bruteForceDistance(mesh, p);
    EXPECT_NEAR(std::abs(source->sample(p).value), expected, 1e-9) << p.x << " " << p.y << " " << p.z;
    EXPECT_NEAR(source->closestPoint(p).distance, expected, 1e-9);
  }
}

// Tricky: pruning bounds are computed in float relative to the mesh centre. A small mesh far from
// the origin, queried from near and very far, must still get exact double distances (a pruning
// margin too small for float rounding would skip the true closest triangle).
TEST(MeshDistance, ExactForMeshFarFromOriginAndFarQueries) {
  TestMesh mesh = testing::bumpySphere(2);
  for (auto& p : mesh.positions) p = p * 0.01f + glm::vec3(3000.0f, -2000.0f, 500.0f);
  const auto source = makeSource(mesh);
  const glm::dvec3 centre(3000.0, -2000.0, 500.0);
  for (const glm::dvec3& offset : randomPoints(200, 0.03, 21)) {
    const glm::dvec3 p = centre + offset;
    EXPECT_NEAR(std::abs(source->sample(p).value), testing::bruteForceDistance(mesh, p), 1e-9);
  }
  for (const glm::dvec3& direction : randomPoints(50, 1.0, 22)) {
    const glm::dvec3 p = centre + 1e6 * direction;
    const double expected = testing::bruteForceDistance(mesh, p);
    EXPECT_NEAR(source->closestPoint(p).distance, expected, 1e-9 * expected);
  }
}

// Tricky: a mesh no larger than one BVH leaf (4 triangles: a tetrahedron) makes the root itself a
// leaf, a separate path in the tree construction. (A lone triangle bounds no volume: refused.)
TEST(MeshDistance, SingleLeafMesh) {
  const TestMesh tetrahedron{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3}};
  const auto source = makeSource(tetrahedron);
  EXPECT_NEAR(source->sample({0.2, 0.2, -0.5}).value, 0.5, 1e-15);
  EXPECT_NEAR(source->sample({2.0, 0.0, 0.0}).value, 1.0, 1e-15);
  EXPECT_NEAR(source->sample({-1.0, -1.0, 1.0}).value, std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(source->sample({0.1, 0.1, 0.1}).value, -0.1, 1e-15);
}

// Tricky: grid rows are the coherent case the seed bound is built for; each step changes the
// closest triangle a little, and rows cross the surface, so stale seeds would show up here.
TEST(MeshDistance, CoherentRowsMatchBruteForce) {
  const TestMesh mesh = testing::bumpySphere(3);
  const auto source = makeSource(mesh);
  std::vector<SdfSample> row(60);
  for (double z : {-0.9, -0.2, 0.35, 1.1}) {
    const glm::dvec3 start(-1.5, 0.1, z), step(0.05, 0.001, 0.0);
    source->sampleRow(start, step, row);
    for (std::size_t i = 0; i < row.size(); ++i) {
      const glm::dvec3 p = start + double(i) * step;
      EXPECT_NEAR(std::abs(row[i].value), testing::bruteForceDistance(mesh, p), 1e-9);
      EXPECT_EQ(row[i].value, source->sample(p).value) << "sampleRow and sample() disagree at " << i;
    }
  }
}

// Tricky: inside a cube, a point on a medial plane (|x| == |y|, ...) is equally far from two or three
// faces, and its gradient depends on which face answers. The search is seeded by the thread's
// previous queries, so "the seed unless something is strictly closer" answered such points by the
// order they were asked in (a bake then differed from run to run with the thread schedule). The
// same lattice asked forwards, backwards and shuffled must give bit-identical samples; the lattice
// includes the centre, equidistant from all six faces, and points outside near edges and corners.
TEST(MeshDistance, TiesGoToOneTriangleWhateverTheQueriesBefore) {
  const auto source = makeSource(testing::cube(3));
  std::vector<glm::dvec3> points;
  for (int k = -5; k <= 5; ++k)
    for (int j = -5; j <= 5; ++j)
      for (int i = -5; i <= 5; ++i) points.emplace_back(0.25 * i, 0.25 * j, 0.25 * k);
  auto samples = [&](const std::vector<std::size_t>& order) {
    std::vector<SdfSample> out(points.size());
    for (std::size_t i : order) out[i] = source->sample(points[i]);
    return out;
  };
  std::vector<std::size_t> order(points.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  const std::vector<SdfSample> forwards = samples(order);
  std::reverse(order.begin(), order.end());
  const std::vector<SdfSample> backwards = samples(order);
  std::shuffle(order.begin(), order.end(), std::mt19937(7));
  const std::vector<SdfSample> shuffled = samples(order);
  int medial = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (const std::vector<SdfSample>* other : {&backwards, &shuffled}) {
      ASSERT_EQ(forwards[i].value, (*other)[i].value) << "at (" << points[i].x << ", " << points[i].y << ", " << points[i].z << ")";
      ASSERT_EQ(forwards[i].gradient, (*other)[i].gradient) << "at (" << points[i].x << ", " << points[i].y << ", " << points[i].z << ")";
    }
    const glm::dvec3 a = glm::abs(points[i]);
    if (forwards[i].value < 0.0 && (a.x == a.y || a.y == a.z || a.x == a.z)) ++medial;
  }
  EXPECT_GT(medial, 100);  // the lattice does hold the ties this test is about
}

// Tricky: the closest point must be on the surface and the distance must be realised by it;
// a closest point from the wrong Voronoi region of a triangle gives a point off the triangle.
TEST(MeshDistance, ClosestPointLiesOnTheReportedTriangle) {
  const TestMesh mesh = testing::cube(3);
  const auto source = makeSource(mesh);
  for (const glm::dvec3& p : randomPoints(200, 2.0, 11)) {
    const MeshClosestPoint c = source->closestPoint(p);
    EXPECT_NEAR(glm::length(p - c.point), c.distance, 1e-12);
    const glm::dvec3 a = testing::corner(mesh, c.triangle, 0), b = testing::corner(mesh, c.triangle, 1),
                     d = testing::corner(mesh, c.triangle, 2);
    EXPECT_NEAR(testing::triangleDistance(c.point, a, b, d), 0.0, 1e-12);
  }
}

// Tricky: the gradient comes from the closest point, not from differencing, so it can silently
// have the wrong sign inside or point the wrong way; central differences of the value catch both.
// Points near the medial axis (closest triangle changes within the stencil) are skipped.
TEST(MeshDistance, GradientMatchesFiniteDifferences) {
  const TestMesh mesh = testing::bumpySphere(3);
  const auto source = makeSource(mesh);
  const double h = 1e-6;
  int checked = 0;
  for (const glm::dvec3& p : randomPoints(300, 1.6, 3)) {
    const SdfSample s = source->sample(p);
    EXPECT_NEAR(glm::length(s.gradient), 1.0, 1e-12);
    bool smooth = true;
    glm::dvec3 fd(0.0);
    for (int axis = 0; axis < 3; ++axis) {
      glm::dvec3 e(0.0);
      e[axis] = h;
      smooth = smooth && source->closestPoint(p + e).triangle == source->closestPoint(p - e).triangle &&
               source->closestPoint(p + e).triangle == source->closestPoint(p).triangle;
      fd[axis] = (source->sample(p + e).value - source->sample(p - e).value) / (2 * h);
    }
    if (!smooth) continue;
    ++checked;
    EXPECT_NEAR(fd.x, s.gradient.x, 1e-5);
    EXPECT_NEAR(fd.y, s.gradient.y, 1e-5);
    EXPECT_NEAR(fd.z, s.gradient.z, 1e-5);
  }
  EXPECT_GT(checked, 250);
}

// Tricky: on the surface p - closest is zero, so the generic formula divides 0 by 0; the source
// must fall back to the face normal (outward for an outward-wound mesh).
TEST(MeshDistance, OnSurfaceGradientIsFaceNormal) {
  const TestMesh mesh = testing::cube(2);
  const auto source = makeSource(mesh);
  const SdfSample top = source->sample({0.3, 1.0, -0.2});
  EXPECT_NEAR(top.value, 0.0, 1e-15);
  EXPECT_NEAR(top.gradient.y, 1.0, 1e-12);
  const SdfSample left = source->sample({-1.0, 0.25, 0.5});
  EXPECT_NEAR(left.gradient.x, -1.0, 1e-12);
}

// Tricky: an axis-aligned box baked on a grid fitted to it has samples exactly on its edges and
// corners, where the closest triangle is whichever adjacent face the search met first: its face
// normal made the Hermite interpolant lean out past the other face (the edge bulged: 2,141 px of
// coverage mismatch against the mesh at K = 8, and another figure for another triangulation of
// the same cube, found by a helper's convergence study). There the gradient must be the feature's
// pseudonormal, the same for both triangulations of the cube; inside a face, the face normal.
TEST(MeshDistance, OnAnEdgeOrCornerTheGradientIsThePseudonormalWhateverTheTriangulation) {
  TestMesh other = testing::cube(1);
  for (std::size_t t = 0; t + 5 < other.indices.size(); t += 6) {  // each quad's other diagonal
    const std::uint32_t a = other.indices[t], b = other.indices[t + 1], c = other.indices[t + 2],
                        d = other.indices[t + 5];
    const std::uint32_t flipped[6] = {a, b, d, b, c, d};
    std::copy(std::begin(flipped), std::end(flipped), other.indices.begin() + std::ptrdiff_t(t));
  }
  const struct {
    glm::dvec3 p;
    glm::dvec3 gradient;
  } cases[] = {
      {{1.0, 1.0, 0.3}, glm::normalize(glm::dvec3(1.0, 1.0, 0.0))},     // an edge
      {{-1.0, 0.2, 1.0}, glm::normalize(glm::dvec3(-1.0, 0.0, 1.0))},   // another edge
      {{1.0, 1.0, 1.0}, glm::normalize(glm::dvec3(1.0, 1.0, 1.0))},     // a corner
      {{-1.0, -1.0, 1.0}, glm::normalize(glm::dvec3(-1.0, -1.0, 1.0))}, // another corner
      {{0.3, 1.0, -0.2}, {0.0, 1.0, 0.0}},                               // inside a face
  };
  for (const TestMesh& mesh : {testing::cube(1), other}) {
    const auto source = makeSource(mesh);
    ASSERT_TRUE(source->stats().pseudoNormalSign);
    for (const auto& c : cases) {
      const SdfSample s = source->sample(c.p);
      EXPECT_NEAR(s.value, 0.0, 1e-12);
      EXPECT_NEAR(glm::length(s.gradient - c.gradient), 0.0, 1e-9)
          << "at (" << c.p.x << ", " << c.p.y << ", " << c.p.z << "): (" << s.gradient.x << ", " << s.gradient.y
          << ", " << s.gradient.z << ")";
    }
  }
}

// Tricky: sample() keeps per-thread coherence state; interleaving two threads (and two sources)
// must not leak one query's seed or sign into another's answer.
TEST(MeshDistance, ConcurrentQueriesGiveTheSameAnswers) {
  const TestMesh mesh = testing::bumpySphere(2);
  const auto source = makeSource(mesh);
  const auto other = makeSource(testing::cube(2));
  const auto points = randomPoints(2000, 1.5, 5);
  std::vector<double> serial(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) serial[i] = source->sample(points[i]).value;
  std::vector<double> parallel(points.size());
  auto worker = [&](std::size_t first) {
    for (std::size_t i = first; i < points.size(); i += 2) {
      parallel[i] = source->sample(points[i]).value;
      (void)other->sample(points[points.size() - 1 - i]);
    }
  };
  std::thread a(worker, 0), b(worker, 1);
  a.join();
  b.join();
  EXPECT_EQ(serial, parallel);
}

// Tricky: a band query must be exact wherever the surface is within the band, and elsewhere
// return a bound that is both >= band (so the baker may treat it as far) and <= the true distance
// (so it is safe), with the right sign. Far signs come from different places per sign mode
// (pseudonormals of a full query, or reused/fresh winding numbers), so both modes are checked.
TEST(MeshDistance, BandQueryIsExactInsideAndSafeOutside) {
  const TestMesh mesh = testing::bumpySphere(3);
  for (const SignMode mode : {SignMode::Auto, SignMode::WindingNumber}) {
    MeshSourceOptions options;
    options.signMode = mode;
    const auto source = makeSource(mesh, options);
    const auto reference = makeSource(mesh);
    const double band = 0.15;
    int far = 0, near = 0;
    std::vector<SdfBandSample> row(80);
    for (double y : {-0.7, 0.0, 0.45}) {
      const glm::dvec3 start(-1.6, y, 0.05), step(0.04, 0.0, 0.0);
      source->sampleBandRow(start, step, band, row);
      for (std::size_t i = 0; i < row.size(); ++i) {
        const SdfSample exact = reference->sample(start + double(i) * step);
        if (std::abs(exact.value) < band) {
          ++near;
          ASSERT_TRUE(row[i].exact) << i;
          EXPECT_EQ(row[i].sample.value, exact.value);
        } else if (!row[i].exact) {
          ++far;
          EXPECT_GE(std::abs(row[i].sample.value), band);
          EXPECT_LE(std::abs(row[i].sample.value), std::abs(exact.value) + 1e-12);
          EXPECT_EQ(std::signbit(row[i].sample.value), std::signbit(exact.value)) << i;
        }
      }
    }
    EXPECT_GT(near, 10);
    EXPECT_GT(far, 100);
  }
}

// Tricky: pruning bounds are squared distances in float. In world units a mesh 1e30 across
// overflows them (every bound +inf, nothing visited: no closest triangle at all) and one 1e-30
// across underflows them (every bound 0, no pruning, wrong "safe" band bounds). Distances, signs
// and band bounds must be those of the unit mesh scaled, at every scale a float mesh can have; the
// factors are not powers of two, so the scaled meshes are not bit-exact copies.
TEST(MeshDistance, ExactAtExtremeScales) {
  const TestMesh unit = testing::bumpySphere(2);
  const auto unitSource = makeSource(unit);
  for (const double scale : {3e30, 3e-30, 1e37, 1e-37}) {
    TestMesh mesh = unit;
    for (auto& p : mesh.positions) p = glm::vec3(glm::dvec3(p) * scale);
    const auto source = makeSource(mesh);
    for (const glm::dvec3& q : randomPoints(100, 1.8, 31)) {
      const glm::dvec3 p = q * scale;
      const double expected = testing::bruteForceDistance(mesh, p);
      const SdfSample s = source->sample(p);
      EXPECT_NEAR(std::abs(s.value), expected, 1e-9 * scale) << "scale " << scale;
      EXPECT_EQ(std::signbit(s.value), std::signbit(unitSource->sample(q).value)) << "scale " << scale;
      const SdfBandSample band = source->sampleBand(p, 0.1 * scale);
      EXPECT_LE(std::abs(band.sample.value), expected * (1.0 + 1e-9)) << "scale " << scale;
      if (!band.exact) {
        EXPECT_GE(std::abs(band.sample.value), 0.1 * scale * (1.0 - 1e-9));
      }
    }
  }
}

// Tricky: a query so far away (1e25 mesh radii) that even the bounds in mesh units overflow float
// must still find the closest triangle rather than report none (which indexed past the triangle
// list when the sign was looked up). Only the distance is checked: at 1e25 radii double rounding
// cannot tell which triangle is nearest, so the pseudonormal sign there is not meaningful. At 1e45
// radii (a shell far thicker than a tiny mesh puts grid points there) the query's own float
// coordinates overflow: the search crashed on the inf and NaN bounds.
TEST(MeshDistance, AbsurdlyFarQueriesStillFindTheClosestTriangle) {
  const TestMesh mesh = testing::bumpySphere(1);
  const auto source = makeSource(mesh);
  for (const double far : {1e25, 1e45})
    for (const glm::dvec3& direction : randomPoints(20, 1.0, 32)) {
      const glm::dvec3 p = far * direction;
      const double expected = testing::bruteForceDistance(mesh, p);
      EXPECT_NEAR(std::abs(source->sample(p).value), expected, 1e-9 * expected) << far;
      EXPECT_NEAR(source->closestPoint(p).distance, expected, 1e-9 * expected) << far;
    }
}

}  // namespace
}  // namespace hsdf
