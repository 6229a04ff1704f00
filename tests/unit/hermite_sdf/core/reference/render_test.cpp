// CPU reference images: reverse-Z depth, normals, hit mask, cell ids, PNG output, bad cameras.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include <glm/gtc/matrix_transform.hpp>

#include "test_files.h"
#include "engine/core/image_io.h"
#include "engine/core/math.h"
#include "hermite_sdf/core/reference.h"

namespace hsdf {
namespace {

using glm::dvec3;

// Same exactly-represented quadric sphere as in caster_test (centre (1,1,1), radius 3/4).
HermiteField quadricSphereField() {
  HermiteField field;
  field.grid.resolution = 9;
  field.grid.spacing = 0.25;
  field.samples.resize(field.grid.sampleCount());
  for (int z = 0; z < 9; ++z)
    for (int y = 0; y < 9; ++y)
      for (int x = 0; x < 9; ++x) {
        const dvec3 d = field.grid.samplePosition(x, y, z) - dvec3(1.0);
        field.samples[field.grid.sampleIndex(x, y, z)] = {float(glm::dot(d, d) - 0.5625), float(2.0 * d.x),
                                                          float(2.0 * d.y), float(2.0 * d.z)};
      }
  return field;
}

// Where a ray meets the quadric sphere: t = -b -+ sqrt(disc) (no crossing when disc < 0).
struct SphereCrossing {
  double b, disc;
};
SphereCrossing crossSphere(const Ray& ray) {
  const dvec3 oc = ray.origin - dvec3(1.0);
  const double b = glm::dot(oc, ray.direction);
  return {b, b * b - (glm::dot(oc, oc) - 0.5625)};
}

struct Camera {
  glm::mat4 view, proj;
  glm::ivec2 size{33, 25};  // odd: the centre pixel's ray is the view axis
  float znear = 0.1f;
};

Camera frontCamera(float znear = 0.1f) {
  Camera c;
  c.znear = znear;
  c.view = engine::math::lookAt({1.2f, 1.1f, 4.0f}, {1.0f, 1.0f, 1.0f}, {0.0f, 1.0f, 0.0f});
  c.proj = engine::math::perspectiveReverseZInfinite(0.7f, float(c.size.x) / float(c.size.y), c.znear);
  return c;
}

// Tricky: depth must be what the GPU writes for reverse-Z (znear / distance along the view axis,
// not along the ray), checked per pixel against the exact sphere through engine::math's own
// conversion; normals, hit mask and cell ids likewise, except for silhouette pixels.
TEST(ReferenceRender, MatchesTheExactSurfacePerPixel) {
  const HermiteField field = quadricSphereField();
  const Camera cam = frontCamera();
  auto image = renderReference(field, cam.view, cam.proj, cam.size);
  ASSERT_TRUE(image.ok()) << image.error().message;
  ASSERT_EQ(image->depth.size(), std::size_t(33 * 25));
  const glm::dmat4 view(cam.view);
  int hits = 0, checked = 0;
  for (int y = 0; y < cam.size.y; ++y)
    for (int x = 0; x < cam.size.x; ++x) {
      const Ray ray = engine::math::pixelRay(cam.view, cam.proj, {float(x) + 0.5f, float(y) + 0.5f}, cam.size);
      const auto [b, disc] = crossSphere(ray);
      if (std::abs(disc) < 1e-6) continue;  // silhouette: either answer is right
      ++checked;
      const std::size_t p = image->pixel(x, y);
      ASSERT_EQ(image->hit[p] != 0, disc > 0.0) << x << "," << y;
      if (disc < 0.0) {
        EXPECT_EQ(image->depth[p], 0.0f);
        EXPECT_EQ(image->cellId[p], -1);
        continue;
      }
      ++hits;
      const dvec3 point = ray.origin + (-b - std::sqrt(disc)) * ray.direction;
      const double viewDistance = -(view * glm::dvec4(point, 1.0)).z;
      EXPECT_NEAR(image->depth[p], engine::math::viewDistanceToDepth(viewDistance, cam.znear), 1e-6);
      EXPECT_NEAR(glm::dot(glm::dvec3(image->normal[p]), glm::normalize(point - dvec3(1.0))), 1.0, 1e-6);
      const glm::ivec3 cell = glm::clamp(glm::ivec3(glm::floor(point / 0.25)), glm::ivec3(0), glm::ivec3(7));
      const int id = cell.x + 8 * (cell.y + 8 * cell.z);
      const bool onCellFace = glm::any(glm::greaterThan(glm::abs(glm::fract(point / 0.25) - 0.5), glm::dvec3(0.49)));
      if (!onCellFace) {
        EXPECT_EQ(image->cellId[p], id) << x << "," << y;
      }
    }
  EXPECT_GT(hits, 100);
  EXPECT_GT(checked, 700);
  // the centre pixel looks straight at the sphere: depth = znear / (|eye - c| - r)
  const float centre = image->depth[image->pixel(16, 12)];
  EXPECT_NEAR(centre, 0.1 / (std::sqrt(0.04 + 0.01 + 9.0) - 0.75), 1e-6);
}

// Tricky: rendering only kept cells (what the GPU draws) must give the same image bit for bit,
// and the work split over threads must not change any pixel.
// Tricky: a near plane through the sphere. The GPU clips everything nearer than the near plane, so
// where it cuts the front of the sphere a pixel shows the inside of the back (the first root behind
// the plane, its normal facing away from the eye), and where the whole sphere along the ray lies in
// front of it, nothing. A reference that casts from the eye draws the clipped front there instead.
TEST(ReferenceRender, RaysStartAtTheNearPlane) {
  const HermiteField field = quadricSphereField();
  const Camera cam = frontCamera(2.6f);  // the sphere: entry ~2.26, exit ~3.76 on the axis; its rim ~2.8 away
  auto image = renderReference(field, cam.view, cam.proj, cam.size);
  ASSERT_TRUE(image.ok()) << image.error().message;
  const glm::dmat4 view(cam.view);
  int backHits = 0, frontHits = 0;
  for (int y = 0; y < cam.size.y; ++y)
    for (int x = 0; x < cam.size.x; ++x) {
      const Ray ray = engine::math::pixelRay(cam.view, cam.proj, {float(x) + 0.5f, float(y) + 0.5f}, cam.size);
      const auto [b, disc] = crossSphere(ray);
      if (disc < 1e-6) continue;  // a miss or a silhouette
      const auto viewDistance = [&](double t) { return -(view * glm::dvec4(ray.origin + t * ray.direction, 1.0)).z; };
      const double entry = -b - std::sqrt(disc), exit = -b + std::sqrt(disc);
      const std::size_t p = image->pixel(x, y);
      if (std::abs(viewDistance(entry) - double(cam.znear)) < 1e-3 || std::abs(viewDistance(exit) - double(cam.znear)) < 1e-3)
        continue;  // a root on the plane itself: either answer is right
      if (viewDistance(exit) < double(cam.znear)) {
        EXPECT_EQ(image->hit[p], 0) << x << "," << y << ": the sphere lies wholly in front of the near plane";
        continue;
      }
      const bool back = viewDistance(entry) < double(cam.znear);
      const double t = back ? exit : entry;
      ASSERT_EQ(image->hit[p], 1) << x << "," << y;
      EXPECT_NEAR(image->depth[p], engine::math::viewDistanceToDepth(viewDistance(t), cam.znear), 1e-6) << x << "," << y;
      const double facing = glm::dot(glm::dvec3(image->normal[p]), ray.direction);
      EXPECT_EQ(facing > 0.0, back) << x << "," << y << ": the back's normal faces away from the eye";
      (back ? backHits : frontHits) += 1;
    }
  EXPECT_GT(backHits, 50);
  EXPECT_GT(frontHits, 10);
}

TEST(ReferenceRender, KeptCellsAndThreadCountDoNotChangeTheImage) {
  const HermiteField field = quadricSphereField();
  auto cells = classifyCells(field, {});
  ASSERT_TRUE(cells.ok());
  const Camera cam = frontCamera();
  RenderOptions one;
  one.threads = 1;
  auto full = renderReference(field, cam.view, cam.proj, cam.size, nullptr, one);
  auto kept = renderReference(field, cam.view, cam.proj, cam.size, &*cells);
  ASSERT_TRUE(full.ok() && kept.ok());
  EXPECT_EQ(full->depth, kept->depth);
  EXPECT_EQ(full->normal, kept->normal);
  EXPECT_EQ(full->hit, kept->hit);
  EXPECT_EQ(full->cellId, kept->cellId);
}

// Tricky: the trilinear image of the same samples differs (the trilinear interpolant is not the
// sphere) but must be close: centre depth within the O(h^2) trilinear error.
TEST(ReferenceRender, RendersTrilinearFields) {
  const HermiteField hermite = quadricSphereField();
  TrilinearField trilinear;
  trilinear.grid = hermite.grid;
  for (const HermiteSample& s : hermite.samples) trilinear.values.push_back(s.f);
  const Camera cam = frontCamera();
  auto image = renderReference(trilinear, cam.view, cam.proj, cam.size);
  ASSERT_TRUE(image.ok());
  const double exactDistance = std::sqrt(0.04 + 0.01 + 9.0) - 0.75;
  const double distance = 0.1 / double(image->depth[image->pixel(16, 12)]);
  EXPECT_NEAR(distance, exactDistance, 0.25 * 0.25);
  EXPECT_NE(distance, exactDistance);
}

// Tricky: zero-sized images, non-finite or singular matrices must be errors, not NaN images.
TEST(ReferenceRender, RejectsBadCameras) {
  const HermiteField field = quadricSphereField();
  const Camera cam = frontCamera();
  EXPECT_FALSE(renderReference(field, cam.view, cam.proj, {0, 10}).ok());
  EXPECT_FALSE(renderReference(field, cam.view, cam.proj, {20000, 10}).ok());
  glm::mat4 broken = cam.view;
  broken[1][2] = std::nanf("");
  EXPECT_FALSE(renderReference(field, broken, cam.proj, cam.size).ok());
  auto singular = renderReference(field, glm::mat4(0.0f), cam.proj, cam.size);
  ASSERT_FALSE(singular.ok());
  EXPECT_NE(singular.error().message.find("singular"), std::string::npos);
}

// Tricky: an object placed by a mirroring, rotated, non-uniformly scaled matrix: the quadric
// sphere becomes an ellipsoid in world space. Each pixel's first hit is solved in closed form
// in world space (the ellipsoid's quadratic along the world ray); the world normal is the
// central-difference gradient of the world implicit function, so neither the ray transform nor the
// inverse-transpose normal of the renderer is reused. A renderer that ignored the model or
// transformed normals by the model itself would miss these by far more than 1e-5.
TEST(ReferenceRender, ModelMatrixPlacesTheFieldInWorldSpace) {
  const HermiteField field = quadricSphereField();
  const Camera cam = frontCamera();
  glm::mat4 model = glm::translate(glm::mat4(1.0f), glm::vec3(0.3f, -0.2f, 0.1f));
  model = glm::rotate(model, 0.7f, glm::normalize(glm::vec3(1.0f, 2.0f, 0.5f)));
  model = glm::scale(model, glm::vec3(-0.9f, 1.3f, 0.5f));
  model = glm::translate(model, glm::vec3(-1.0f));  // the sphere's centre at the pivot
  RenderOptions options;
  options.model = model;
  auto image = renderReference(field, cam.view, cam.proj, cam.size, nullptr, options);
  ASSERT_TRUE(image.ok()) << image.error().message;
  const glm::dmat4 inverse = glm::inverse(glm::dmat4(model));
  // g(x) = |M^-1 x - c|^2 - r^2: the world-space implicit function of the ellipsoid.
  auto g = [&](const dvec3& x) {
    const dvec3 d = dvec3(inverse * glm::dvec4(x, 1.0)) - dvec3(1.0);
    return glm::dot(d, d) - 0.5625;
  };
  const glm::dmat4 view(cam.view);
  int hits = 0, checked = 0;
  for (int y = 0; y < cam.size.y; ++y)
    for (int x = 0; x < cam.size.x; ++x) {
      const Ray ray = engine::math::pixelRay(cam.view, cam.proj, {float(x) + 0.5f, float(y) + 0.5f}, cam.size);
      // g along the ray is a quadratic a t^2 + b t + c; recover it from three samples.
      const double g0 = g(ray.origin), g1 = g(ray.origin + ray.direction), gm = g(ray.origin - ray.direction);
      const double a = 0.5 * (g1 + gm) - g0, b = 0.5 * (g1 - gm), c = g0;
      const double disc = b * b - 4.0 * a * c;
      if (std::abs(disc) < 1e-6 * b * b) continue;  // silhouette
      ++checked;
      const std::size_t p = image->pixel(x, y);
      ASSERT_EQ(image->hit[p] != 0, disc > 0.0) << x << "," << y;
      if (disc < 0.0) continue;
      ++hits;
      const double t = (-b - std::sqrt(disc)) / (2.0 * a);
      const dvec3 point = ray.origin + t * ray.direction;
      const double viewDistance = -(view * glm::dvec4(point, 1.0)).z;
      EXPECT_NEAR(image->depth[p], engine::math::viewDistanceToDepth(viewDistance, cam.znear), 1e-5);
      const double e = 1e-6;
      const dvec3 gradient(g(point + dvec3(e, 0, 0)) - g(point - dvec3(e, 0, 0)),
                           g(point + dvec3(0, e, 0)) - g(point - dvec3(0, e, 0)),
                           g(point + dvec3(0, 0, e)) - g(point - dvec3(0, 0, e)));
      EXPECT_NEAR(glm::dot(glm::dvec3(image->normal[p]), glm::normalize(gradient)), 1.0, 1e-5) << x << "," << y;
    }
  EXPECT_GT(hits, 60);
  EXPECT_GT(checked, 700);

  // A model that cannot be inverted (or is not affine) is an error naming the model.
  options.model = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 0.0f, 1.0f));
  auto singular = renderReference(field, cam.view, cam.proj, cam.size, nullptr, options);
  ASSERT_FALSE(singular.ok());
  EXPECT_NE(singular.error().message.find("model matrix is singular"), std::string::npos);
  options.model = glm::mat4(1.0f);
  options.model[0][3] = 0.5f;
  EXPECT_FALSE(renderReference(field, cam.view, cam.proj, cam.size, nullptr, options).ok());
}

// Tricky: the PNGs must encode what the arrays say: nearest hit white in the depth image, misses
// black, and the normal facing the camera ~ (128, 128, 255).
TEST(ReferenceRender, WritesDepthAndNormalPngs) {
  const HermiteField field = quadricSphereField();
  const Camera cam = frontCamera();
  auto image = renderReference(field, cam.view, cam.proj, cam.size);
  ASSERT_TRUE(image.ok());
  const hsdftest::ScopedTempPath folder("reference_render_test");  // its own: tests run side by side
  const std::filesystem::path& dir = folder.path();
  std::filesystem::create_directories(dir);
  ASSERT_TRUE(writeDepthPng(*image, dir / "depth.png").ok());
  ASSERT_TRUE(writeNormalPng(*image, dir / "normal.png").ok());
  auto depth = engine::readPng(dir / "depth.png");
  auto normal = engine::readPng(dir / "normal.png");
  ASSERT_TRUE(depth.ok() && normal.ok());
  ASSERT_EQ(depth->width, 33u);
  ASSERT_EQ(depth->height, 25u);
  std::uint8_t brightest = 0;
  for (std::size_t p = 0; p < image->hit.size(); ++p) brightest = std::max(brightest, depth->rgba[4 * p]);
  EXPECT_EQ(brightest, 255);
  EXPECT_EQ(depth->rgba[0], 0);  // top-left corner: a miss
  const std::size_t centre = 4 * image->pixel(16, 12);
  EXPECT_GE(depth->rgba[centre], 250);
  EXPECT_NEAR(normal->rgba[centre + 2], 255, 3);
  EXPECT_NEAR(normal->rgba[centre + 0], 128, 12);
}

}  // namespace
}  // namespace hsdf
