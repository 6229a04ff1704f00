// The capture's ground truth: the mesh caster's BVH must find the same closest hit as testing
// every triangle, and the analytic caster must land on the exact surface with the exact normal.
#include "ground_truth.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "hermite_sdf/core/analytic.h"

namespace capture {
namespace {

using engine::math::Ray;

// A UV sphere of `rings` x `segments` quads (two triangles each), outward winding.
engine::scene::TriangleSoup uvSphere(int rings, int segments, float radius) {
  engine::scene::TriangleSoup soup;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s <= segments; ++s) {
      const float theta = 3.14159265f * float(r) / float(rings), phi = 6.2831853f * float(s) / float(segments);
      soup.positions.push_back(radius * glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                                  std::sin(theta) * std::sin(phi)));
    }
  auto at = [&](int r, int s) { return std::uint32_t(r * (segments + 1) + s); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      soup.indices.insert(soup.indices.end(), {at(r, s), at(r, s + 1), at(r + 1, s)});
      soup.indices.insert(soup.indices.end(), {at(r, s + 1), at(r + 1, s + 1), at(r + 1, s)});
    }
  return soup;
}

// Every triangle, closest hit: what the BVH must reproduce.
double bruteForce(const engine::scene::TriangleSoup& soup, const Ray& ray) {
  double best = INFINITY;
  for (std::size_t i = 0; i < soup.indices.size(); i += 3) {
    const glm::dvec3 a(soup.positions[soup.indices[i]]), b(soup.positions[soup.indices[i + 1]]),
        c(soup.positions[soup.indices[i + 2]]);
    const glm::dvec3 e1 = b - a, e2 = c - a, q = glm::cross(ray.direction, e2);
    const double det = glm::dot(e1, q);
    if (det == 0.0) continue;
    const glm::dvec3 s = ray.origin - a, r = glm::cross(s, e1);
    const double u = glm::dot(s, q) / det, v = glm::dot(ray.direction, r) / det, t = glm::dot(e2, r) / det;
    if (u >= 0 && v >= 0 && u + v <= 1 && t > 0) best = std::min(best, t);
  }
  return best;
}

// Tricky: rays from every direction, many grazing the silhouette, through a tree of ~1000 leaves:
// a BVH that prunes a node it should visit, or stops at the first leaf hit instead of the nearest,
// reports a farther hit or a miss here.
TEST(MeshTruth, BvhFindsTheSameClosestHitAsEveryTriangle) {
  const auto soup = uvSphere(24, 48, 1.0f);
  const auto surface = meshSurface(soup);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const glm::dvec3 origin = glm::normalize(glm::dvec3(unit(rng), unit(rng), unit(rng))) * 3.0;
    const glm::dvec3 aim(0.9 * unit(rng), 0.9 * unit(rng), 0.9 * unit(rng));  // some rays miss
    const Ray ray{origin, glm::normalize(aim - origin)};
    const double expected = bruteForce(soup, ray);
    const auto hit = surface->cast(ray);
    ASSERT_EQ(hit.has_value(), std::isfinite(expected)) << "ray " << i;
    if (!hit) continue;
    ++hits;
    EXPECT_NEAR(hit->distance, expected, 1e-12) << "ray " << i;
    EXPECT_LT(glm::dot(hit->normal, ray.direction), 0.0) << "the face normal faces the ray";
    EXPECT_NEAR(glm::length(hit->normal), 1.0, 1e-12);
  }
  EXPECT_GT(hits, 1000);
}

// Tricky: a face seen from its back (the ray hits the inside of an open mesh) still gets the
// normal that faces the ray; and the normal is the face's, not a smooth one.
TEST(MeshTruth, FaceNormalIsGeometricAndFacesTheRay) {
  engine::scene::TriangleSoup soup;
  soup.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  soup.indices = {0, 1, 2};  // counter-clockwise seen from +z: normal +z
  const auto surface = meshSurface(soup);
  const auto front = surface->cast({{0.1, 0.0, 2.0}, {0.0, 0.0, -1.0}});
  ASSERT_TRUE(front);
  EXPECT_DOUBLE_EQ(front->distance, 2.0);
  EXPECT_EQ(front->normal, glm::dvec3(0, 0, 1));
  const auto back = surface->cast({{0.1, 0.0, -3.0}, {0.0, 0.0, 1.0}});
  ASSERT_TRUE(back);
  EXPECT_DOUBLE_EQ(back->distance, 3.0);
  EXPECT_EQ(back->normal, glm::dvec3(0, 0, -1));
}

// Tricky: the BVH reorders the triangles, so a hit must carry its own triangle's object, not the
// object of the triangle that was at its index before sorting: two overlapping objects, the near
// one named 7 and the far one 3, each hit where the other is behind or absent.
TEST(MeshTruth, HitsNameTheirTrianglesObject) {
  engine::scene::TriangleSoup soup;
  soup.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, {-1, -1, -1}, {3, -1, -1}, {1, 3, -1}};
  soup.indices = {3, 4, 5, 0, 1, 2};
  soup.triangleNodes = {3, 7};
  const auto surface = meshSurface(soup);
  const auto near = surface->cast({{0.0, -0.5, 2.0}, {0.0, 0.0, -1.0}});
  ASSERT_TRUE(near);
  EXPECT_EQ(near->part, 7);
  const auto far = surface->cast({{2.0, 0.0, 2.0}, {0.0, 0.0, -1.0}});  // outside the near triangle
  ASSERT_TRUE(far);
  EXPECT_EQ(far->part, 3);
  soup.triangleNodes.clear();
  EXPECT_EQ(meshSurface(soup)->cast({{0.0, -0.5, 2.0}, {0.0, 0.0, -1.0}})->part, -1) << "no objects: unknown";
}

// Tricky: a ray that passes the unit sphere at 0.999 of its radius grazes it: sphere tracing
// creeps along it in small steps; the hit must still be the exact first intersection.
TEST(AnalyticTruth, SphereHitsAreExactIncludingGrazingRays) {
  auto source = hsdf::makeAnalyticSource("sphere");
  ASSERT_TRUE(source.ok());
  const auto surface = analyticSurface(std::move(source.value()));
  for (double offset : {0.0, 0.5, 0.9, 0.999}) {
    const Ray ray{{offset, 0.0, 5.0}, {0.0, 0.0, -1.0}};
    const auto hit = surface->cast(ray);
    ASSERT_TRUE(hit) << offset;
    const double expected = 5.0 - std::sqrt(1.0 - offset * offset);
    EXPECT_NEAR(hit->distance, expected, 1e-7) << offset;
    const glm::dvec3 exactNormal = glm::normalize(ray.origin + expected * ray.direction);
    EXPECT_NEAR(glm::dot(hit->normal, exactNormal), 1.0, 1e-9) << offset;
  }
  EXPECT_FALSE(surface->cast({{1.001, 0.0, 5.0}, {0.0, 0.0, -1.0}}));
}

// Tricky: the torus has a hole; a ray down its axis must miss, one through the tube must hit at
// the tube's exact entry.
TEST(AnalyticTruth, TorusHoleMissesAndTubeHits) {
  auto source = hsdf::makeAnalyticSource("torus");  // major 1, minor 0.35, around +y
  ASSERT_TRUE(source.ok());
  const auto surface = analyticSurface(std::move(source.value()));
  EXPECT_FALSE(surface->cast({{0.0, 3.0, 0.0}, {0.0, -1.0, 0.0}}));
  const auto hit = surface->cast({{1.0, 3.0, 0.0}, {0.0, -1.0, 0.0}});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->distance, 3.0 - 0.35, 1e-7);
  EXPECT_NEAR(hit->normal.y, 1.0, 1e-9);
}

// Tricky: a ray that starts inside an exact distance field sees a negative value at once; a
// caster that stops at the first value below its tolerance reports a hit at its start, where the
// GPU's root search (the first sign change) finds the exit.
TEST(AnalyticTruth, RayStartingInsideHitsWhereItLeaves) {
  auto source = hsdf::makeAnalyticSource("sphere");
  ASSERT_TRUE(source.ok());
  const auto surface = analyticSurface(std::move(source.value()));
  const auto hit = surface->cast({{0.0, 0.0, 0.5}, {0.0, 0.0, -1.0}});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->distance, 1.5, 1e-7);
  EXPECT_NEAR(hit->normal.z, -1.0, 1e-9);
}

// Tricky: the near plane (4.5 from the eye) cuts the unit sphere, whose near side is 4 from the
// eye. The GPU draws nothing nearer than the plane, so the centre pixel shows the far side, 6 from
// the eye; a truth cast from the eye reports 4 there, and a truth that forgets to count the eye's
// distance to the plane reports 1.5. Both casters, mesh and analytic, must agree.
TEST(CastTruth, RaysStartAtTheNearPlaneAndDistancesAreFromTheEye) {
  constexpr int kSize = 21;  // odd: the centre pixel's ray is the view axis
  const auto camera = engine::render::CameraView::lookAt({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, 0.0f}, 0.6f, 4.5f, 1.0f);
  auto source = hsdf::makeAnalyticSource("sphere");
  ASSERT_TRUE(source.ok());
  const TruthImage analytic = castTruth(*analyticSurface(std::move(source.value())), camera, kSize, kSize);
  const TruthImage mesh = castTruth(*meshSurface(uvSphere(63, 127, 1.0f)), camera, kSize, kSize);
  const std::size_t centre = std::size_t(kSize / 2) * kSize + kSize / 2;
  ASSERT_TRUE(analytic.hit(centre));
  ASSERT_TRUE(mesh.hit(centre));
  EXPECT_NEAR(analytic.distance[centre], 6.0, 1e-5);
  EXPECT_NEAR(mesh.distance[centre], 6.0, 1e-3);
  // A corner pixel's ray from the plane passes outside the sphere's cut disc: a miss for both.
  EXPECT_FALSE(analytic.hit(0));
  EXPECT_FALSE(mesh.hit(0));
}

}  // namespace
}  // namespace capture
