// The bundled bunny, imported from glTF and rendered headless, against a CPU ray cast of the same
// triangles: the GPU image must cover the same pixels at the same depths.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "engine/core/math.h"
#include "engine/render/scene_instantiate.h"
#include "engine/scene/gltf/gltf_loader.h"
#include "engine/scene/transform.h"
#include "device_tolerances.h"
#include "gpu_test_support.h"
#include "shared/host_device.h"

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

// What a CPU ray cast of a triangle soup sees per pixel.
struct RayCastImage {
  std::vector<float> depth;         // reverse-Z depth of the nearest triangle; 0 where nothing is hit
  std::vector<glm::dvec3> normal;   // its unit geometric normal by its winding (outward for soups
                                    // from flattenTriangles, which undoes mirroring)
};

RayCastImage rayCast(const scene::TriangleSoup& soup, const render::CameraView& camera, std::uint32_t w, std::uint32_t h) {
  RayCastImage image{std::vector<float>(std::size_t(w) * h, 0.0f), std::vector<glm::dvec3>(std::size_t(w) * h)};
  const glm::dvec3 forward = -glm::dvec3(glm::inverse(camera.view)[2]);
  for (std::uint32_t y = 0; y < h; ++y) {
    for (std::uint32_t x = 0; x < w; ++x) {
      const math::Ray ray = math::pixelRay(camera.view, camera.proj, {float(x) + 0.5f, float(y) + 0.5f},
                                           {int(w), int(h)});
      double best = std::numeric_limits<double>::infinity();
      std::size_t bestTriangle = 0;
      for (std::size_t i = 0; i + 2 < soup.indices.size(); i += 3) {
        const auto t = intersectTriangle(ray, soup.positions[soup.indices[i]], soup.positions[soup.indices[i + 1]],
                                         soup.positions[soup.indices[i + 2]]);
        if (t && *t < best) {
          best = *t;
          bestTriangle = i;
        }
      }
      if (!std::isfinite(best)) continue;
      const std::size_t p = std::size_t(y) * w + x;
      image.depth[p] = float(math::viewDistanceToDepth(best * glm::dot(ray.direction, forward), camera.znear));
      const glm::dvec3 a = soup.positions[soup.indices[bestTriangle]], b = soup.positions[soup.indices[bestTriangle + 1]],
                       c = soup.positions[soup.indices[bestTriangle + 2]];
      image.normal[p] = glm::normalize(glm::cross(b - a, c - a));
    }
  }
  return image;
}

std::pair<glm::vec3, glm::vec3> soupBounds(const scene::TriangleSoup& soup) {
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
  for (const glm::vec3& p : soup.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return {lo, hi};
}

// A camera 2.2 bounding radii from the centre of the soup's bounds, looking at it.
render::CameraView orbitCamera(const scene::TriangleSoup& soup, float yaw) {
  const auto [lo, hi] = soupBounds(soup);
  const glm::vec3 center = 0.5f * (lo + hi);
  const float radius = 0.5f * glm::length(hi - lo);
  const glm::vec3 eye = math::orbitEye(center, 2.2f * radius, yaw, 0.3f);
  return render::CameraView::lookAt(eye, center, 0.8f, 0.01f * radius, 1.0f);
}

// The GPU frame (and, if given, its DEBUG_VIEW_NORMALS rendering) against the ray cast.
// A coverage disagreement is allowed only on the silhouette (some 8-neighbour differs in the
// reference); same triangles and same rays give depths equal up to float rasterization, except on
// the silhouette, where the surface grazes the ray and the rasterizer may pick the neighbouring
// triangle of the one the cast hits. `minCovered`: enough pixels for the checks to mean something.
void expectMatchesRayCast(const Frame& frame, const Frame* normals, const RayCastImage& reference, int minCovered = 0) {
  const std::uint32_t w = frame.width, h = frame.height;
  int covered = 0, disagree = 0, interiorDisagree = 0, normalsChecked = 0, normalsFacingAway = 0;
  double maxRelativeDepthError = 0.0, maxSilhouetteDepthError = 0.0;
  std::vector<double> normalErrors;
  for (std::uint32_t y = 0; y < h; ++y) {
    for (std::uint32_t x = 0; x < w; ++x) {
      const std::size_t p = std::size_t(y) * w + x;
      const float ref = reference.depth[p];
      const float gpu = frame.depthAt(x, y);
      if (ref > 0.0f) ++covered;
      bool silhouette = false;  // some 8-neighbour inside the image differs in the reference
      for (std::uint32_t ny = y == 0 ? 0 : y - 1; ny <= std::min(y + 1, h - 1); ++ny)
        for (std::uint32_t nx = x == 0 ? 0 : x - 1; nx <= std::min(x + 1, w - 1); ++nx)
          silhouette |= (reference.depth[std::size_t(ny) * w + nx] > 0.0f) != (ref > 0.0f);
      if ((ref > 0.0f) != (gpu > 0.0f)) {
        ++disagree;
        if (!silhouette) ++interiorDisagree;
        continue;
      }
      if (ref <= 0.0f) continue;
      const double relativeError = double(std::abs(gpu - ref) / ref);
      (silhouette ? maxSilhouetteDepthError : maxRelativeDepthError) =
          std::max(silhouette ? maxSilhouetteDepthError : maxRelativeDepthError, relativeError);
      if (!normals || silhouette) continue;
      // Interpolated vertex normals against the flat normal of the triangle hit: close, and on
      // the same side (a mirrored mesh whose normals were not taken through the inverse transpose
      // would point into the object).
      const glm::dvec3 n = decodeNormal(normals->rgba, p);
      ++normalsChecked;
      normalsFacingAway += glm::dot(n, reference.normal[p]) <= 0.0;
      normalErrors.push_back(std::acos(std::clamp(glm::dot(n, reference.normal[p]), -1.0, 1.0)) * 57.29578);
    }
  }
  std::sort(normalErrors.begin(), normalErrors.end());
  const double normalP90 = normalErrors.empty() ? 0.0 : normalErrors[normalErrors.size() * 9 / 10];
  std::printf("covered %d, disagree %d (interior %d), max relative depth error %.2e (silhouette %.2e), "
              "normals checked %d, facing away %d, error p90 %.1f deg\n",
              covered, disagree, interiorDisagree, maxRelativeDepthError, maxSilhouetteDepthError, normalsChecked,
              normalsFacingAway, normalP90);
  const DeviceTolerances tolerance;  // the mesh tolerances are the same on every device
  EXPECT_GT(covered, minCovered);
  EXPECT_LE(disagree, tolerance.meshSilhouetteCoverageShare * covered);
  EXPECT_EQ(interiorDisagree, 0);
  EXPECT_LT(maxRelativeDepthError, tolerance.meshInteriorRelativeDepth);
  EXPECT_LT(maxSilhouetteDepthError, tolerance.meshSilhouetteRelativeDepth);
  if (normals) {
    EXPECT_GT(normalsChecked, covered / 2);
    EXPECT_LE(normalsFacingAway, normalsChecked / 100);
    EXPECT_LT(normalP90, 20.0) << "smooth normals of the bunny stay near its facets";
  }
}

// Why: exercises the whole path file -> importer -> entities -> mesh pool -> indirect draws ->
// depth prepass; a wrong node transform, index offset or winding shows as a coverage difference.
TEST_F(GpuTest, BunnyMatchesCpuRayCastOfItsTriangles) {
  auto data = scene::loadGltf(sampleAsset("bunny.glb"));
  ASSERT_TRUE(data.ok()) << data.error().message;
  const render::InstantiatedScene instantiated = render::instantiateScene(*data, registry_, *pool_);
  ASSERT_FALSE(instantiated.renderables.empty());
  const scene::TriangleSoup soup = scene::flattenTriangles(*data);

  const std::uint32_t w = 96, h = 96;
  createRenderer(w, h);
  for (const float yaw : {0.3f, 2.5f}) {
    SCOPED_TRACE("yaw " + std::to_string(yaw));
    const render::CameraView camera = orbitCamera(soup, yaw);
    expectMatchesRayCast(render(camera), nullptr, rayCast(soup, camera, w, h), int(w * h) / 10);
  }
}

// Why: a glTF accessor may hold vertices no triangle uses (an exporter's leftovers, a shared
// buffer). The scene's bounds frame the camera, size the ground and set the near plane: one unused
// vertex 100 units away made a unit triangle cover 4 pixels of 4,643. The bounds, the mesh pool's
// (frustum culling) and the scene's, are those of the triangles.
TEST_F(GpuTest, AVertexNoTriangleUsesDoesNotBoundTheScene) {
  scene::SceneData data;
  scene::MeshPrimitiveData triangle;
  triangle.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {100, 0, 0}};
  triangle.normals.assign(4, glm::vec3(0, 0, 1));
  triangle.indices = {0, 1, 2};
  data.meshes.push_back({"triangle", {triangle}});
  scene::NodeData node;
  node.mesh = 0;
  node.local = node.world = glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 2));
  data.nodes.push_back(node);
  const render::InstantiatedScene instantiated = render::instantiateScene(data, registry_, *pool_);
  EXPECT_EQ(instantiated.boundsMin, glm::vec3(0, 0, 2));
  EXPECT_EQ(instantiated.boundsMax, glm::vec3(1, 1, 2));
  const render::MeshRange& range = pool_->range(registry_.get<render::MeshRenderable>(instantiated.renderables[0]).mesh);
  EXPECT_EQ(range.boundsMax, glm::vec3(1, 1, 0));
}

// Why: a glTF primitive without NORMAL must be drawn with flat normals (the spec asks clients to
// compute them); the area-weighted smooth normals over a cube's 8 shared corners drew it as a
// rounded blob with dark wedges, unlike the flat-faced SDF baked from the same triangles (found by
// a helper looking at the images). Seen from a corner, three faces: three normals, each over its
// whole face; the triangles keep their shared corners for everyone else (the SDF's closedness).
TEST_F(GpuTest, APrimitiveWithoutNormalsIsDrawnFlat) {
  createRenderer(96, 96);
  scene::SceneData data;
  scene::MeshPrimitiveData cube;
  for (int c = 0; c < 8; ++c) cube.positions.push_back(glm::vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1) - 0.5f);
  cube.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                  2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  cube.normals.assign(8, glm::vec3(0, 1, 0));  // what a smooth fill would hold; flat must not use them
  cube.flatNormals = true;
  data.meshes.push_back({"cube", {cube}});
  scene::NodeData node;
  node.mesh = 0;
  node.local = node.world = glm::mat4(1.0f);
  data.nodes.push_back(node);
  render::instantiateScene(data, registry_, *pool_);
  scene::updateWorldTransforms(registry_);
  const render::CameraView camera =
      render::CameraView::lookAt({1.6f, 1.3f, 1.9f}, {0.0f, 0.0f, 0.0f}, 0.8f, 0.05f, 1.0f);
  const Frame frame = renderWith(camera, DEBUG_VIEW_NORMALS);
  std::map<std::uint32_t, int> colours;
  for (std::size_t i = 0; i < frame.depth.size(); ++i) {
    if (frame.depth[i] <= 0.0f) continue;
    const std::uint8_t* c = &frame.rgba[i * 4];
    ++colours[std::uint32_t(c[0]) << 16 | std::uint32_t(c[1]) << 8 | c[2]];
  }
  ASSERT_EQ(colours.size(), 3u) << "three visible faces, one normal each";
  for (const auto& [colour, pixels] : colours) EXPECT_GT(pixels, 300) << std::hex << colour;
  EXPECT_EQ(context_->validationMessageCount(), 0u);
}

// `data` with a new root node (local matrix `parent`) above its roots, whose local matrices are
// premultiplied by `local`; world matrices recomputed (parents come before their children).
scene::SceneData placeUnder(const scene::SceneData& data, const glm::mat4& parent, const glm::mat4& local) {
  scene::SceneData placed = data;
  scene::NodeData root;
  root.name = "placement";
  root.local = parent;
  placed.nodes.insert(placed.nodes.begin(), root);
  for (std::size_t n = 1; n < placed.nodes.size(); ++n) {
    scene::NodeData& node = placed.nodes[n];
    if (node.parent < 0) node.local = local * node.local;
    node.parent = node.parent < 0 ? 0 : node.parent + 1;
  }
  for (scene::NodeData& node : placed.nodes)
    node.world = node.parent < 0 ? node.local : placed.nodes[std::size_t(node.parent)].world * node.local;
  return placed;
}

// Why: glTF allows negative scales (an editor's "mirror") and non-uniform ones, and a
// non-uniformly scaled parent over a rotated child gives a sheared world matrix. A mirroring
// matrix turns every triangle clockwise on screen: with a fixed front face the rasterizer culls the
// outside and shows the inside of the far side (wrong depth everywhere). Normals must go through
// the inverse transpose to stay perpendicular to stretched or sheared surfaces. The path runs from
// scene data through instantiateScene (TRS decomposition of each node, including a negative
// scale) and the transform hierarchy, against a CPU cast of the same triangles in world space.
TEST_F(GpuTest, MirroredScaledAndShearedGltfNodesMatchCpuRayCast) {
  auto data = scene::loadGltf(sampleAsset("bunny.glb"));
  ASSERT_TRUE(data.ok()) << data.error().message;
  const auto [lo, hi] = soupBounds(scene::flattenTriangles(*data));
  const std::uint32_t w = 96, h = 96;
  createRenderer(w, h);
  std::vector<NamedTransform> transforms = userTransforms(0.5f * (lo + hi));
  // A millimetre-to-metre export: glm::decompose's absolute epsilon on the determinant used to turn
  // this node into the identity, drawing a bunny 1000 times too large around the tiny camera.
  const glm::vec3 pivot = 0.5f * (lo + hi);
  transforms.push_back({"scale 1e-3", glm::mat4(1.0f),
                        glm::translate(glm::mat4(1.0f), pivot) * glm::scale(glm::mat4(1.0f), glm::vec3(1e-3f)) *
                            glm::translate(glm::mat4(1.0f), -pivot)});
  for (const NamedTransform& transform : transforms) {
    SCOPED_TRACE(transform.label);
    registry_.clear();
    const scene::SceneData placed = placeUnder(*data, transform.parent, transform.local);
    render::instantiateScene(placed, registry_, *pool_);
    const scene::TriangleSoup soup = scene::flattenTriangles(placed);
    for (const float yaw : {0.3f, 2.5f}) {
      SCOPED_TRACE("yaw " + std::to_string(yaw));
      const render::CameraView camera = orbitCamera(soup, yaw);
      const Frame frame = render(camera);
      const Frame normals = renderWith(camera, DEBUG_VIEW_NORMALS);
      // The flattened bunny (scale 0.4 along one axis) seen edge-on covers less of the image.
      expectMatchesRayCast(frame, &normals, rayCast(soup, camera, w, h), int(w * h) / 20);
    }
  }
}

// Why: mirrored and unmirrored meshes in one frame are drawn in two batches of the same indirect
// buffer with different front faces; each batch must draw its own objects (an offset error would
// draw one object twice and drop the other, a missing state change would cull one of them wrong).
TEST_F(GpuTest, MirroredAndUnmirroredMeshesInOneFrame) {
  auto data = scene::loadGltf(sampleAsset("bunny.glb"));
  ASSERT_TRUE(data.ok()) << data.error().message;
  const auto [lo, hi] = soupBounds(scene::flattenTriangles(*data));
  const glm::vec3 offset(0.6f * (hi.x - lo.x), 0.0f, 0.0f);
  // Left: the bunny as it is; right: mirrored in x (a negative-scale node, as a glTF file has it).
  const scene::SceneData left = placeUnder(*data, glm::translate(glm::mat4(1.0f), -offset), glm::mat4(1.0f));
  const scene::SceneData right = placeUnder(*data, glm::translate(glm::mat4(1.0f), offset),
                                            userTransforms(0.5f * (lo + hi))[0].local);
  scene::TriangleSoup soup = scene::flattenTriangles(left);
  const scene::TriangleSoup mirrored = scene::flattenTriangles(right);
  const auto base = static_cast<std::uint32_t>(soup.positions.size());
  soup.positions.insert(soup.positions.end(), mirrored.positions.begin(), mirrored.positions.end());
  for (const std::uint32_t i : mirrored.indices) soup.indices.push_back(base + i);
  // Right first: the mirrored batch must not depend on creation order.
  render::instantiateScene(right, registry_, *pool_);
  render::instantiateScene(left, registry_, *pool_);

  const std::uint32_t w = 128, h = 64;
  createRenderer(w, h);
  const glm::vec3 sceneLo = lo - offset, sceneHi = hi + offset;
  const glm::vec3 center = 0.5f * (sceneLo + sceneHi);
  const render::CameraView camera = render::CameraView::lookAt(
      center + glm::vec3(0.2f, 0.3f, 1.0f) * glm::length(sceneHi - sceneLo), center, 0.6f, 0.01f, float(w) / float(h));
  const Frame frame = render(camera);
  const Frame normals = renderWith(camera, DEBUG_VIEW_NORMALS);
  expectMatchesRayCast(frame, &normals, rayCast(soup, camera, w, h), int(w * h) / 10);
}

// Why: 1-pixel and 7-pixel wide viewports, 10 and 150 degree fields of view and a mesh a few
// pixels wide, here mirrored and sheared, push the projection and the viewport maths to their
// ends; each must render without a validation message and match the ray cast.
TEST_F(GpuTest, ExtremeCamerasAndViewportsMatchCpuRayCast) {
  auto data = scene::loadGltf(sampleAsset("bunny.glb"));
  ASSERT_TRUE(data.ok()) << data.error().message;
  const scene::TriangleSoup original = scene::flattenTriangles(*data);
  const auto [lo, hi] = soupBounds(original);
  const NamedTransform transform = userTransforms(0.5f * (lo + hi))[2];  // mirroring, sheared
  const scene::SceneData placed = placeUnder(*data, transform.parent, transform.local);
  render::instantiateScene(placed, registry_, *pool_);
  const scene::TriangleSoup soup = scene::flattenTriangles(placed);
  const auto [placedLo, placedHi] = soupBounds(soup);
  for (const CameraSetup& setup : extremeCameras(0.5f * (placedLo + placedHi), 0.5f * glm::length(placedHi - placedLo))) {
    SCOPED_TRACE(setup.label);
    createRenderer(setup.size.x, setup.size.y);
    expectMatchesRayCast(render(setup.camera), nullptr, rayCast(soup, setup.camera, setup.size.x, setup.size.y));
  }
}

}  // namespace
}  // namespace gputest
