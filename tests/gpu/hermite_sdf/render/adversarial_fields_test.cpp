// Adversarial fields (numerical robustness) drawn by every method — Hermite cells,
// trilinear and Hermite sphere tracing — on lavapipe with the validation layers on: zero gradients
// everywhere, values of 1e30, a surface tangent to a cell face, rays along cell edges and through
// cell corners. Each frame must finish (a shader loop that does not terminate hangs lavapipe and
// the ctest times out), leave no validation message, write only finite depths inside the grid's
// screen footprint, and match the CPU reference ray caster of its interpolant where the method's
// premise holds (the sphere tracers assume |f| bounds the distance: see each case).
//
// The fields are built sample by sample (not baked): a baker would never produce them, a file or a
// user's generator may. K = 8, spacing 1, grid [0, 7]^3; images 63x63 (odd, so that the centre
// pixel's ray is exactly the camera's axis and can be aimed along a cell edge or diagonal).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "engine/core/math.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/core/field.h"
#include "hermite_sdf/render/features.h"
#include "hermite_sdf/render/sphere_trace_feature.h"
#include "device_tolerances.h"
#include "hermite_test_support.h"
#include "shared/host_device.h"

namespace gputest {
namespace {

using namespace engine;
using hsdf::RenderMethod;

constexpr std::uint32_t kSize = 63;
constexpr int kResolution = 8;
bool cellMethod(RenderMethod method) {
  return method == RenderMethod::Cells || method == RenderMethod::CellRuns || method == RenderMethod::CellBricks;
}

// A field with sample (i, j, k) = sample(position).
hsdf::HermiteField makeField(const std::function<hsdf::HermiteSample(const glm::dvec3&)>& sample) {
  hsdf::HermiteField field;
  field.grid.resolution = kResolution;
  field.grid.origin = glm::dvec3(0.0);
  field.grid.spacing = 1.0;
  field.samples.resize(field.grid.sampleCount());
  for (int k = 0; k < kResolution; ++k)
    for (int j = 0; j < kResolution; ++j)
      for (int i = 0; i < kResolution; ++i)
        field.samples[field.grid.sampleIndex(i, j, k)] = sample(field.grid.samplePosition(i, j, k));
  return field;
}

// The exact distance to a sphere and its gradient.
hsdf::HermiteSample sphereSample(const glm::dvec3& p, const glm::dvec3& center, double radius) {
  const glm::dvec3 d = p - center;
  const double length = glm::length(d);
  const glm::dvec3 g = length > 0.0 ? d / length : glm::dvec3(0.0, 0.0, 1.0);
  return {float(length - radius), float(g.x), float(g.y), float(g.z)};
}

struct Case {
  std::string label;
  hsdf::HermiteField field;
  render::CameraView camera;
  // Methods whose output must match the reference: the sphere tracers only where |f| bounds the
  // distance to the surface (else a step can jump over it, which is the method, not a bug).
  bool tracersMatch = true;
  // Whether the cells' normals must match too (see HugeValues for the case where they do not).
  bool cellNormalsMatch = true;
};

render::CameraView lookAt(const glm::vec3& eye, const glm::vec3& target) {
  return render::CameraView::lookAt(eye, target, 0.9f, 0.05f, 1.0f);
}

class AdversarialFieldsTest : public GpuTest {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    createRenderer(kSize, kSize);
    const Status added = hsdf::addRenderFeatures(*renderer_);
    ASSERT_TRUE(added.ok()) << added.error().message;
  }

  // Draws `c` with every method and checks the frame (header comment).
  void expectBoundedAndMatching(const Case& c) {
    auto asset = hsdf::makeSdfAsset(c.label, c.field, c.field.grid.bounds());
    ASSERT_TRUE(asset.ok()) << asset.error().message;
    const ecs::Entity entity = addSdf(registry_, *asset, RenderMethod::Cells);
    const hsdf::ReferenceImage hermiteReference = reference(c, &(*asset)->classification, nullptr);
    const hsdf::TrilinearField trilinear = trilinearOf(c.field);
    const hsdf::ReferenceImage trilinearReference = reference(c, nullptr, &trilinear);
    const DeviceTolerances tolerance = tolerancesFor(*context_);
    for (const RenderMethod method : hsdf::kRenderMethods) {
      const std::string where = c.label + ", " + hsdf::renderMethodName(method);
      registry_.get<hsdf::HermiteSdfRenderable>(entity).method = method;
      const Frame normals = renderWith(c.camera, DEBUG_VIEW_NORMALS);
      expectBounded(normals, c, where);
      const hsdf::ReferenceImage& ref =
          method == RenderMethod::TrilinearSphereTrace ? trilinearReference : hermiteReference;
      const ImageComparison cmp = compareWithReference(normals, &normals.rgba, ref, c.camera, 1.0);
      std::printf("[ %s ] hits ref %d gpu %d, disagree %d, holes %d, extras %d, interior depth err p99 %.2e cells, "
                  "normal err p99 %.2f deg\n",
                  where.c_str(), cmp.referenceHits, cmp.gpuHits, cmp.disagreements, cmp.interiorHoles,
                  cmp.interiorExtras, cmp.interiorDepthErrorP99, cmp.normalErrorP99Degrees);
      if (!cellMethod(method) && !c.tracersMatch) continue;
      EXPECT_GT(cmp.referenceHits, 100) << where << ": too little surface in view to mean anything";
      EXPECT_EQ(cmp.interiorHoles, 0) << where;
      EXPECT_EQ(cmp.interiorExtras, 0) << where;
      EXPECT_GE(cmp.agreement(int(kSize * kSize)), 1.0 - tolerance.adversarialCoverageDisagreement) << where;
      EXPECT_LT(cmp.interiorDepthErrorP99, tolerance.adversarialInteriorDepthP99Cells) << where;
      if (!cellMethod(method) || c.cellNormalsMatch) {
        EXPECT_LT(cmp.normalErrorP99Degrees, 2.0) << where;
      }
    }
    registry_.destroy(entity);
  }

  hsdf::ReferenceImage reference(const Case& c, const hsdf::CellClassification* cells,
                                 const hsdf::TrilinearField* trilinear) {
    auto image = trilinear ? hsdf::renderReference(*trilinear, c.camera.view, c.camera.proj, {int(kSize), int(kSize)})
                           : hsdf::renderReference(c.field, c.camera.view, c.camera.proj, {int(kSize), int(kSize)},
                                                   cells);
    EXPECT_TRUE(image.ok()) << image.error().message;
    return image.ok() ? std::move(*image) : hsdf::ReferenceImage{};
  }

  // Every depth finite and in [0, 1]; every hit inside the screen footprint of the grid's box
  // (plus a pixel): a shader that ran away with NaN or inf writes elsewhere or garbage.
  static void expectBounded(const Frame& frame, const Case& c, const std::string& where) {
    glm::vec2 lo(1e9f), hi(-1e9f);
    bool behind = false;
    const hsdf::Aabb box = c.field.grid.bounds();
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 p(corner & 1 ? box.max.x : box.min.x, corner & 2 ? box.max.y : box.min.y,
                        corner & 4 ? box.max.z : box.min.z);
      const glm::vec4 clip = c.camera.proj * c.camera.view * glm::vec4(p, 1.0f);
      if (clip.w <= 0.0f) {
        behind = true;
        continue;
      }
      const glm::vec2 ndc = glm::vec2(clip) / clip.w;
      const glm::vec2 pixel = (ndc * 0.5f + 0.5f) * float(kSize);
      lo = glm::min(lo, pixel);
      hi = glm::max(hi, pixel);
    }
    int nonFinite = 0, outside = 0;
    for (std::uint32_t y = 0; y < frame.height; ++y) {
      for (std::uint32_t x = 0; x < frame.width; ++x) {
        const float depth = frame.depthAt(x, y);
        if (!std::isfinite(depth) || depth < 0.0f || depth > 1.0f) ++nonFinite;
        if (depth <= 0.0f || behind) continue;
        // The projection's y may point either way: test both row conventions.
        const float px = float(x) + 0.5f, py = float(y) + 0.5f, flipped = float(kSize) - py;
        const bool inX = px >= lo.x - 1.0f && px <= hi.x + 1.0f;
        const bool inY = (py >= lo.y - 1.0f && py <= hi.y + 1.0f) || (flipped >= lo.y - 1.0f && flipped <= hi.y + 1.0f);
        if (!inX || !inY) ++outside;
      }
    }
    EXPECT_EQ(nonFinite, 0) << where << ": depths that are not finite or outside [0, 1]";
    EXPECT_EQ(outside, 0) << where << ": hits outside the grid's screen footprint";
  }
};

// Zero gradients everywhere with values z - 3.5: the Hermite interpolant becomes a smoothstep in
// z (flat at every sample), so Newton steps and gradient-based normals divide by ~0 at the samples,
// and the cells' gradient records are all zero. The surface is still the plane z = 3.5 (between
// two sample planes). The sphere tracers' premise holds (|f| <= distance * 1.5: a smoothstep's
// slope is at most 1.5, and they step by f, which underestimates here).
TEST_F(AdversarialFieldsTest, ZeroGradientsEverywhere) {
  Case c{"zero gradients",
         makeField([](const glm::dvec3& p) { return hsdf::HermiteSample{float(p.z - 3.5), 0.0f, 0.0f, 0.0f}; }),
         lookAt({3.3f, -4.0f, 9.0f}, {3.5f, 3.5f, 3.5f})};
  expectBoundedAndMatching(c);
}

// Values of +-1e30 (a step between two sample planes) with gradients of 1e30: squares and products
// of these overflow float, the interpolant's coefficients are ~1e30. Cells must still find the
// root (coverage and depth match the reference) and stay finite; the sphere tracers step by f,
// which is no distance bound (one step leaves the grid): they must stay bounded and finish (they
// draw nothing), not match. The cells' normals must match too: the squared length of a 1e30
// gradient overflows float, so the resolve scales the gradient by its largest component before
// normalizing (without that the normals were the normalized (1,1,1), 54.7 degrees off).
TEST_F(AdversarialFieldsTest, HugeValues) {
  Case c{"huge values", makeField([](const glm::dvec3& p) {
           return hsdf::HermiteSample{p.z < 3.5 ? -1e30f : 1e30f, 0.0f, 0.0f, 1e30f};
         }),
         lookAt({3.3f, -4.0f, 9.0f}, {3.5f, 3.5f, 3.5f}), false, true};
  expectBoundedAndMatching(c);
}

// A sphere whose top touches the sample plane z = 5 at one point (centre z = 3, radius 2): the
// cells above it see f >= 0 with a double root on their face, the cells below a sign change that
// ends on it. Seen from above, the camera looks straight at the tangent point.
TEST_F(AdversarialFieldsTest, SurfaceTangentToACellFace) {
  const glm::dvec3 center(3.5, 3.5, 3.0);
  Case c{"tangent to a cell face", makeField([&](const glm::dvec3& p) { return sphereSample(p, center, 2.0); }),
         lookAt({3.5f, 2.0f, 12.0f}, {3.5f, 3.5f, 3.0f})};
  expectBoundedAndMatching(c);
}

// The centre pixel's ray runs exactly along the cell edge x = y = 3 (the camera's axis), its
// neighbours along cell faces: the cell walk steps through edges where two or four cells meet, and
// the plane z = 3.5 (a sphere would do as well) is met inside that edge.
TEST_F(AdversarialFieldsTest, RaysAlongCellEdges) {
  const glm::dvec3 center(3.0, 3.0, 3.5);
  Case c{"rays along cell edges", makeField([&](const glm::dvec3& p) { return sphereSample(p, center, 2.5); }),
         lookAt({3.0f, 3.0f, 12.0f}, {3.0f, 3.0f, 0.0f})};
  expectBoundedAndMatching(c);
}

// The centre pixel's ray is the grid diagonal: it passes exactly through the corners (i, i, i),
// where eight cells meet, and enters the sphere (centre on the diagonal) there.
TEST_F(AdversarialFieldsTest, RaysThroughCellCorners) {
  const glm::dvec3 center(4.0, 4.0, 4.0);
  Case c{"rays through cell corners",
         makeField([&](const glm::dvec3& p) { return sphereSample(p, center, 2.0 * std::sqrt(3.0)); }),
         lookAt({-4.0f, -4.0f, -4.0f}, {4.0f, 4.0f, 4.0f})};
  expectBoundedAndMatching(c);
}

}  // namespace
}  // namespace gputest
