// The bundled bunny, imported from glTF and rendered headless, against a CPU ray cast of the same
// triangles: the GPU image must cover the same pixels at the same depths.
#include <cmath>
#include <limits>
#include <optional>

#include <gtest/gtest.h>

#include "engine/core/math.h"
#include "engine/render/scene_instantiate.h"
#include "engine/scene/gltf_loader.h"
#include "engine/scene/transform.h"
#include "gpu_test_support.h"

namespace gputest {
namespace {

using namespace engine;

// Möller–Trumbore in double; returns the ray parameter of the hit.
std::optional<double> intersectTriangle(const math::Ray& ray, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 e1 = b - a, e2 = c - a;
  const glm::dvec3 p = glm::cross(ray.direction, e2);
  const double det = glm::dot(e1, p);
  if (std::abs(det) < 1e-14) return std::nullopt;
  const double inv = 1.0 / det;
  const glm::dvec3 s = ray.origin - a;
  const double u = glm::dot(s, p) * inv;
  if (u < 0.0 || u > 1.0) return std::nullopt;
  const glm::dvec3 q = glm::cross(s, e1);
  const double v = glm::dot(ray.direction, q) * inv;
  if (v < 0.0 || u + v > 1.0) return std::nullopt;
  const double t = glm::dot(e2, q) * inv;
  return t > 0.0 ? std::optional<double>(t) : std::nullopt;
}

// Reverse-Z depth of the nearest triangle along each pixel's ray (0 where nothing is hit).
std::vector<float> rayCastDepth(const scene::TriangleSoup& soup, const render::CameraView& camera, std::uint32_t w,
                                std::uint32_t h) {
  std::vector<float> depth(std::size_t(w) * h, 0.0f);
  const glm::dvec3 forward = -glm::dvec3(glm::inverse(camera.view)[2]);
  for (std::uint32_t y = 0; y < h; ++y) {
    for (std::uint32_t x = 0; x < w; ++x) {
      const math::Ray ray = math::pixelRay(camera.view, camera.proj, {float(x) + 0.5f, float(y) + 0.5f},
                                           {int(w), int(h)});
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i + 2 < soup.indices.size(); i += 3) {
        const auto t = intersectTriangle(ray, soup.positions[soup.indices[i]], soup.positions[soup.indices[i + 1]],
                                         soup.positions[soup.indices[i + 2]]);
        if (t && *t < best) best = *t;
      }
      if (std::isfinite(best))
        depth[std::size_t(y) * w + x] = float(math::viewDistanceToDepth(best * glm::dot(ray.direction, forward), camera.znear));
    }
  }
  return depth;
}

// Why: exercises the whole path file -> importer -> entities -> mesh pool -> indirect draws ->
// depth prepass; a wrong node transform, index offset or winding shows as a coverage difference.
TEST_F(GpuTest, BunnyMatchesCpuRayCastOfItsTriangles) {
  auto data = scene::loadGltf(std::filesystem::path(HSDF_ASSET_DIR) / "bunny.glb");
  ASSERT_TRUE(data.ok()) << data.error().message;
  const render::InstantiatedScene instantiated = render::instantiateScene(*data, registry_, *pool_);
  ASSERT_FALSE(instantiated.renderables.empty());
  const scene::TriangleSoup soup = scene::flattenTriangles(*data);

  const std::uint32_t w = 96, h = 96;
  createRenderer(w, h);
  const glm::vec3 center = 0.5f * (instantiated.boundsMin + instantiated.boundsMax);
  const float radius = 0.5f * glm::length(instantiated.boundsMax - instantiated.boundsMin);
  for (const float yaw : {0.3f, 2.5f}) {
    SCOPED_TRACE("yaw " + std::to_string(yaw));
    const glm::vec3 eye = math::orbitEye(center, 2.2f * radius, yaw, 0.3f);
    const render::CameraView camera = render::CameraView::lookAt(eye, center, 0.8f, 0.01f * radius, 1.0f);
    const Frame frame = render(camera);
    const std::vector<float> reference = rayCastDepth(soup, camera, w, h);

    int covered = 0, disagree = 0, interiorDisagree = 0;
    double maxRelativeDepthError = 0.0;
    for (std::uint32_t y = 1; y + 1 < h; ++y) {
      for (std::uint32_t x = 1; x + 1 < w; ++x) {
        const float ref = reference[y * w + x];
        const float gpu = frame.depthAt(x, y);
        if (ref > 0.0f) ++covered;
        if ((ref > 0.0f) == (gpu > 0.0f)) {
          if (ref > 0.0f) maxRelativeDepthError = std::max(maxRelativeDepthError, double(std::abs(gpu - ref) / ref));
          continue;
        }
        ++disagree;
        // A disagreement is allowed only on the silhouette: some 8-neighbour differs in the reference.
        bool silhouette = false;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            silhouette |= (reference[(y + dy) * w + (x + dx)] > 0.0f) != (ref > 0.0f);
        if (!silhouette) ++interiorDisagree;
      }
    }
    EXPECT_GT(covered, int(w * h) / 10);
    EXPECT_LT(double(disagree) / covered, 0.02);
    EXPECT_EQ(interiorDisagree, 0);
    // Same triangles, same rays: depth differs only by float rasterization and interpolation.
    EXPECT_LT(maxRelativeDepthError, 2e-3);
  }
}

}  // namespace
}  // namespace gputest
