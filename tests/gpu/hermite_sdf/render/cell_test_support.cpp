#include "cell_test_support.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

#include "engine/core/image_io.h"
#include "engine/core/math.h"
#include "engine/gpu/pipeline_statistics.h"

namespace gputest {

using namespace engine;

void dumpImages(const std::string& folder, const char* label, const Frame& normals, const hsdf::ReferenceImage& reference) {
  static int counter = 0;
  const std::string prefix = folder + "/" + label + "_" + std::to_string(counter++);
  (void)writePng(prefix + "_gpu.png", normals.rgba, normals.width, normals.height, 4);
  (void)hsdf::writeNormalPng(reference, prefix + "_ref.png");
  std::vector<std::uint8_t> diff(normals.rgba.size(), 0);
  for (std::size_t i = 0; i < reference.hit.size(); ++i) {
    const bool gpu = normals.rgba[i * 4 + 0] != normals.rgba[0] || normals.rgba[i * 4 + 1] != normals.rgba[1];
    diff[i * 4 + 3] = 255;
    if (reference.hit[i] && !gpu) diff[i * 4 + 0] = 255;
    if (!reference.hit[i] && gpu) diff[i * 4 + 2] = 255;
    if (reference.hit[i] && gpu) diff[i * 4 + 1] = 60;
  }
  (void)writePng(prefix + "_diff.png", diff, normals.width, normals.height, 4);
}

render::CameraView orbitCamera(const hsdf::SdfAsset& asset, int view, float distanceScale) {
  const glm::vec3 center = glm::vec3(asset.surfaceBounds.center());
  const float radius = 0.5f * float(glm::length(asset.surfaceBounds.size()));
  const float yaw = 0.4f + float(view) * 1.047f;             // six views around the object
  const float pitch = (view % 2 == 0) ? 0.3f : -0.45f;       // above and below
  const glm::vec3 eye = math::orbitEye(center, distanceScale * radius, yaw, pitch);
  return render::CameraView::lookAt(eye, center, 0.9f, 0.01f * radius, 1.0f);
}

glm::vec3 torusHole(const hsdf::SdfAsset& torus) {
  const hsdf::Aabb bounds = torus.surfaceBounds;
  return glm::vec3(bounds.center()) + glm::vec3(0.0f, 0.05f * float(bounds.size().y), 0.0f);
}
glm::vec3 torusRing(const hsdf::SdfAsset& torus) {
  const hsdf::Aabb bounds = torus.surfaceBounds;
  return glm::vec3(bounds.center()) + glm::vec3(float(bounds.size().x) * 0.5f, 0.0f, 0.0f);
}

std::optional<render::CameraView> insideACellCamera(const hsdf::SdfAsset& torus) {
  const glm::vec3 hole = torusHole(torus), ring = torusRing(torus);
  const float h = float(torus.field.grid.spacing);
  auto hit = hsdf::castRay(torus.field, {glm::dvec3(hole), glm::normalize(glm::dvec3(ring - hole))});
  if (!hit.ok() || !hit->has_value()) return std::nullopt;
  const glm::vec3 surface((*hit)->position);
  const glm::vec3 eye = surface - 0.5f * h * glm::normalize(ring - hole);
  return render::CameraView::lookAt(eye, surface + glm::vec3(0.0f, 0.3f * h, 0.0f), 1.2f, 0.25f * h, 1.0f);
}

std::optional<render::CameraView> justOutsideAKeptCellCamera(const hsdf::SdfAsset& asset) {
  const hsdf::CellStream& cells = asset.cells;
  const double h = cells.grid.spacing;
  std::set<std::array<int, 3>> kept;
  for (const hsdf::CellRecord& r : cells.records) kept.insert({r.x, r.y, r.z});
  const std::vector<std::uint16_t> codes = hsdf::proxyBoxCodes(cells);
  constexpr double kSteps = hsdf::kProxySteps;
  for (std::size_t i = 0; i < cells.records.size(); ++i) {
    const hsdf::CellRecord& r = cells.records[i];
    const hsdf::CellProxyBox box = hsdf::unpackProxyBox(codes[i]);
    if (kept.count({r.x + 1, r.y, r.z}) != 0 || box.hi[0] != hsdf::kProxySteps) continue;
    const glm::dvec3 inCell(1.0 + 1.0 / 16384.0, (box.lo[1] + box.hi[1]) / (2.0 * kSteps), (box.lo[2] + box.hi[2]) / (2.0 * kSteps));
    const glm::dvec3 eye = cells.grid.origin + h * (glm::dvec3(r.x, r.y, r.z) + inCell);
    const auto hit = hsdf::castRay(asset.field, {eye, glm::dvec3(-1.0, 0.0, 0.0)});
    if (!hit.ok() || !hit->has_value() || (*hit)->t > h) continue;
    return render::CameraView::lookAt(glm::vec3(eye), glm::vec3(eye - glm::dvec3(h, 0.0, 0.0)), 1.2f, float(1e-6 * h), 1.0f);
  }
  return std::nullopt;
}

void expectMatchesReference(const ImageComparison& c, int pixels, int minHits) {
  EXPECT_GT(c.referenceHits, minHits);
  EXPECT_GE(c.agreement(pixels), 0.999);
  EXPECT_EQ(c.interiorHoles, 0);
  EXPECT_EQ(c.interiorExtras, 0);
  EXPECT_LT(c.interiorDepthErrorP99, 1e-3) << "with 1 refinement step the depth error must stay below 1e-3 cells (99%)";
  EXPECT_LT(c.depthErrorP99, 1e-2) << "including silhouette pixels";
  EXPECT_LT(c.normalErrorP99Degrees, 2.0);
}

std::uint64_t prepassFragments(const render::Renderer& renderer) {
  const auto* s = gpu::findStatistics(renderer.lastPipelineStatistics(), "depth prepass");
  return s ? s->fragmentShaderInvocations : 0;
}

TileComparison compareTilesWithBoxes(const Frame& boxes, const Frame& tiles) {
  TileComparison c;
  for (std::size_t i = 0; i < boxes.depth.size(); ++i) {
    const bool a = boxes.depth[i] > 0.0f, b = tiles.depth[i] > 0.0f;
    c.hitsBoxes += a;
    c.hitsTiles += b;
    c.coverageDiffers += a != b;
    if (a && b)
      c.depthRelativeMax = std::max(c.depthRelativeMax, double(std::abs(boxes.depth[i] - tiles.depth[i]) / boxes.depth[i]));
    for (int k = 0; k < 3; ++k)
      if (std::abs(int(boxes.rgba[i * 4 + k]) - int(tiles.rgba[i * 4 + k])) > 8) {
        ++c.colourDiffers;
        break;
      }
  }
  return c;
}

}  // namespace gputest
