// Meshes baked as shells (MeshSourceOptions::shellThickness): f = |d| - t/2 around the triangles,
// against distances computed here independently of the mesh code (a square's, by hand; the
// brute-force triangle distance of mesh_test_meshes.h).
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "hermite_sdf/core/mesh_source.h"
#include "mesh_test_meshes.h"

namespace hsdf {
namespace {

using testing::TestMesh;

constexpr double kThickness = 0.2;

// The square [-1, 1]^2 at z = 0, two triangles facing +z: an open sheet with no inside.
TestMesh square() {
  TestMesh m;
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

// The distance to that square, by its geometry alone.
double squareDistance(const glm::dvec3& p) {
  const glm::dvec2 outside = glm::max(glm::abs(glm::dvec2(p.x, p.y)) - 1.0, 0.0);
  return std::sqrt(glm::dot(outside, outside) + p.z * p.z);
}

std::unique_ptr<MeshSource> shellOf(const TestMesh& m, double thickness = kThickness) {
  MeshSourceOptions options;
  options.shellThickness = thickness;
  auto source = MeshSource::create(m.positions, m.indices, options);
  EXPECT_TRUE(source.ok()) << source.error().message;
  return source.ok() ? std::move(*source) : nullptr;
}

// Tricky: the winding number refuses a lone sheet (it bounds no volume); as a shell it has an
// inside of its own on both sides, and the value must be the distance less t/2 everywhere, past
// the edges (distance to an edge or corner) as well as over the face, with a unit gradient.
TEST(MeshShell, ASheetIsAShellOfItsThicknessEverywhere) {
  const TestMesh sheet = square();
  EXPECT_FALSE(MeshSource::create(sheet.positions, sheet.indices).ok()) << "a solid bake of a sheet is refused";
  const auto shell = shellOf(sheet);
  ASSERT_TRUE(shell);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int i = 0; i < 500; ++i) {
    const glm::dvec3 p(u(rng), u(rng), 0.5 * u(rng));
    const SdfSample s = shell->sample(p);
    const double expected = squareDistance(p) - 0.5 * kThickness;
    EXPECT_NEAR(s.value, expected, 1e-9) << p.x << " " << p.y << " " << p.z;
    EXPECT_NEAR(glm::length(s.gradient), 1.0, 1e-9);
    // The gradient is the value's: central differences of the independent distance.
    const double e = 1e-6;
    const glm::dvec3 numeric{squareDistance(p + glm::dvec3(e, 0, 0)) - squareDistance(p - glm::dvec3(e, 0, 0)),
                             squareDistance(p + glm::dvec3(0, e, 0)) - squareDistance(p - glm::dvec3(0, e, 0)),
                             squareDistance(p + glm::dvec3(0, 0, e)) - squareDistance(p - glm::dvec3(0, 0, e))};
    if (squareDistance(p) > 1e-3) {
      EXPECT_LT(glm::length(s.gradient - numeric / (2.0 * e)), 1e-5);
    }
  }
  // On both sides of the sheet, half the thickness off it, lies the surface.
  EXPECT_NEAR(shell->sample({0.3, -0.2, 0.1}).value, 0.0, 1e-12);
  EXPECT_NEAR(shell->sample({0.3, -0.2, -0.1}).value, 0.0, 1e-12);
  EXPECT_NEAR(shell->sample({0.3, -0.2, 0.0}).value, -0.1, 1e-12) << "the middle of the shell";
  // The bounds hold the shell, not only the triangles.
  EXPECT_LE(shell->bounds().min.z, -0.1);
  EXPECT_GE(shell->bounds().max.z, 0.1);
  EXPECT_LE(shell->bounds().min.x, -1.1);
}

// Tricky: a closed mesh as a shell is hollow: its centre, inside the solid a plain bake makes, is
// outside the shell (positive), at its distance to the faces less t/2.
TEST(MeshShell, AClosedMeshIsAHollowWall) {
  const TestMesh box = testing::cube(2);
  auto solid = MeshSource::create(box.positions, box.indices);
  ASSERT_TRUE(solid.ok());
  EXPECT_LT((*solid)->sample({0.2, 0.1, 0.0}).value, 0.0);
  const auto shell = shellOf(box);
  ASSERT_TRUE(shell);
  for (const glm::dvec3 p : {glm::dvec3(0.2, 0.1, 0.0), glm::dvec3(0.95, 0.0, 0.0), glm::dvec3(1.05, 0.3, -0.2),
                             glm::dvec3(1.5, 1.5, 1.5)})
    EXPECT_NEAR(shell->sample(p).value, testing::bruteForceDistance(box, p) - 0.5 * kThickness, 1e-9)
        << p.x << " " << p.y << " " << p.z;
}

// Tricky: the band queries ask the mesh for triangles within band + t/2 (the shell's surface is
// t/2 nearer than the triangles): exact answers must equal sample(), and a bound must be a true
// lower bound of the shell's distance, at least the band, positive (a shell has no far inside).
TEST(MeshShell, BandQueriesAgreeWithSamplesAndBoundTheRest) {
  const auto shell = shellOf(square());
  ASSERT_TRUE(shell);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.6, 1.6), w(-0.7, 0.7);  // half the points within the band
  const double band = 0.25;
  int exact = 0, bounded = 0;
  for (int i = 0; i < 400; ++i) {
    const glm::dvec3 p(u(rng), u(rng), w(rng));
    const double truth = squareDistance(p) - 0.5 * kThickness;
    const SdfBandSample b = shell->sampleBand(p, band);
    if (b.exact) {
      ++exact;
      EXPECT_NEAR(b.sample.value, truth, 1e-9);
    } else {
      ++bounded;
      EXPECT_GE(b.sample.value, band - 1e-12);
      EXPECT_LE(b.sample.value, truth + 1e-9);
    }
    EXPECT_EQ(b.exact, std::abs(truth) <= band + 1e-12) << "exact exactly where the shell is within the band";
    const std::optional<SdfSample> near = shell->sampleNear(p, band);
    EXPECT_EQ(near.has_value(), b.exact);
    if (near) {
      EXPECT_NEAR(near->value, truth, 1e-9);
    }
  }
  EXPECT_GT(exact, 20);
  EXPECT_GT(bounded, 20);
}

// Tricky: NaN fails every comparison, so a check written as `thickness < 0` lets it through.
TEST(MeshShell, AThicknessThatIsNotAFiniteNonNegativeNumberIsRefusedNamingIt) {
  const TestMesh sheet = square();
  for (const double bad : {-0.1, std::nan(""), double(INFINITY)}) {
    MeshSourceOptions options;
    options.shellThickness = bad;
    const auto source = MeshSource::create(sheet.positions, sheet.indices, options);
    ASSERT_FALSE(source.ok()) << bad;
    EXPECT_NE(source.error().message.find("shell thickness"), std::string::npos) << source.error().message;
  }
}

}  // namespace
}  // namespace hsdf
