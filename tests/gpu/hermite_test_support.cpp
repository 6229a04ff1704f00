#include "hermite_test_support.h"

#include <algorithm>
#include <cstring>
#include <cmath>
#include <cstdio>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/core/math.h"
#include "engine/render/components.h"
#include "engine/scene/gltf/gltf_loader.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/core/analytic.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/core/field.h"
#include "hermite_sdf/core/mesh_source.h"
#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/render/sphere_trace_feature.h"
#include "shared/host_device.h"

namespace gputest {

using namespace engine;

std::shared_ptr<const hsdf::SdfAsset> bakeAsset(const std::string& shape, int resolution) {
  std::unique_ptr<hsdf::SdfSource> source;
  if (shape == "bunny") {
    auto data = scene::loadGltf(sampleAsset("bunny.glb"));
    EXPECT_TRUE(data.ok()) << data.error().message;
    if (!data) return nullptr;
    auto mesh = hsdf::MeshSource::create(scene::flattenTriangles(*data));
    EXPECT_TRUE(mesh.ok()) << mesh.error().message;
    if (!mesh) return nullptr;
    source = std::move(mesh.value());
  } else {
    auto analytic = hsdf::makeAnalyticSource(shape);
    EXPECT_TRUE(analytic.ok()) << analytic.error().message;
    if (!analytic) return nullptr;
    source = std::move(analytic.value());
  }
  auto grid = hsdf::fitGrid(source->bounds(), resolution, 1);
  EXPECT_TRUE(grid.ok()) << grid.error().message;
  if (!grid) return nullptr;
  auto field = hsdf::bakeHermiteField(*source, *grid);
  EXPECT_TRUE(field.ok()) << field.error().message;
  if (!field) return nullptr;
  auto asset = hsdf::makeSdfAsset(shape, std::move(field.value()), source->bounds());
  EXPECT_TRUE(asset.ok()) << asset.error().message;
  return asset ? asset.value() : nullptr;
}

hsdf::TrilinearField trilinearOf(const hsdf::HermiteField& field) {
  hsdf::TrilinearField out;
  out.grid = field.grid;
  out.values.reserve(field.samples.size());
  for (const hsdf::HermiteSample& s : field.samples) out.values.push_back(s.f);
  return out;
}

hsdf::HermiteField roundedToHalf(const hsdf::HermiteField& field) {
  hsdf::HermiteField out = field;
  auto round = [](float v) { return hsdf::halfToFloat(hsdf::floatToHalf(v)); };
  for (hsdf::HermiteSample& s : out.samples) s = {round(s.f), round(s.fx), round(s.fy), round(s.fz)};
  return out;
}

namespace {

// The CPU reference of `method`'s interpolant (trilinear for the trilinear tracer, else Hermite).
hsdf::ReferenceImage referenceOf(hsdf::RenderMethod method, const hsdf::HermiteField& field, const glm::mat4& view,
                                 const glm::mat4& proj, glm::ivec2 size, const hsdf::RenderOptions& options) {
  auto reference = [&]() -> Expected<hsdf::ReferenceImage> {
    if (method == hsdf::RenderMethod::TrilinearSphereTrace)
      return hsdf::renderReference(trilinearOf(field), view, proj, size, options);
    ENGINE_TRY_ASSIGN(const hsdf::CellClassification cells, hsdf::classifyCells(field));
    return hsdf::renderReference(field, view, proj, size, &cells, options);
  }();
  EXPECT_TRUE(reference.ok()) << reference.error().message;
  return reference ? std::move(reference.value()) : hsdf::ReferenceImage{};
}

}  // namespace

hsdf::ReferenceImage referenceFor(hsdf::RenderMethod method, const hsdf::HermiteField& field,
                                  const render::CameraView& camera, glm::ivec2 size, const glm::mat4& model) {
  hsdf::RenderOptions options;
  options.model = model;
  return referenceOf(method, field, camera.view, camera.proj, size, options);
}

hsdf::ReferenceImage referenceFromTheEye(const hsdf::HermiteField& field, const render::CameraView& camera,
                                         glm::ivec2 size, hsdf::RenderMethod method) {
  hsdf::RenderOptions options;
  options.model = glm::translate(glm::mat4(1.0f), -camera.position);
  const glm::mat4 rotation(camera.viewFrom(glm::dvec3(camera.position)));
  return referenceOf(method, field, rotation, camera.proj, size, options);
}

ecs::Entity addTracedSdf(ecs::Registry& registry, std::shared_ptr<const hsdf::SdfAsset> asset,
                         hsdf::RenderMethod method, const glm::mat4& transform, bool half) {
  const ecs::Entity entity = registry.create();
  registry.emplace<scene::WorldTransform>(entity, scene::WorldTransform{transform});
  hsdf::HermiteSdfRenderable renderable;
  renderable.asset = std::move(asset);
  renderable.method = method;
  renderable.halfPrecision = half;
  registry.emplace<hsdf::HermiteSdfRenderable>(entity, renderable);
  return entity;
}

ecs::Entity addSdf(ecs::Registry& registry, std::shared_ptr<const hsdf::SdfAsset> asset, hsdf::RenderMethod method,
                   const glm::mat4& transform, std::uint32_t subdivisions) {
  const ecs::Entity entity = registry.create();
  registry.emplace<scene::Transform>(entity);
  registry.emplace<scene::WorldTransform>(entity, scene::WorldTransform{transform});
  hsdf::HermiteSdfRenderable renderable;
  renderable.asset = std::move(asset);
  renderable.method = method;
  renderable.subdivisions = subdivisions;
  registry.emplace<hsdf::HermiteSdfRenderable>(entity, renderable);
  return entity;
}

render::FrameSettings splitInHalves(std::uint32_t width, std::uint32_t height,
                                    const std::function<void(std::uint32_t side)>& show) {
  render::FrameSettings split;
  for (std::uint32_t side = 0; side < 2; ++side)
    split.regions.push_back({VkRect2D{{std::int32_t(side * width / 2), 0}, {width / 2, height}},
                             [show, side] { show(side); }});
  return split;
}

namespace {

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  const std::size_t k = std::min(values.size() - 1, std::size_t(p * double(values.size())));
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
  return values[k];
}

bool neighbourhoodAllEqual(const hsdf::ReferenceImage& ref, int x, int y, bool value) {
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int nx = x + dx, ny = y + dy;
      if (nx < 0 || ny < 0 || nx >= ref.width || ny >= ref.height) return false;  // image edge counts as edge
      if ((ref.hit[ref.pixel(nx, ny)] != 0) != value) return false;
    }
  return true;
}

bool allHitsWithin(const hsdf::ReferenceImage& ref, int x, int y, int radius) {
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      const int nx = x + dx, ny = y + dy;
      if (nx < 0 || ny < 0 || nx >= ref.width || ny >= ref.height || !ref.hit[ref.pixel(nx, ny)]) return false;
    }
  return true;
}

bool noHitsWithin(const hsdf::ReferenceImage& ref, int x, int y, int radius) {
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      const int nx = x + dx, ny = y + dy;
      if (nx >= 0 && ny >= 0 && nx < ref.width && ny < ref.height && ref.hit[ref.pixel(nx, ny)]) return false;
    }
  return true;
}

// Pixels within `radius` of an occlusion edge of the reference: two 4-adjacent hits whose distances
// along their rays differ by more than kOcclusionJumpCells. There a ray grazes the silhouette of a
// nearer part in front of a farther one, and, as at the outer silhouette, a float search may rightly
// pass the nearer part where the double reference just touches it.
constexpr double kOcclusionJumpCells = 1.0;

std::vector<bool> nearOcclusionEdges(const hsdf::ReferenceImage& ref, const std::vector<double>& cellsAlongRay, int radius) {
  std::vector<bool> edge(ref.hit.size(), false), near(ref.hit.size(), false);
  for (int y = 0; y < ref.height; ++y)
    for (int x = 0; x < ref.width; ++x) {
      const std::size_t i = ref.pixel(x, y);
      if (!ref.hit[i]) continue;
      for (const glm::ivec2 d : {glm::ivec2(1, 0), glm::ivec2(0, 1)}) {
        if (x + d.x >= ref.width || y + d.y >= ref.height) continue;
        const std::size_t j = ref.pixel(x + d.x, y + d.y);
        if (ref.hit[j] && std::abs(cellsAlongRay[i] - cellsAlongRay[j]) > kOcclusionJumpCells) edge[i] = edge[j] = true;
      }
    }
  for (int y = 0; y < ref.height; ++y)
    for (int x = 0; x < ref.width; ++x) {
      if (!edge[ref.pixel(x, y)]) continue;
      for (int ny = std::max(0, y - radius); ny <= std::min(ref.height - 1, y + radius); ++ny)
        for (int nx = std::max(0, x - radius); nx <= std::min(ref.width - 1, x + radius); ++nx) near[ref.pixel(nx, ny)] = true;
    }
  return near;
}

}  // namespace

ImageComparison compareWithReference(const Frame& gpu, const std::vector<std::uint8_t>* normalRgba,
                                     const hsdf::ReferenceImage& reference, const render::CameraView& camera,
                                     double spacing, const glm::mat4& model) {
  ImageComparison result;
  std::vector<double> depthErrors, interiorDepthErrors, normalErrors;
  const bool placed = model != glm::mat4(1.0f);
  const glm::dmat3 inverseModel = glm::inverse(glm::dmat3(model));
  // Per reference hit, once: cells per world unit along its ray (a cell measures h / |M^-1 d| world
  // units along d) and its distance in those cells.
  std::vector<double> cellsPerWorldUnit(reference.hit.size(), 1.0 / spacing), referenceCells(reference.hit.size(), 0.0);
  for (int y = 0; y < reference.height; ++y)
    for (int x = 0; x < reference.width; ++x) {
      const std::size_t i = reference.pixel(x, y);
      if (!reference.hit[i]) continue;
      if (placed) {
        const math::Ray ray = math::pixelRay(camera.view, camera.proj, {float(x) + 0.5f, float(y) + 0.5f},
                                             {reference.width, reference.height});
        cellsPerWorldUnit[i] = glm::length(inverseModel * ray.direction) / spacing;
      }
      referenceCells[i] = math::depthToViewDistance(camera.proj, reference.depth[i]) * cellsPerWorldUnit[i];
    }
  const std::vector<bool> occlusionEdge = nearOcclusionEdges(reference, referenceCells, 2);
  for (int y = 0; y < reference.height; ++y) {
    for (int x = 0; x < reference.width; ++x) {
      const std::size_t i = reference.pixel(x, y);
      const bool refHit = reference.hit[i] != 0;
      const float depth = gpu.depthAt(std::uint32_t(x), std::uint32_t(y));
      const bool gpuHit = depth > 0.0f;
      result.referenceHits += refHit;
      result.gpuHits += gpuHit;
      if (refHit != gpuHit) {
        ++result.disagreements;
        if (refHit && neighbourhoodAllEqual(reference, x, y, true)) ++result.interiorHoles;
        if (gpuHit && neighbourhoodAllEqual(reference, x, y, false)) ++result.interiorExtras;
        continue;
      }
      if (!refHit) continue;
      const double gpuDistance = math::depthToViewDistance(camera.proj, depth);
      const double refDistance = math::depthToViewDistance(camera.proj, reference.depth[i]);
      depthErrors.push_back(std::abs(gpuDistance - refDistance) * cellsPerWorldUnit[i]);
      const bool interior = allHitsWithin(reference, x, y, 2) && !occlusionEdge[i];
      if (interior && depthErrors.back() > kDepthOutlierCells) ++result.interiorDepthOutliers;
      if (interior) interiorDepthErrors.push_back(depthErrors.back());
      if (normalRgba) {
        const glm::dvec3 n = decodeNormal(*normalRgba, i);
        const glm::dvec3 r = glm::dvec3(reference.normal[i]);
        result.normalFlips += glm::dot(n, r) < 0.0;
        result.interiorNormalFlips += interior && glm::dot(n, r) < 0.0;
        // The shading flips normals facing away from the eye; compare orientation-free.
        const double cosine = std::min(1.0, std::abs(glm::dot(n, r)));
        normalErrors.push_back(std::acos(cosine) * 180.0 / 3.14159265358979);
      }
    }
  }
  result.depthErrorP50 = percentile(depthErrors, 0.5);
  result.depthErrorP90 = percentile(depthErrors, 0.9);
  result.depthErrorP99 = percentile(depthErrors, 0.99);
  result.interiorDepthErrorP99 = percentile(interiorDepthErrors, 0.99);
  result.depthErrorMax = depthErrors.empty() ? 0.0 : *std::max_element(depthErrors.begin(), depthErrors.end());
  result.normalErrorP99Degrees = percentile(normalErrors, 0.99);
  return result;
}

int wireEdgePixels(const Frame& wire, const Frame& shaded) {
  int edges = 0;
  for (std::size_t i = 0; i < wire.depth.size(); ++i) {
    const std::uint8_t* c = &wire.rgba[i * 4];
    edges += c[0] > 230 && c[1] > 200 && c[2] < 150 && std::memcmp(c, &shaded.rgba[i * 4], 3) != 0;
  }
  return edges;
}

int countIsolatedPixels(const Frame& frame, int tolerance, const std::function<bool(std::size_t)>& wrong) {
  const auto close = [tolerance](const glm::u8vec4& a, const glm::u8vec4& b) {
    for (int c = 0; c < 3; ++c)
      if (std::abs(int(a[c]) - int(b[c])) > tolerance) return false;
    return true;
  };
  int isolated = 0;
  for (std::uint32_t y = 1; y + 1 < frame.height; ++y)
    for (std::uint32_t x = 1; x + 1 < frame.width; ++x) {
      const glm::u8vec4 first = frame.pixel(x - 1, y - 1);
      bool agree = true;
      for (int dy = -1; dy <= 1 && agree; ++dy)
        for (int dx = -1; dx <= 1 && agree; ++dx)
          if (dx != 0 || dy != 0) agree = close(first, frame.pixel(x + dx, y + dy));
      isolated += agree && !close(first, frame.pixel(x, y)) && (!wrong || wrong(std::size_t(y) * frame.width + x));
    }
  return isolated;
}

std::vector<bool> wrongPixels(const Frame& normals, const hsdf::ReferenceImage& reference, double degrees) {
  std::vector<bool> wrong(reference.hit.size(), false);
  const double cosine = std::cos(degrees * 3.14159265358979 / 180.0);
  for (std::size_t i = 0; i < wrong.size(); ++i) {
    const int x = int(i % std::size_t(reference.width)), y = int(i / std::size_t(reference.width));
    if (!allHitsWithin(reference, x, y, 2) && !noHitsWithin(reference, x, y, 2)) continue;  // near a silhouette
    const bool gpuHit = normals.depth[i] > 0.0f;
    if (gpuHit != (reference.hit[i] != 0)) wrong[i] = true;
    else if (gpuHit) wrong[i] = std::abs(glm::dot(decodeNormal(normals.rgba, i), glm::dvec3(reference.normal[i]))) < cosine;
  }
  return wrong;
}

WorldSphere worldSphere(const hsdf::SdfAsset& asset, const glm::mat4& model) {
  glm::vec3 lo, hi;
  math::transformBounds(model, glm::vec3(asset.surfaceBounds.min), glm::vec3(asset.surfaceBounds.max), lo, hi);
  return {0.5f * (lo + hi), 0.5f * glm::length(hi - lo)};
}

render::CameraView orbitAround(const WorldSphere& sphere, int view) {
  const float yaw = 0.4f + float(view) * 2.1f;
  const float pitch = (view % 2 == 0) ? 0.3f : -0.45f;
  const glm::vec3 eye = math::orbitEye(sphere.center, 1.9f * sphere.radius, yaw, pitch);
  return render::CameraView::lookAt(eye, sphere.center, 0.9f, 0.01f * sphere.radius, 1.0f);
}

engine::render::CameraView orthographicLike(const engine::render::CameraView& camera, float ymag, float znear, float zfar) {
  engine::render::Camera ortho;
  ortho.projection = engine::render::Projection::kOrthographic;
  ortho.xmag = ortho.ymag = ymag;
  ortho.znear = znear;
  ortho.zfar = zfar;
  const engine::Expected<engine::render::CameraView> made =
      engine::render::CameraView::fromWorld(glm::inverse(camera.view), ortho, 1.0f);
  EXPECT_TRUE(made.ok()) << made.error().message;
  return made ? *made : camera;
}

namespace {

// Where the far cameras look from, seen from the centre of what they frame.
glm::vec3 farViewFrom() { return glm::normalize(glm::vec3(0.6f, 0.5f, 0.8f)); }

}  // namespace

std::pair<render::CameraView, render::CameraView> farCameras(const WorldSphere& sphere, double distance) {
  const float far = float(distance), radius = sphere.radius;
  const glm::vec3 eye = sphere.center + far * farViewFrom();
  const render::CameraView telephoto =
      render::CameraView::lookAt(eye, sphere.center, 2.0f * std::atan(0.8f * radius / far), far - 2.0f * radius, 1.0f);
  return {telephoto, orthographicLike(telephoto, 0.8f * radius, far - 2.0f * radius, far + 2.0f * radius)};
}

namespace {

// The surface bounds' sphere, made as the far tests made it before WorldSphere (their numbers kept).
WorldSphere surfaceSphere(const hsdf::SdfAsset& asset) {
  return {glm::vec3(asset.surfaceBounds.center()), 0.5f * float(glm::length(asset.surfaceBounds.size()))};
}

}  // namespace

std::pair<render::CameraView, render::CameraView> farCameras(const hsdf::SdfAsset& asset, double cells) {
  return farCameras(surfaceSphere(asset), double(float(cells * asset.field.grid.spacing)));
}

std::pair<render::CameraView, render::CameraView> farBackCameras(const WorldSphere& sphere, double distance) {
  const render::CameraView far = farCameras(sphere, distance).second;
  const glm::dmat3 rotation(glm::mat3(far.view));
  const glm::dvec3 ahead = -glm::inverse(rotation)[2];
  render::CameraView moved = far;
  moved.position = glm::vec3(glm::dvec3(far.position) + (distance - 3.0 * double(sphere.radius)) * ahead);
  moved.view[3] = glm::vec4(glm::vec3(-(rotation * glm::dvec3(moved.position))), 1.0f);
  return {far, orthographicLike(moved, far.ymag, sphere.radius, 5.0f * sphere.radius)};
}

std::pair<render::CameraView, render::CameraView> farBackCameras(const hsdf::SdfAsset& asset, double cells) {
  return farBackCameras(surfaceSphere(asset), cells * asset.field.grid.spacing);
}

TwoObjects twoOverlappingObjects(const hsdf::SdfAsset& asset) {
  const glm::vec3 center(asset.surfaceBounds.center());
  const float radius = 0.5f * float(glm::length(asset.surfaceBounds.size()));
  const glm::vec3 towardEye = farViewFrom();
  const glm::vec3 across = glm::normalize(glm::cross(glm::vec3(0.0f, 1.0f, 0.0f), towardEye));
  const glm::vec3 moved = -0.1f * radius * towardEye + 0.55f * radius * across;
  TwoObjects two;
  two.models[0] = glm::mat4(1.0f);
  two.models[1] = glm::translate(glm::mat4(1.0f), center + moved) * glm::rotate(glm::mat4(1.0f), 1.5708f, across) *
                  glm::translate(glm::mat4(1.0f), -center);
  two.frame = {center + 0.5f * moved, radius + 0.5f * glm::length(moved)};
  return two;
}

hsdf::ReferenceImage nearerHits(hsdf::ReferenceImage first, const hsdf::ReferenceImage& second) {
  int firstWins = 0, secondWins = 0, both = 0;
  for (std::size_t i = 0; i < first.hit.size(); ++i) {
    both += first.hit[i] && second.hit[i];
    if (!second.hit[i] || (first.hit[i] && second.depth[i] <= first.depth[i])) {
      firstWins += first.hit[i];
      continue;
    }
    ++secondWins;
    first.depth[i] = second.depth[i];
    first.normal[i] = second.normal[i];
    first.hit[i] = second.hit[i];
    first.cellId[i] = second.cellId[i];
  }
  std::printf("two objects: the first wins %d px, the second %d, both hit %d\n", firstWins, secondWins, both);
  EXPECT_GT(firstWins, 2000);
  EXPECT_GT(secondWins, 2000);
  EXPECT_GT(both, 1000) << "the objects must overlap on screen";
  return first;
}

void expectFarCoverage(const ImageComparison& c, int disagreements, int minHits) {
  EXPECT_GT(c.referenceHits, minHits);
  EXPECT_LE(c.disagreements, disagreements) << "pixels whose coverage differs from the reference";
  EXPECT_EQ(c.interiorHoles, 0);
  EXPECT_EQ(c.interiorExtras, 0);
}

void expectFarNormals(const Frame& normals, const hsdf::ReferenceImage& reference, const ImageComparison& c,
                      const std::string& label, double outlierShare, double p99Degrees) {
  const std::vector<bool> wrong = wrongPixels(normals, reference, kFarNormalDegrees);
  const int outliers = int(std::count(wrong.begin(), wrong.end(), true));
  std::printf("[ %s ] normals more than %.0f deg off: %d of %d hits\n", label.c_str(), kFarNormalDegrees, outliers,
              c.referenceHits);
  EXPECT_LE(outliers, int(outlierShare * c.referenceHits)) << "normals more than " << kFarNormalDegrees << " degrees off";
  EXPECT_LT(c.normalErrorP99Degrees, p99Degrees);
}

namespace {

std::size_t coveredPixels(const Frame& frame) {
  return std::size_t(std::count_if(frame.depth.begin(), frame.depth.end(), [](float d) { return d > 0.0f; }));
}

}  // namespace

HermiteGpuTest::WarmedPipelines HermiteGpuTest::warmedCounts() const {
  WarmedPipelines counts;
  if (auto* cells = renderer_->feature<hsdf::HermiteCellFeature>()) counts.cells = cells->pipelineCounts();
  if (auto* tracer = renderer_->feature<hsdf::SphereTraceFeature>()) counts.tracer = tracer->pipelineCounts();
  return counts;
}

std::uint32_t HermiteGpuTest::compiledByModule() const {
  const WarmedPipelines counts = warmedCounts();
  return counts.cells.compiled + counts.tracer.compiled;
}

void HermiteGpuTest::setWarming(bool warm) {
  if (auto* cells = renderer_->feature<hsdf::HermiteCellFeature>()) cells->settings().warmPipelines = warm;
  if (auto* tracer = renderer_->feature<hsdf::SphereTraceFeature>()) tracer->settings().warmPipelines = warm;
}

void HermiteGpuTest::waitForWarmers() {
  if (auto* cells = renderer_->feature<hsdf::HermiteCellFeature>()) cells->waitForWarmPipelines();
  if (auto* tracer = renderer_->feature<hsdf::SphereTraceFeature>()) tracer->waitForWarmPipelines();
}

// One run of expectSwitchesAfterWarmingCompileNothing: the switch frames, read back.
std::vector<Frame> HermiteGpuTest::switchFrames(bool warm, const std::function<void()>& createFeatures,
                                                const std::shared_ptr<const hsdf::SdfAsset>& asset,
                                                const render::CameraView& camera, hsdf::RenderMethod start,
                                                std::span<const hsdf::RenderMethod> switches,
                                                WarmedPipelines& warmed) {
  registry_ = ecs::Registry();
  createFeatures();
  setWarming(warm);
  const ecs::Entity entity = addTracedSdf(registry_, asset, start);
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  waitForWarmers();
  warmed = warmedCounts();
  const std::uint32_t before = compiledByModule();
  std::vector<Frame> frames;
  for (const hsdf::RenderMethod method : switches) {
    const std::uint32_t compiled = compiledByModule();
    registry_.get<hsdf::HermiteSdfRenderable>(entity).method = method;
    frames.push_back(renderWith(camera, DEBUG_VIEW_NONE));
    if (warm) {
      EXPECT_EQ(compiledByModule(), compiled) << "the frame switching from " << hsdf::renderMethodName(start)
                                              << " to " << hsdf::renderMethodName(method) << " compiled "
                                              << compiledByModule() - compiled << " pipeline(s)";
    }
    start = method;
  }
  if (!warm) {
    EXPECT_GT(compiledByModule(), before) << "the switch frames of a renderer that never warmed compiled nothing";
  }
  return frames;
}

HermiteGpuTest::WarmedPipelines HermiteGpuTest::expectSwitchesAfterWarmingCompileNothing(
    const std::function<void()>& createFeatures, const std::shared_ptr<const hsdf::SdfAsset>& asset,
    const render::CameraView& camera, hsdf::RenderMethod start, std::span<const hsdf::RenderMethod> switches) {
  WarmedPipelines warmed, cold;
  const std::vector<Frame> warmedFrames = switchFrames(true, createFeatures, asset, camera, start, switches, warmed);
  const std::vector<Frame> coldFrames = switchFrames(false, createFeatures, asset, camera, start, switches, cold);
  EXPECT_EQ(warmedFrames.size(), coldFrames.size());
  for (std::size_t i = 0; i < std::min(warmedFrames.size(), coldFrames.size()); ++i) {
    const char* method = hsdf::renderMethodName(switches[i]);
    EXPECT_GT(coveredPixels(warmedFrames[i]), 500u) << "switch to " << method;
    EXPECT_TRUE(warmedFrames[i].depth == coldFrames[i].depth) << "switch to " << method;
    EXPECT_TRUE(warmedFrames[i].rgba == coldFrames[i].rgba) << "switch to " << method;
  }
  return warmed;
}

}  // namespace gputest
