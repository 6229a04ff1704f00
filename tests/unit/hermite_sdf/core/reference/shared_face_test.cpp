// Roots on faces shared by two cells: the reference caster must find every hit on a flat
// face that lies on a sample plane, within rounding of one, or is crossed by it at a tiny angle.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hermite_sdf/core/analytic.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/core/reference.h"

namespace hsdf {
namespace {

using glm::dvec3;

// Samples at -1 + i h over [-1, 1]^3: the box's faces lie on sample planes when its centre is a
// sample (odd K: the origin; even K: half a cell off it) and its half extents are whole cells.
double boxCentre(int k) { return k % 2 == 1 ? 0.0 : 1.0 / double(k - 1); }

HermiteField boxField(int k, const dvec3& half) {
  GridSpec grid;
  grid.resolution = k;
  grid.spacing = 2.0 / double(k - 1);
  grid.origin = dvec3(-1.0);
  const BoxSource box(dvec3(boxCentre(k)), half);
  auto field = bakeHermiteField(box, grid);
  EXPECT_TRUE(field.ok());
  return std::move(field.value());
}

struct FaceMisses {
  int rays = 0;
  int misses = 0;       // no hit, or a hit off the face (the ray went through it)
  double worstDepth = 0.0;  // |z - face| over the hits, in cells
};

// Rays from below aimed at the -z face of the box at z = -half.z, tilted a little so that they
// cross it at every position relative to the cells.
FaceMisses castAtBottomFace(const HermiteField& field, const CellClassification* cells, const dvec3& half) {
  const double c = boxCentre(field.grid.resolution);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> across(-0.9, 0.9), tilt(-0.3, 0.3);
  FaceMisses result;
  for (int i = 0; i < 4000; ++i) {
    const Ray ray{dvec3(c + across(rng) * half.x, c + across(rng) * half.y, -1.5), dvec3(tilt(rng), tilt(rng), 1.0)};
    // Only rays that meet the face in a cell whose corners all lie on or under the flat part of the
    // face (within a cell of an edge the interpolant rounds the edge off).
    const double face = c - half.z;
    const double t = (face - ray.origin.z) / ray.direction.z;
    const dvec3 p = ray.origin + t * ray.direction - dvec3(c);
    const double inset = 1.01 * field.grid.spacing;
    if (std::abs(p.x) > half.x - inset || std::abs(p.y) > half.y - inset) continue;
    ++result.rays;
    const auto hit = cells ? castRayKeptCells(field, *cells, ray) : castRay(field, ray);
    EXPECT_TRUE(hit.ok());
    const double error = hit.value() ? std::abs(hit.value()->position.z - face) / field.grid.spacing : HUGE_VAL;
    if (error > 1e-3) ++result.misses;
    else result.worstDepth = std::max(result.worstDepth, error);
  }
  return result;
}

// Why: with the face exactly on a sample plane, f there is 0 or a rounding error of either sign,
// and the root is on the face two cells share; each cell's segment ends or starts there, so the
// root is at the very end of one segment and the very start of the next.
TEST(ReferenceSharedFaces, FindsFacesOnSamplePlanesAtEveryResolution) {
  for (int k = 8; k <= 40; ++k) {
    const double h = 2.0 / double(k - 1);
    const dvec3 half = glm::max(glm::floor(dvec3(0.6, 0.45, 0.3) * (double(k - 1) / 2.0)), dvec3(1.0)) * h;
    const HermiteField field = boxField(k, half);
    const auto cells = classifyCells(field);
    ASSERT_TRUE(cells.ok());
    for (const CellClassification* c : {static_cast<const CellClassification*>(nullptr), &cells.value()}) {
      const FaceMisses m = castAtBottomFace(field, c, half);
      if (std::min(half.x, half.y) >= 2.0 * h) {
        EXPECT_GT(m.rays, 100) << "K=" << k;
      }
      EXPECT_EQ(m.misses, 0) << "K=" << k << (c ? " kept cells" : " all cells");
    }
  }
}

// Why: 1e-7 inside or outside the plane, the samples on the plane are tiny but not rounding
// errors, and the classifier may drop one of the two cells.
TEST(ReferenceSharedFaces, FindsFacesWithin1e7OfSamplePlanes) {
  for (int k : {8, 11, 16, 17, 32, 33}) {
    const double h = 2.0 / double(k - 1);
    for (double offset : {1e-7, -1e-7}) {
      const dvec3 half = glm::max(glm::floor(dvec3(0.6, 0.45, 0.3) * (double(k - 1) / 2.0)), dvec3(1.0)) * h + offset;
      const HermiteField field = boxField(k, half);
      const auto cells = classifyCells(field);
      ASSERT_TRUE(cells.ok());
      const FaceMisses m = castAtBottomFace(field, &cells.value(), half);
      EXPECT_EQ(m.misses, 0) << "K=" << k << " offset " << offset;
    }
  }
}

}  // namespace
}  // namespace hsdf
