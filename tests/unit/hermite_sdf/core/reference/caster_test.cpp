// Reference ray caster: accuracy against exact surfaces, brute force, grazing and tangent rays,
// rays starting inside, rays missing the grid, kept-cells equivalence, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hermite_sdf/core/analytic.h"
#include "hermite_sdf/core/reference.h"

namespace hsdf {
namespace {

using glm::dvec3;

// F = |p - c|^2 - r^2 is a sum of separable quadratics, which the Ferguson interpolant reproduces
// EXACTLY; with h = 1/4, c = (1,1,1) and r = 3/4 every sample and gradient is exact in float. So
// the interpolant's surface is known in closed form: exact hits, tangents and double roots.
HermiteField quadricSphereField(int k = 9) {
  HermiteField field;
  field.grid.resolution = k;
  field.grid.spacing = 0.25;
  field.grid.origin = dvec3(0.0);
  field.samples.resize(field.grid.sampleCount());
  for (int z = 0; z < k; ++z)
    for (int y = 0; y < k; ++y)
      for (int x = 0; x < k; ++x) {
        const dvec3 d = field.grid.samplePosition(x, y, z) - dvec3(1.0);
        field.samples[field.grid.sampleIndex(x, y, z)] = {float(glm::dot(d, d) - 0.5625), float(2.0 * d.x),
                                                          float(2.0 * d.y), float(2.0 * d.z)};
      }
  return field;
}

// First intersection parameter of a ray with the sphere (centre, radius), or NaN.
double exactSphereHit(const Ray& ray, const dvec3& centre, double radius) {
  const dvec3 oc = ray.origin - centre;
  const double a = glm::dot(ray.direction, ray.direction), b = glm::dot(oc, ray.direction);
  const double c = glm::dot(oc, oc) - radius * radius;
  const double disc = b * b - a * c;
  if (disc < 0.0) return std::nan("");
  const double near = (-b - std::sqrt(disc)) / a;
  return near >= 0.0 ? near : (-b + std::sqrt(disc)) / a;
}

std::optional<RayHit> cast(const HermiteField& field, const Ray& ray, const CastOptions& options = {}) {
  auto result = castRay(field, ray, options);
  EXPECT_TRUE(result.ok()) << result.error().message;
  return result.ok() ? *result : std::nullopt;
}

dvec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return glm::normalize(dvec3(g(rng), g(rng), g(rng)));
}

// Tricky: the interpolant is exactly the quadric sphere, so hits must match to rounding (1e-12),
// whatever cell faces and edges the rays cross, and normals must be exact.
TEST(ReferenceCaster, HitsAnExactlyRepresentedSurfaceToRounding) {
  const HermiteField field = quadricSphereField();
  std::mt19937_64 rng(71);
  int hits = 0;
  for (int i = 0; i < 500; ++i) {
    const dvec3 dir = randomUnit(rng);
    const dvec3 target = dvec3(1.0) + 0.7 * randomUnit(rng);
    const Ray ray{target - 3.0 * dir, dir};
    const double expected = exactSphereHit(ray, dvec3(1.0), 0.75);
    const auto hit = cast(field, ray);
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(hit->t, expected, 1e-12);
    const dvec3 normal = glm::normalize(hit->position - dvec3(1.0));
    EXPECT_NEAR(glm::dot(normal, hit->normal), 1.0, 1e-12);
    EXPECT_EQ(hit->cell, glm::ivec3(glm::floor(hit->position / 0.25 - 1e-9 * dvec3(glm::sign(ray.direction)))))
        << "cell must contain the hit (entered along the ray)";
    ++hits;
  }
  EXPECT_EQ(hits, 500);
}

// Tricky: a ray tangent to the surface has a double root and no sign change; it lies in the grid
// plane y = 7h here, so the cells on both sides of the plane meet it. It must report the contact
// point, while rays 1e-6 farther out miss and rays 1e-6 closer hit at the first of two close roots.
TEST(ReferenceCaster, GrazingRaysTouchMissAndHitCorrectly) {
  const HermiteField field = quadricSphereField();
  const Ray tangent{{-2.0, 1.75, 1.0}, {1.0, 0.0, 0.0}};  // distance 0.75 from the centre
  const auto touch = cast(field, tangent);
  ASSERT_TRUE(touch.has_value());
  EXPECT_NEAR(touch->t, 3.0, 1e-5);
  EXPECT_NEAR(touch->normal.y, 1.0, 1e-4);

  const Ray outside{{-2.0, 1.75 + 1e-6, 1.0}, {1.0, 0.0, 0.0}};
  EXPECT_FALSE(cast(field, outside).has_value());

  const Ray inside{{-2.0, 1.75 - 1e-6, 1.0}, {1.0, 0.0, 0.0}};
  const auto hit = cast(field, inside);
  ASSERT_TRUE(hit.has_value());
  EXPECT_FALSE(hit->contact);
  EXPECT_NEAR(hit->t, exactSphereHit(inside, dvec3(1.0), 0.75), 1e-9);
  EXPECT_LT(hit->t, 3.0 - 1e-3);  // the first of the two roots, 2 * 1.2e-3 apart

  // An oblique tangent not aligned with the grid: the touching point within sqrt-tolerance.
  const dvec3 dir = glm::normalize(dvec3(1.0, 0.3, -0.2));
  const dvec3 normal = glm::normalize(glm::cross(dir, dvec3(0.2, 1.0, 0.4)));
  const dvec3 touchPoint = dvec3(1.0) + 0.75 * normal;
  const auto oblique = cast(field, Ray{touchPoint - 2.0 * dir, dir});
  ASSERT_TRUE(oblique.has_value());
  EXPECT_NEAR(oblique->t, 2.0, 1e-5);
}

// Tricky: origins inside the surface (hit where the ray leaves), inside a cell but outside the
// surface, exactly on a grid vertex, and rays that start beyond the surface or end before it.
TEST(ReferenceCaster, HandlesOriginsInsideTheGridAndRayRanges) {
  const HermiteField field = quadricSphereField();
  std::mt19937_64 rng(72);
  for (int i = 0; i < 100; ++i) {
    const dvec3 dir = randomUnit(rng);
    const Ray fromCentre{dvec3(1.0) + 0.3 * randomUnit(rng), dir};
    const auto exit = cast(field, fromCentre);
    ASSERT_TRUE(exit.has_value());
    EXPECT_NEAR(exit->t, exactSphereHit(fromCentre, dvec3(1.0), 0.75), 1e-12);
    EXPECT_GT(glm::dot(exit->normal, dir), 0.0);  // gradient points outwards where the ray leaves
  }
  const Ray fromVertex{{0.25, 0.5, 0.25}, glm::normalize(dvec3(1.0, 0.8, 1.1))};  // a sample point
  const auto hit = cast(field, fromVertex);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, exactSphereHit(fromVertex, dvec3(1.0), 0.75), 1e-12);

  const Ray awayFromSurface{{0.1, 0.1, 0.1}, glm::normalize(dvec3(-1.0, -0.2, -0.3))};
  EXPECT_FALSE(cast(field, awayFromSurface).has_value());

  const Ray through{{-1.0, 1.0, 1.0}, {1.0, 0.0, 0.0}};  // enters at t = 1.25, leaves at 2.75
  CastOptions options;
  options.tMax = 1.2;
  EXPECT_FALSE(cast(field, through, options).has_value());
  options.tMax = 10.0;
  options.tMin = 2.0;  // starts inside: next root is the exit
  ASSERT_TRUE(cast(field, through, options).has_value());
  EXPECT_NEAR(cast(field, through, options)->t, 2.75, 1e-12);
}

// Tricky: rays that miss the grid box (parallel to an axis just outside a face, pointing away,
// passing a corner) must return no hit without touching the field; degenerate rays are errors.
TEST(ReferenceCaster, RaysMissingTheGridAndBadRays) {
  const HermiteField field = quadricSphereField();  // grid box [0,2]^3
  EXPECT_FALSE(cast(field, Ray{{-1.0, 2.0 + 1e-9, 1.0}, {1.0, 0.0, 0.0}}).has_value());
  EXPECT_FALSE(cast(field, Ray{{3.0, 1.0, 1.0}, {1.0, 0.0, 0.0}}).has_value());
  EXPECT_FALSE(cast(field, Ray{{-1.0, -1.0, 3.1}, glm::normalize(dvec3(1.0, 1.0, 0.0))}).has_value());
  EXPECT_FALSE(castRay(field, Ray{{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}}).ok());
  EXPECT_FALSE(castRay(field, Ray{{std::nan(""), 0.0, 0.0}, {1.0, 0.0, 0.0}}).ok());
  EXPECT_FALSE(castRay(field, Ray{{0.0, 0.0, 0.0}, {HUGE_VAL, 0.0, 0.0}}).ok());
  CastOptions reversed;
  reversed.tMin = 2.0;
  reversed.tMax = 1.0;
  EXPECT_FALSE(castRay(field, Ray{{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}}, reversed).ok());
  HermiteField broken = field;
  broken.samples.pop_back();
  const auto error = castRay(broken, Ray{{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}});
  ASSERT_FALSE(error.ok());
  EXPECT_NE(error.error().message.find("samples"), std::string::npos);
}

HermiteField bakeShape(const SdfSource& source, int k) {
  auto grid = fitGrid(source.bounds(), k, 1);
  EXPECT_TRUE(grid.ok());
  auto field = bakeHermiteField(source, *grid, {});
  EXPECT_TRUE(field.ok());
  return std::move(*field);
}

// Tricky: against a real SDF the interpolant is only an approximation: with zero twists the
// error is O(h^2) (not h^4), so the test checks the measured constant (max |dt| <= 0.03 h^2,
// normals within 0.08 h radians) and second-order convergence from K = 32 to K = 64.
TEST(ReferenceCaster, ConvergesToAnAnalyticSphere) {
  const dvec3 centre(0.1, -0.05, 0.02);
  const SphereSource sphere(centre, 1.0);
  double previousError = 0.0;
  for (int k : {32, 64}) {
    const HermiteField field = bakeShape(sphere, k);
    const double h = field.grid.spacing;
    std::mt19937_64 rng(73);
    double maxError = 0.0, maxAngle = 0.0;
    for (int i = 0; i < 400; ++i) {
      const dvec3 dir = randomUnit(rng);
      const Ray ray{centre + 0.9 * randomUnit(rng) - 3.0 * dir, dir};
      const auto hit = cast(field, ray);
      ASSERT_TRUE(hit.has_value());
      const double expected = exactSphereHit(ray, centre, 1.0);
      maxError = std::max(maxError, std::abs(hit->t - expected));
      const dvec3 normal = glm::normalize(ray.origin + expected * dir - centre);
      maxAngle = std::max(maxAngle, std::acos(std::min(1.0, glm::dot(normal, hit->normal))));
    }
    EXPECT_LE(maxError, 0.03 * h * h) << "K=" << k;
    EXPECT_LE(maxAngle, 0.08 * h) << "K=" << k;
    if (previousError > 0.0) {
      EXPECT_GT(previousError / maxError, 3.0) << "second-order convergence";
    }
    previousError = maxError;
  }
}

// The interpolant at world point p, looked up independently of the caster's traversal.
double interpolantAt(const HermiteField& field, const dvec3& p) {
  const dvec3 g = (p - field.grid.origin) / field.grid.spacing;
  const int n = field.grid.cellsPerAxis();
  const glm::ivec3 cell = glm::clamp(glm::ivec3(glm::floor(g)), glm::ivec3(0), glm::ivec3(n - 1));
  return hermiteValue(field.cellCorners<double>(cell.x, cell.y, cell.z), field.grid.spacing, g - dvec3(cell));
}

// Tricky: brute force marches every ray in steps of h/100 and evaluates the interpolant directly;
// no sign change may occur before the caster's hit (no missed first root), and every ray the
// caster calls a miss must show no sign change at all. The blob has thin parts and a blend.
TEST(ReferenceCaster, NoEarlierRootThanBruteForceFinds) {
  auto blob = makeAnalyticSource("blob");
  ASSERT_TRUE(blob.ok());
  const HermiteField field = bakeShape(**blob, 20);
  const Aabb box = field.grid.bounds();
  const double step = field.grid.spacing / 100.0;
  std::mt19937_64 rng(74);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int hits = 0, misses = 0;
  for (int i = 0; i < 150; ++i) {
    const dvec3 dir = randomUnit(rng);
    const dvec3 target = box.min + box.size() * dvec3(unit(rng), unit(rng), unit(rng));
    const Ray ray{target - 4.0 * dir, dir};
    const auto hit = cast(field, ray);
    // March only inside the grid box.
    double tEnter = 0.0, tExit = 1e9;
    for (int a = 0; a < 3; ++a) {
      const double t1 = (box.min[a] - ray.origin[a]) / dir[a], t2 = (box.max[a] - ray.origin[a]) / dir[a];
      tEnter = std::max(tEnter, std::min(t1, t2));
      tExit = std::min(tExit, std::max(t1, t2));
    }
    double firstSignChange = HUGE_VAL;
    if (tEnter < tExit) {
      double previous = interpolantAt(field, ray.origin + tEnter * dir);
      for (double t = tEnter + step; t <= tExit; t += step) {
        const double value = interpolantAt(field, ray.origin + t * dir);
        if ((value < 0.0) != (previous < 0.0) || value == 0.0) {
          firstSignChange = t;
          break;
        }
        previous = value;
      }
    }
    if (hit) {
      ++hits;
      EXPECT_LE(hit->t, firstSignChange + 1e-12) << "ray " << i;
      EXPECT_GE(hit->t, firstSignChange - step - 1e-9) << "ray " << i << ": brute force saw no sign change before";
    } else {
      ++misses;
      EXPECT_EQ(firstSignChange, HUGE_VAL) << "ray " << i << " missed a root";
    }
  }
  EXPECT_GT(hits, 30);
  EXPECT_GT(misses, 10);
}

// Tricky: the cell-restricted caster skips every Empty cell; it must give bit-identical hits
// (same t, normal, cell) for all shapes, with and without refined classification.
TEST(ReferenceCaster, KeptCellsOnlyGivesIdenticalHits) {
  std::mt19937_64 rng(75);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const std::string& name : analyticShapeNames()) {
    auto source = makeAnalyticSource(name);
    ASSERT_TRUE(source.ok());
    const HermiteField field = bakeShape(**source, 24);
    for (int depth : {0, 2}) {
      ClassifyOptions options;
      options.refineDepth = depth;
      auto cells = classifyCells(field, options);
      ASSERT_TRUE(cells.ok());
      const Aabb box = field.grid.bounds();
      int hits = 0;
      for (int i = 0; i < 300; ++i) {
        const dvec3 dir = randomUnit(rng);
        const Ray ray{box.min + box.size() * dvec3(unit(rng), unit(rng), unit(rng)) - 3.0 * dir, dir};
        const auto all = cast(field, ray);
        auto kept = castRayKeptCells(field, *cells, ray);
        ASSERT_TRUE(kept.ok());
        ASSERT_EQ(all.has_value(), kept->has_value()) << name << " ray " << i;
        if (!all) continue;
        ++hits;
        EXPECT_EQ(all->t, (*kept)->t);
        EXPECT_EQ(all->cell, (*kept)->cell);
        EXPECT_EQ(all->normal, (*kept)->normal);
      }
      EXPECT_GT(hits, 50) << name;
    }
  }
}

// Tricky: the trilinear interpolant reproduces a plane exactly (hit to rounding), and follows a
// sphere with its own, larger O(h^2) error; misses stay misses.
TEST(ReferenceCaster, TrilinearFieldHits) {
  TrilinearField plane;
  plane.grid.resolution = 6;
  plane.grid.spacing = 0.2;
  plane.values.resize(plane.grid.sampleCount());
  const dvec3 n = glm::normalize(dvec3(0.3, 1.0, -0.4));
  const double offset = glm::dot(n, dvec3(0.5));  // the plane passes through the grid centre
  for (int z = 0; z < 6; ++z)
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 6; ++x)
        plane.values[plane.grid.sampleIndex(x, y, z)] = float(glm::dot(n, plane.grid.samplePosition(x, y, z)) - offset);
  std::mt19937_64 rng(76);
  for (int i = 0; i < 100; ++i) {
    const dvec3 dir = randomUnit(rng);
    const Ray ray{dvec3(0.5) - 2.0 * dir, dir};
    auto hit = castRay(plane, ray);
    ASSERT_TRUE(hit.ok());
    ASSERT_TRUE(hit->has_value());
    EXPECT_NEAR(glm::dot(n, (*hit)->position) - offset, 0.0, 1e-6);  // float samples
    EXPECT_NEAR(std::abs(glm::dot((*hit)->normal, n)), 1.0, 1e-6);
  }
  const SphereSource sphere(dvec3(0.0), 1.0);
  auto grid = fitGrid(sphere.bounds(), 32, 1);
  ASSERT_TRUE(grid.ok());
  auto field = bakeTrilinearField(sphere, *grid, {});
  ASSERT_TRUE(field.ok());
  for (int i = 0; i < 100; ++i) {
    const dvec3 dir = randomUnit(rng);
    const Ray ray{0.8 * randomUnit(rng) - 3.0 * dir, dir};
    auto hit = castRay(*field, ray);
    ASSERT_TRUE(hit.ok() && hit->has_value());
    EXPECT_NEAR((*hit)->t, exactSphereHit(ray, dvec3(0.0), 1.0), 0.6 * grid->spacing * grid->spacing);
  }
  EXPECT_FALSE(castRay(*field, Ray{{5.0, 5.0, 5.0}, {1.0, 0.0, 0.0}})->has_value());
}

}  // namespace
}  // namespace hsdf
