// Analytic SDF sources: values, exactness, gradients, bounds and the factory by name.
#include "hermite_sdf/core/analytic.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace hsdf {
namespace {

using glm::dvec3;

dvec3 centralDifference(const SdfSource& source, const dvec3& p, double step) {
  dvec3 g;
  for (int a = 0; a < 3; ++a) {
    dvec3 e(0.0);
    e[a] = step;
    g[a] = (source.sample(p + e).value - source.sample(p - e).value) / (2.0 * step);
  }
  return g;
}

dvec3 randomPoint(std::mt19937_64& rng, const Aabb& box, double grow) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const dvec3 lo = box.min - grow, hi = box.max + grow;
  return lo + (hi - lo) * dvec3(unit(rng), unit(rng), unit(rng));
}

// Tricky: each value is worked out by hand for a point where a wrong formula (e.g. the common
// box SDF that ignores the inside distance, or a torus around the wrong axis) gives another number.
TEST(AnalyticSources, ValuesAtKnownPoints) {
  const SphereSource sphere({1.0, 0.0, 0.0}, 0.5);
  EXPECT_NEAR(sphere.sample({1.0, 2.0, 0.0}).value, 1.5, 1e-15);
  EXPECT_NEAR(sphere.sample({1.0, 0.0, 0.0}).value, -0.5, 1e-15);

  const BoxSource box({0.0, 0.0, 0.0}, {1.0, 0.7, 0.5});
  EXPECT_NEAR(box.sample({0.0, 0.0, 0.0}).value, -0.5, 1e-15);              // nearest face is z
  EXPECT_NEAR(box.sample({2.0, 0.0, 0.0}).value, 1.0, 1e-15);               // off a face
  EXPECT_NEAR(box.sample({2.0, 1.7, 1.5}).value, std::sqrt(3.0), 1e-15);    // off a corner
  EXPECT_NEAR(box.sample({0.9, 0.0, 0.0}).value, -0.1, 1e-15);
  EXPECT_EQ(box.sample({0.0, 0.0, -0.2}).gradient, dvec3(0.0, 0.0, -1.0));

  const TorusSource torus({0.0, 0.0, 0.0}, 1.0, 0.35);
  EXPECT_NEAR(torus.sample({1.0, 0.0, 0.0}).value, -0.35, 1e-15);  // on the core circle
  EXPECT_NEAR(torus.sample({0.0, 0.0, 0.0}).value, 0.65, 1e-15);   // centre of the hole
  EXPECT_NEAR(torus.sample({0.0, 0.0, -1.5}).value, 0.15, 1e-15);
  EXPECT_NEAR(torus.sample({0.0, 1.0, 1.0}).value, 0.65, 1e-15);   // above the ring: axis is y

  const CapsuleSource capsule({0.0, 0.0, 0.0}, {2.0, 0.0, 0.0}, 0.5);
  EXPECT_NEAR(capsule.sample({1.0, 1.0, 0.0}).value, 0.5, 1e-15);
  EXPECT_NEAR(capsule.sample({3.0, 0.0, 0.0}).value, 0.5, 1e-15);  // beyond the end cap
  EXPECT_NEAR(capsule.sample({-1.0, 0.0, 1.0}).value, std::sqrt(2.0) - 0.5, 1e-15);
}

// Tricky: exactness (not just a bound) is checked against the brute-force distance to dense samples
// of the parametrised surface, inside and outside, including near edges and corners of the box.
TEST(AnalyticSources, AreExactDistances) {
  std::mt19937_64 rng(11);
  const BoxSource box({0.1, 0.0, -0.2}, {1.0, 0.7, 0.5});
  const TorusSource torus({0.0, 0.2, 0.0}, 1.0, 0.35);
  const CapsuleSource capsule({-0.8, -0.3, 0.0}, {0.8, 0.3, 0.0}, 0.4);
  const int n = 160;
  std::vector<dvec3> boxSurface, torusSurface, capsuleSurface;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double s = double(i) / n, t = double(j) / n;
      for (int face = 0; face < 6; ++face) {  // box faces: axis face/2, side face%2
        const int a = face / 2, b = (a + 1) % 3, c = (a + 2) % 3;
        dvec3 q;
        q[a] = face % 2 ? 1.0 : -1.0;
        q[b] = 2.0 * s - 1.0;
        q[c] = 2.0 * t - 1.0;
        boxSurface.push_back(dvec3(0.1, 0.0, -0.2) + q * dvec3(1.0, 0.7, 0.5));
      }
      const double u = 2.0 * M_PI * s, v = 2.0 * M_PI * t;
      torusSurface.push_back(dvec3((1.0 + 0.35 * std::cos(v)) * std::cos(u), 0.2 + 0.35 * std::sin(v),
                                   (1.0 + 0.35 * std::cos(v)) * std::sin(u)));
      // Capsule: the cylinder around the axis plus a hemisphere at each end.
      const dvec3 a(-0.8, -0.3, 0.0), b(0.8, 0.3, 0.0);
      const dvec3 axis = glm::normalize(b - a);
      const dvec3 e1 = glm::normalize(glm::cross(axis, dvec3(0.0, 0.0, 1.0))), e2 = glm::cross(axis, e1);
      capsuleSurface.push_back(glm::mix(a, b, s) + 0.4 * (std::cos(v) * e1 + std::sin(v) * e2));
      const double polar = 0.5 * M_PI * s;  // from the pole to the rim of a hemisphere
      const dvec3 around = std::cos(v) * e1 + std::sin(v) * e2;
      capsuleSurface.push_back(a + 0.4 * (-std::cos(polar) * axis + std::sin(polar) * around));
      capsuleSurface.push_back(b + 0.4 * (std::cos(polar) * axis + std::sin(polar) * around));
    }
  auto bruteForce = [](const std::vector<dvec3>& surface, const dvec3& p) {
    double best = HUGE_VAL;
    for (const dvec3& q : surface) best = std::min(best, glm::length(p - q));
    return best;
  };
  struct Case {
    const SdfSource* source;
    const std::vector<dvec3>* surface;
  };
  for (const Case& c : {Case{&box, &boxSurface}, Case{&torus, &torusSurface}, Case{&capsule, &capsuleSurface}}) {
    for (int trial = 0; trial < 40; ++trial) {
      const dvec3 p = randomPoint(rng, c.source->bounds(), 0.5);
      const double d = c.source->sample(p).value;
      // The dense surface samples are at most ~0.03 apart, so brute force overestimates by < 0.02.
      EXPECT_NEAR(std::abs(d), bruteForce(*c.surface, p), 0.02) << "at " << p.x << " " << p.y << " " << p.z;
    }
  }
}

// Tricky: the gradient of every shape (including the smooth union's blend weights) must match
// finite differences of its own value; points near kinks are excluded per shape, by geometry.
TEST(AnalyticSources, GradientsMatchFiniteDifferences) {
  std::mt19937_64 rng(12);
  for (const std::string& name : analyticShapeNames()) {
    auto source = makeAnalyticSource(name);
    ASSERT_TRUE(source.ok()) << name;
    int checked = 0;
    for (int trial = 0; trial < 4000 && checked < 300; ++trial) {
      const dvec3 p = randomPoint(rng, (*source)->bounds(), 0.3);
      const SdfSample s = (*source)->sample(p);
      // Kinks (centres, axes, core circles, medial planes of the box) lie at least ~0.15 inside
      // every shape, so a shell around the surface is kink-free.
      if (std::abs(s.value) > 0.1) continue;
      if (name == "box") {  // inside near edges the nearest face switches: skip near-ties
        const dvec3 q = glm::abs(p) - dvec3(1.0, 0.7, 0.5);
        const double a = std::max(q.x, std::max(q.y, q.z));
        const double b = q.x + q.y + q.z - a - std::min(q.x, std::min(q.y, q.z));
        if (s.value < 0.0 && a - b < 1e-3) continue;
      }
      const dvec3 fd = centralDifference(**source, p, 1e-6);
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(s.gradient[a], fd[a], 1e-6) << name;
      ++checked;
    }
    EXPECT_GE(checked, 100) << name;
  }
}

// Tricky: |grad| = 1 is checked on finite differences of the VALUE (a wrong value formula with
// a normalized gradient would pass a check on the returned gradient alone).
TEST(AnalyticSources, ExactShapesSatisfyTheEikonalEquation) {
  std::mt19937_64 rng(13);
  for (const char* name : {"sphere", "box", "torus", "capsule"}) {
    auto source = makeAnalyticSource(name);
    ASSERT_TRUE(source.ok());
    int checked = 0;
    for (int trial = 0; trial < 2000 && checked < 200; ++trial) {
      const dvec3 p = randomPoint(rng, (*source)->bounds(), 0.5);
      if ((*source)->sample(p).value < -0.05) continue;  // stay away from interior kinks
      EXPECT_NEAR(glm::length(centralDifference(**source, p, 1e-6)), 1.0, 1e-6) << name;
      EXPECT_NEAR(glm::length((*source)->sample(p).gradient), 1.0, 1e-12) << name;
      ++checked;
    }
    EXPECT_GE(checked, 100);
  }
}

// Tricky: where the children are farther apart than k the blend must vanish exactly (clamped
// weight), and inside the blend the union lies below both children by at most k/4.
TEST(SmoothUnion, BlendsOnlyWithinItsRadius) {
  const double k = 0.3;
  const SdfSample a{0.5, {1.0, 0.0, 0.0}}, b{0.9, {0.0, 1.0, 0.0}};
  const SdfSample far = smoothMin(a, b, k);
  EXPECT_EQ(far.value, 0.5);
  EXPECT_EQ(far.gradient, a.gradient);
  const SdfSample c{0.6, {0.0, 1.0, 0.0}};
  const SdfSample near = smoothMin(a, c, k);
  EXPECT_LT(near.value, 0.5);
  EXPECT_GE(near.value, 0.5 - k / 4.0);
  EXPECT_GT(near.gradient.x, 0.0);
  EXPECT_GT(near.gradient.y, 0.0);
  EXPECT_NEAR(near.gradient.x + near.gradient.y, 1.0, 1e-15);  // convex combination
  const SdfSample tie = smoothMin(a, SdfSample{0.5, {0.0, 1.0, 0.0}}, k);
  EXPECT_NEAR(tie.value, 0.5 - k / 4.0, 1e-15);  // the deepest point of the blend
}

// Tricky: a point outside the (padded) bounds must be outside the shape; for the smooth union the
// bounds must include the k/4 growth of the blend.
TEST(AnalyticSources, BoundsEncloseTheSurface) {
  std::mt19937_64 rng(14);
  for (const std::string& name : analyticShapeNames()) {
    auto source = makeAnalyticSource(name);
    ASSERT_TRUE(source.ok());
    const Aabb b = (*source)->bounds();
    for (int trial = 0; trial < 2000; ++trial) {
      const dvec3 p = randomPoint(rng, b, 0.5);
      const bool outside = glm::any(glm::lessThan(p, b.min)) || glm::any(glm::greaterThan(p, b.max));
      if (outside) {
        EXPECT_GT((*source)->sample(p).value, 0.0) << name;
      }
    }
    // Not too loose either: the surface comes close to every face of the box (the blend growth k/4
    // of the smooth union is a bound, not attained).
    const double slack = name == "blob" ? 0.08 : 1e-2;
    for (int face = 0; face < 6; ++face) {
      const int axis = face / 2;
      double closest = HUGE_VAL;
      for (int i = 0; i <= 40; ++i)
        for (int j = 0; j <= 40; ++j) {
          dvec3 p = b.min + b.size() * dvec3(i / 40.0, j / 40.0, i / 40.0);
          p[(axis + 2) % 3] = b.min[(axis + 2) % 3] + b.size()[(axis + 2) % 3] * (j / 40.0);
          p[(axis + 1) % 3] = b.min[(axis + 1) % 3] + b.size()[(axis + 1) % 3] * (i / 40.0);
          p[axis] = face % 2 ? b.max[axis] : b.min[axis];
          closest = std::min(closest, (*source)->sample(p).value);
        }
      EXPECT_LT(closest, slack) << name << " face " << face;
    }
  }
}

// Tricky: unknown names (and names differing only by case) must give an error naming the shape
// and listing the valid ones, not a null pointer.
TEST(AnalyticSources, FactoryKnowsEveryShapeAndRejectsOthers) {
  for (const char* name : {"sphere", "box", "torus", "capsule", "blob"}) {
    auto source = makeAnalyticSource(name);
    ASSERT_TRUE(source.ok()) << name;
    ASSERT_NE(source->get(), nullptr);
    const Aabb b = (*source)->bounds();
    bool foundInside = false;  // a real solid, not an empty or inverted shape
    for (int i = 0; i < 1000 && !foundInside; ++i)
      foundInside = (*source)->sample(b.min + b.size() * dvec3(i % 10, (i / 10) % 10, i / 100) / 9.0).value < 0.0;
    EXPECT_TRUE(foundInside) << name;
  }
  EXPECT_EQ(analyticShapeNames().size(), 5u);
  for (const char* name : {"cube", "Sphere", ""}) {
    auto source = makeAnalyticSource(name);
    ASSERT_FALSE(source.ok());
    EXPECT_NE(source.error().message.find(std::string("'") + name + "'"), std::string::npos) << source.error().message;
    EXPECT_NE(source.error().message.find("torus"), std::string::npos);
  }
}

}  // namespace
}  // namespace hsdf
