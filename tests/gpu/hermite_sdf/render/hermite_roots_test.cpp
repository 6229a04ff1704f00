// Robust roots of the Hermite cells: surfaces on, near and half a cell off the sample
// planes, thin features, planes through cell edges and corners, grazing rays — in the default
// search (the paper's n samples, with the Bernstein fallback when they show no sign change) and in
// the certified mode, at chosen resolutions K from 8 to 64 (sweptResolutions). Each frame is
// compared with the CPU reference ray caster of the same interpolant (coverage away from
// silhouettes, depth outliers), counted for isolated wrong pixels (specks), and, for boxes on the
// sample planes, compared with the dense Hermite sphere tracer of the same field.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/core/image_io.h"
#include "engine/core/math.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/core/analytic.h"
#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/core/field.h"
#include "hermite_sdf/render/features.h"
#include "hermite_sdf/render/sphere_trace_feature.h"
#include "hermite_test_support.h"
#include "shared/host_device.h"

namespace gputest {
namespace {

using namespace engine;

constexpr std::uint32_t kWidth = 112;
constexpr std::uint32_t kHeight = 84;
constexpr int kMinK = 8;
constexpr int kMaxK = 64;

// HSDF_TEST_K=k runs only resolution k (for looking at one failure).
bool selected(int k) {
  const char* only = std::getenv("HSDF_TEST_K");
  return only == nullptr || std::atoi(only) == k;
}

// The resolutions the sweeps draw. Every K from 8 to 64 took CI ~90 s; these are the ones where
// the grid does something of its own: the smallest grids, whose rounded box edges turn within a
// cell (8-13); the grids whose spacing 2 / (K - 1) is a power of two, so that sample planes and
// face positions are exact in binary and f is exactly 0 on whole planes of samples (9, 17, 33: at
// K = 33 thousands of specks before the overlap rule); and both parities (the grid's centre on a
// sample or between two; the two views alternate with it) at the sizes in between and at the top.
// HSDF_TEST_K=k runs only k (any K), HSDF_TEST_K=all every K from 8 to 64.
std::vector<int> sweptResolutions() {
  const char* only = std::getenv("HSDF_TEST_K");
  if (only != nullptr && std::string(only) != "all") return {std::atoi(only)};
  if (only == nullptr) return {8, 9, 10, 11, 12, 13, 16, 17, 24, 31, 32, 33, 47, 48, 63, 64};
  std::vector<int> every;
  for (int k = kMinK; k <= kMaxK; ++k) every.push_back(k);
  return every;
}

// A grid over [-1, 1]^3: sample i of each axis lies at -1 + i h.
hsdf::GridSpec unitGrid(int resolution) {
  hsdf::GridSpec grid;
  grid.resolution = resolution;
  grid.spacing = 2.0 / double(resolution - 1);
  grid.origin = glm::dvec3(-1.0);
  return grid;
}

// A box rotated by `rotation` about its centre (the exact SDF in the box's frame).
class RotatedBoxSource final : public hsdf::SdfSource {
 public:
  RotatedBoxSource(const glm::dvec3& centre, const glm::dvec3& half, const glm::dmat3& rotation)
      : centre_(centre), box_(glm::dvec3(0.0), half), rotation_(rotation) {}
  hsdf::SdfSample sample(const glm::dvec3& p) const override {
    hsdf::SdfSample local = box_.sample(glm::transpose(rotation_) * (p - centre_));
    local.gradient = rotation_ * local.gradient;
    return local;
  }
  hsdf::Aabb bounds() const override { return {centre_ + box_.bounds().min, centre_ + box_.bounds().max}; }

 private:
  glm::dvec3 centre_;
  hsdf::BoxSource box_;
  glm::dmat3 rotation_;
};

// The half-space dot(n, p) <= d, cut by the grid: its plane is the only surface.
class HalfSpaceSource final : public hsdf::SdfSource {
 public:
  HalfSpaceSource(const glm::dvec3& normal, double d) : normal_(glm::normalize(normal)), d_(d) {}
  hsdf::SdfSample sample(const glm::dvec3& p) const override { return {glm::dot(normal_, p) - d_, normal_}; }
  hsdf::Aabb bounds() const override { return {glm::dvec3(-0.8), glm::dvec3(0.8)}; }

 private:
  glm::dvec3 normal_;
  double d_;
};

// A spherical shell |‖p‖ - r| - thickness/2: two surfaces closer together than a cell.
class ShellSource final : public hsdf::SdfSource {
 public:
  ShellSource(double radius, double thickness) : sphere_(glm::dvec3(0.0), radius), half_(0.5 * thickness) {}
  hsdf::SdfSample sample(const glm::dvec3& p) const override {
    hsdf::SdfSample s = sphere_.sample(p);
    if (s.value < 0.0) s = {-s.value, -s.gradient};
    s.value -= half_;
    return s;
  }
  hsdf::Aabb bounds() const override { return sphere_.bounds(); }

 private:
  hsdf::SphereSource sphere_;
  double half_;
};

std::shared_ptr<const hsdf::SdfAsset> bake(const std::string& label, const hsdf::SdfSource& source,
                                           const hsdf::GridSpec& grid) {
  auto field = hsdf::bakeHermiteField(source, grid);
  EXPECT_TRUE(field.ok()) << field.error().message;
  if (!field) return nullptr;
  auto asset = hsdf::makeSdfAsset(label, std::move(field.value()), source.bounds());
  EXPECT_TRUE(asset.ok()) << asset.error().message;
  return asset ? asset.value() : nullptr;
}

// A sample point at the middle of the grid (the origin for odd K, half a cell off it for even K):
// a box centred there with half extents of whole cells has its faces on sample planes.
glm::dvec3 gridCentre(int resolution) { return glm::dvec3(resolution % 2 == 1 ? 0.0 : 1.0 / double(resolution - 1)); }

// Box half extents in whole cells, per axis a different share of the grid so that all three face
// pairs are distinct, and at least one cell.
glm::dvec3 wholeCells(int resolution) {
  const double cells = double(resolution - 1) / 2.0;
  return glm::max(glm::floor(glm::dvec3(0.6, 0.45, 0.3) * cells), glm::dvec3(1.0));
}

// The paper's search (with its fallback when the samples show no sign change) and the certified one.
constexpr bool kCertified[] = {false, true};
// The cells' own proxies, and the bricks, whose fragments walk several cells each: a root on a face
// two cells share must not be lost inside a brick or between bricks either. Both run in both modes:
// the walk stops at the first step whose searches report a root, and the default search reports
// roots (interpolated, contacts, its fallback's) where the certified one may not, so the default
// mode, the renderer's own, is the one whose walk a wrong stop would show in.
constexpr hsdf::RenderMethod kCellMethods[] = {hsdf::RenderMethod::Cells, hsdf::RenderMethod::CellBricks};

// With HSDF_TEST_DUMP=folder, a failing frame's GPU normals, the reference normals and a map of
// depth errors (red: GPU behind the reference, blue: in front, scaled so 0.05 cells is full).
void dump(const std::string& folder, std::string label, const Frame& normals, const hsdf::ReferenceImage& reference,
          const render::CameraView& camera, double spacing) {
  for (char& ch : label)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  const std::string prefix = folder + "/" + label;
  (void)writePng(prefix + "_gpu.png", normals.rgba, normals.width, normals.height, 4);
  (void)hsdf::writeNormalPng(reference, prefix + "_ref.png");
  std::vector<std::uint8_t> map(normals.rgba.size(), 0);
  for (std::size_t i = 0; i < reference.hit.size(); ++i) {
    map[i * 4 + 3] = 255;
    const float depth = normals.depth[i];
    if (!reference.hit[i] || depth <= 0.0f) continue;
    const double error = (math::depthToViewDistance(depth, camera.znear) -
                          math::depthToViewDistance(reference.depth[i], camera.znear)) / spacing;
    const auto level = std::uint8_t(std::min(255.0, 40.0 + 215.0 * std::abs(error) / kDepthOutlierCells));
    map[i * 4 + (error > 0.0 ? 0 : 2)] = level;
  }
  (void)writePng(prefix + "_depth.png", map, normals.width, normals.height, 4);
}

class HermiteRootsTest : public GpuTest {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    createRenderer(kWidth, kHeight);
    const Status added = hsdf::addRenderFeatures(*renderer_);
    ASSERT_TRUE(added.ok()) << added.error().message;
  }

  hsdf::HermiteSdfRenderable& show(std::shared_ptr<const hsdf::SdfAsset> asset) {
    if (!entity_) entity_ = addSdf(registry_, asset, hsdf::RenderMethod::Cells);
    auto& renderable = registry_.get<hsdf::HermiteSdfRenderable>(*entity_);
    renderable.asset = std::move(asset);
    return renderable;
  }

  // Renders `asset` from `camera` in every mode and checks each frame against the reference:
  // no coverage difference away from silhouettes, no depth outlier, no speck.
  void expectRobust(const std::shared_ptr<const hsdf::SdfAsset>& asset, const render::CameraView& camera,
                    const std::string& label) {
    auto reference = hsdf::renderReference(asset->field, camera.view, camera.proj, {int(kWidth), int(kHeight)},
                                           &asset->classification);
    ASSERT_TRUE(reference.ok()) << reference.error().message;
    int referenceHits = 0;
    for (std::uint8_t hit : reference->hit) referenceHits += hit;
    EXPECT_GT(referenceHits, 300) << label << ": too little surface in view for the test to mean anything";
    for (const hsdf::RenderMethod method : kCellMethods)
    for (const bool certified : kCertified) {
      hsdf::HermiteSdfRenderable& renderable = show(asset);
      renderable.method = method;
      renderable.subdivisions = 3;  // the paper's n and the renderer's default
      renderable.refineSteps = 1;
      renderable.certified = certified;
      // One frame: the normals view also carries the prepass depth.
      const Frame normals = renderWith(camera, DEBUG_VIEW_NORMALS);
      const ImageComparison c =
          compareWithReference(normals, &normals.rgba, *reference, camera, asset->field.grid.spacing);
      // A missed root shows another surface (or none): coverage differs or the normal is far off.
      // The paper's search places its root by interpolation and `refine` Newton steps; where the
      // normal turns by tens of degrees per pixel (rounded edges at K = 8) that placement alone
      // can move a normal by 10-20 degrees, so it is held to 30 and the certified search to 10.
      const std::vector<bool> wrong = wrongPixels(normals, *reference, certified ? 10.0 : 30.0);
      const int specks = countIsolatedPixels(normals, 24, [&wrong](std::size_t i) { return wrong[i]; });
      const std::string where = label + ", " + hsdf::renderMethodName(method) +
                                (certified ? ", certified" : ", n=" + std::to_string(renderable.subdivisions));
      EXPECT_EQ(c.interiorHoles, 0) << where;
      EXPECT_EQ(c.interiorExtras, 0) << where;
      EXPECT_EQ(specks, 0) << where;
      // The certified search places the first root to 2^-18 of its interval: depth is the
      // reference's away from silhouettes. The paper's search places it by interpolation between
      // samples and `refine` Newton steps, whose error where F curves within a fraction of a cell
      // (rounded box edges, thin features) can exceed the outlier bound; only its coverage is held.
      if (certified) {
        EXPECT_EQ(c.interiorDepthOutliers, 0) << where;
      }
      if (c.interiorHoles + c.interiorExtras + c.interiorDepthOutliers + specks > 0 && std::getenv("HSDF_TEST_DUMP"))
        dump(std::getenv("HSDF_TEST_DUMP"), where, normals, *reference, camera, asset->field.grid.spacing);
      if (c.interiorHoles + c.interiorExtras + c.interiorDepthOutliers + specks > 0)
        std::printf("[ %s ] disagree %d, holes %d, extras %d, depth outliers %d, specks %d\n", where.c_str(),
                    c.disagreements, c.interiorHoles, c.interiorExtras, c.interiorDepthOutliers, specks);
    }
  }

  // Coverage of the cells against the dense Hermite sphere tracer of the same field, away from the
  // reference's silhouettes (the tracer stops within eps of the surface, so silhouettes may differ).
  void expectCoverageMatchesHermiteTracer(const std::shared_ptr<const hsdf::SdfAsset>& asset,
                                          const render::CameraView& camera, const std::string& label) {
    hsdf::HermiteSdfRenderable& renderable = show(asset);
    renderable.certified = false;
    renderable.subdivisions = 3;
    renderable.method = hsdf::RenderMethod::Cells;
    const Frame cells = renderWith(camera, DEBUG_VIEW_NONE);
    show(asset).method = hsdf::RenderMethod::HermiteSphereTrace;
    const Frame traced = renderWith(camera, DEBUG_VIEW_NONE);
    int differ = 0;
    for (std::uint32_t y = 1; y + 1 < kHeight; ++y)
      for (std::uint32_t x = 1; x + 1 < kWidth; ++x) {
        bool uniform = true;  // the tracer's own 3x3 neighbourhood: away from its silhouette
        const bool centre = traced.depthAt(x, y) > 0.0f;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) uniform &= (traced.depthAt(x + dx, y + dy) > 0.0f) == centre;
        differ += uniform && (cells.depthAt(x, y) > 0.0f) != centre;
      }
    EXPECT_EQ(differ, 0) << label << ": cells and the dense Hermite tracer disagree on coverage";
  }

  render::CameraView view(const hsdf::SdfAsset& asset, int index) const {
    return orbitAround(worldSphere(asset, glm::mat4(1.0f)), index);
  }

  std::optional<ecs::Entity> entity_;
};

// Why: faces of a box fitted to the grid lie on sample planes, so f is 0 or a rounding error at
// whole planes of samples and the root sits on the face two cells share. Each cell computes the
// face point in its own local coordinates; rounding put it just outside both segments and the ray
// went through the face (thousands of specks at K = 33 before the overlap rule).
TEST_F(HermiteRootsTest, BoxFacesOnSamplePlanesAcrossResolutions) {
  for (const int k : sweptResolutions()) {
    const hsdf::GridSpec grid = unitGrid(k);
    const hsdf::BoxSource box(gridCentre(k), wholeCells(k) * grid.spacing);
    const auto asset = bake("box on planes", box, grid);
    ASSERT_NE(asset, nullptr);
    const int v = k % 2;
    const std::string label = "box on planes K=" + std::to_string(k) + " view " + std::to_string(v);
    expectRobust(asset, view(*asset, v), label);
    expectCoverageMatchesHermiteTracer(asset, view(*asset, v), label);
  }
}

// Why: half a cell off, the faces cut through the middle of a layer of cells: every sample is a
// clear distance from the surface, the baseline that must not regress.
TEST_F(HermiteRootsTest, BoxFacesHalfACellOffAcrossResolutions) {
  for (const int k : sweptResolutions()) {
    const hsdf::GridSpec grid = unitGrid(k);
    const hsdf::BoxSource box(gridCentre(k), (wholeCells(k) + 0.5) * grid.spacing);
    const auto asset = bake("box half off", box, grid);
    ASSERT_NE(asset, nullptr);
    const int v = k % 2;  // the two views alternate over K: every face, both parities
    expectRobust(asset, view(*asset, v), "box half off K=" + std::to_string(k) + " view " + std::to_string(v));
  }
}

// Why: 1e-7 from a plane (inside on x and z, outside on y), the samples on the plane are tiny but
// not zero and of either sign: one of the two cells holds the root within float rounding of the
// face, the other may be proven empty by the classifier.
TEST_F(HermiteRootsTest, BoxFacesWithin1e7OfSamplePlanesAcrossResolutions) {
  for (const int k : sweptResolutions()) {
    const hsdf::GridSpec grid = unitGrid(k);
    const hsdf::BoxSource box(gridCentre(k), wholeCells(k) * grid.spacing + glm::dvec3(1e-7, -1e-7, 1e-7));
    const auto asset = bake("box near planes", box, grid);
    ASSERT_NE(asset, nullptr);
    const int v = k % 2;  // the two views alternate over K: every face, both parities
    expectRobust(asset, view(*asset, v), "box near planes K=" + std::to_string(k) + " view " + std::to_string(v));
  }
}

// Why: a slab two cells thick with both faces on sample planes: whole layers of cells are crossed
// by the surface only on their faces, and the rays leave the slab within two cells of entering.
TEST_F(HermiteRootsTest, SlabsWithFacesOnSamplePlanesAcrossResolutions) {
  for (const int k : sweptResolutions()) {
    const hsdf::GridSpec grid = unitGrid(k);
    const hsdf::BoxSource slab(gridCentre(k), glm::dvec3(grid.spacing, 0.7, 0.6));
    const auto asset = bake("slab", slab, grid);
    ASSERT_NE(asset, nullptr);
    const int v = k % 2;  // the two views alternate over K: every face, both parities
    expectRobust(asset, view(*asset, v), "slab K=" + std::to_string(k) + " view " + std::to_string(v));
  }
}

// Why: a slab 0.6 cells thick between two sample planes: the interpolant dips below zero for about
// a third of a cell, so along oblique rays (segments up to 1.7 cells, samples 0.58 cells apart at
// n = 3) both roots can fall between two samples and no sample changes sign: the paper's search
// alone steps over the slab.
TEST_F(HermiteRootsTest, ThinSlabsBetweenSamplePlanesAcrossResolutions) {
  for (const int k : sweptResolutions()) {
    const hsdf::GridSpec grid = unitGrid(k);
    const double center = (std::floor(0.3 * double(k - 1)) + 0.5) * grid.spacing - 1.0;
    const hsdf::BoxSource slab(glm::dvec3(center, 0.0, 0.0), glm::dvec3(0.3 * grid.spacing, 0.7, 0.6));
    const auto asset = bake("thin slab", slab, grid);
    ASSERT_NE(asset, nullptr);
    const int v = k % 2;
    expectRobust(asset, view(*asset, v), "thin slab K=" + std::to_string(k) + " view " + std::to_string(v));
  }
}

// Why: a spherical shell thinner than a cell is thin in every direction and at every position
// relative to the samples, so some rays pass through both of its surfaces within one segment.
TEST_F(HermiteRootsTest, ThinSphericalShellsAcrossResolutions) {
  for (const int k : sweptResolutions()) {
    const hsdf::GridSpec grid = unitGrid(k);
    const ShellSource shell(0.6, 0.7 * grid.spacing);
    const auto asset = bake("shell", shell, grid);
    ASSERT_NE(asset, nullptr);
    const int v = k % 2;
    expectRobust(asset, view(*asset, v), "shell K=" + std::to_string(k) + " view " + std::to_string(v));
  }
}

// Why: turned by 1e-4 rad, each face crosses its sample plane: f on the plane changes sign across
// the face in steps far below a cell, so neighbouring cells disagree about which of them holds it.
TEST_F(HermiteRootsTest, BoxesRotatedBySmallAngles) {
  const glm::dmat3 rotation = glm::dmat3(glm::rotate(glm::dmat4(1.0), 1e-4, glm::normalize(glm::dvec3(1.0, 2.0, 3.0))));
  for (int k : {8, 13, 16, 24, 32, 33, 47, 64}) {
    if (!selected(k)) continue;
    const hsdf::GridSpec grid = unitGrid(k);
    const RotatedBoxSource box(gridCentre(k), wholeCells(k) * grid.spacing, rotation);
    const auto asset = bake("rotated box", box, grid);
    ASSERT_NE(asset, nullptr);
    const int v = k % 2;  // the two views alternate over K: every face, both parities
    expectRobust(asset, view(*asset, v), "rotated box K=" + std::to_string(k) + " view " + std::to_string(v));
  }
}

// Why: x + y = 0 runs along the z-aligned edges of cells and x + y + z = 0 through sample points
// (for odd K): the surface touches cells at an edge or a corner only, where the classifier's zero
// rule decides whether a cell is kept and rays cross several cells at one point.
TEST_F(HermiteRootsTest, PlanesThroughCellEdgesAndCorners) {
  for (int k : {8, 9, 16, 17, 33, 64, 65}) {
    if (!selected(k)) continue;
    const hsdf::GridSpec grid = unitGrid(k);
    const HalfSpaceSource edges(glm::dvec3(1.0, 1.0, 0.0), 0.0);
    const HalfSpaceSource corners(glm::dvec3(1.0, 1.0, 1.0), 0.0);
    for (const auto* source : {&edges, &corners}) {
      const std::string label = std::string(source == &edges ? "plane through edges" : "plane through corners") +
                                " K=" + std::to_string(k);
      const auto asset = bake(label, *source, grid);
      ASSERT_NE(asset, nullptr);
      // From the positive side of the plane, once straight on and once obliquely.
      const glm::vec3 normal = glm::normalize(glm::vec3(source == &edges ? glm::dvec3(1, 1, 0) : glm::dvec3(1, 1, 1)));
      const glm::vec3 side = glm::normalize(glm::cross(normal, glm::vec3(0.0f, 0.0f, 1.0f) + 0.3f * normal));
      for (const glm::vec3 eye : {3.0f * normal, 2.5f * glm::normalize(normal + 0.9f * side)}) {
        const auto camera = render::CameraView::lookAt(eye, glm::vec3(0.0f), 0.9f, 0.01f, float(kWidth) / float(kHeight));
        expectRobust(asset, camera, label);
      }
    }
  }
}

// Why: a ray 1-3 degrees above a flat face on a sample plane runs along it for many cells with F a
// rounding error from zero, then enters it; every cell along the way must neither see a false root
// nor let the real one through.
TEST_F(HermiteRootsTest, RaysGrazingFlatFaces) {
  for (int k : {8, 16, 24, 33, 64}) {
    if (!selected(k)) continue;
    const hsdf::GridSpec grid = unitGrid(k);
    const glm::dvec3 half = wholeCells(k) * grid.spacing;
    const glm::dvec3 centre = gridCentre(k);
    const hsdf::BoxSource box(centre, half);
    const auto asset = bake("box for grazing rays", box, grid);
    ASSERT_NE(asset, nullptr);
    for (double degrees : {1.0, 3.0}) {
      const double elevation = degrees * 3.14159265358979 / 180.0;
      const glm::vec3 top = glm::vec3(centre + glm::dvec3(0.0, half.y, 0.0));
      const glm::vec3 eye = top + glm::vec3(0.3f, float(3.0 * std::tan(elevation)), 3.0f);
      const auto camera = render::CameraView::lookAt(eye, top, 0.9f, 0.01f,
                                                     float(kWidth) / float(kHeight));
      expectRobust(asset, camera, "grazing " + std::to_string(int(degrees)) + " deg K=" + std::to_string(k));
    }
  }
}

}  // namespace
}  // namespace gputest
