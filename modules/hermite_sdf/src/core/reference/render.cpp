#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>

#include "engine/core/image_io.h"
#include "hermite_sdf/core/reference.h"
#include "reference/caster_internal.h"

namespace hsdf {
namespace {

constexpr int kMaxImageSide = 16384;

bool isFinite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

engine::Status validateCamera(const glm::mat4& view, const glm::mat4& proj, glm::ivec2 size) {
  if (size.x < 1 || size.y < 1 || size.x > kMaxImageSide || size.y > kMaxImageSide)
    return engine::makeError(fmt::format("image size {}x{} is outside 1..{}", size.x, size.y, kMaxImageSide));
  if (!isFinite(view) || !isFinite(proj)) return engine::makeError("view or projection matrix is not finite");
  if (glm::determinant(glm::dmat4(proj) * glm::dmat4(view)) == 0.0)
    return engine::makeError("view-projection matrix is singular");
  return {};
}

engine::Status validateModel(const glm::mat4& model) {
  if (!isFinite(model)) return engine::makeError("model matrix is not finite");
  if (model[0][3] != 0.0f || model[1][3] != 0.0f || model[2][3] != 0.0f || model[3][3] != 1.0f)
    return engine::makeError("model matrix is not affine (its last row is not 0 0 0 1)");
  if (glm::determinant(glm::dmat3(model)) == 0.0) return engine::makeError("model matrix is singular");
  return {};
}

// A world ray in object space: same points, direction renormalized (t becomes object units).
Ray toObject(const Ray& world, const glm::dmat4& inverseModel) {
  return {glm::dvec3(inverseModel * glm::dvec4(world.origin, 1.0)),
          glm::normalize(glm::dvec3(inverseModel * glm::dvec4(world.direction, 0.0)))};
}

// Rays of every pixel centre in object space, each from its point on the near plane (the GPU draws
// nothing nearer: with the near plane through the surface, a pixel shows what lies behind it); an
// error if the camera cannot produce valid rays.
engine::Expected<std::vector<Ray>> cameraRays(const glm::mat4& view, const glm::mat4& proj, glm::ivec2 size,
                                              const glm::mat4& model) {
  ENGINE_TRY(validateCamera(view, proj, size));
  ENGINE_TRY(validateModel(model));
  const glm::dmat4 inverseModel = glm::inverse(glm::dmat4(model));
  std::vector<Ray> rays(std::size_t(size.x) * std::size_t(size.y));
  try {
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x)
        rays[std::size_t(y) * std::size_t(size.x) + std::size_t(x)] = toObject(
            engine::math::pixelRayFromNearPlane(view, proj, glm::vec2(float(x) + 0.5f, float(y) + 0.5f), size),
            inverseModel);
  } catch (const std::invalid_argument& e) {
    return engine::makeError(fmt::format("camera cannot produce pixel rays: {}", e.what()));
  }
  for (const Ray& ray : rays)
    ENGINE_TRY(detail::validateRay(ray, CastOptions{}).withContext("camera ray"));
  return rays;
}

ReferenceImage emptyImage(glm::ivec2 size) {
  ReferenceImage image;
  image.width = size.x;
  image.height = size.y;
  const std::size_t count = std::size_t(size.x) * std::size_t(size.y);
  image.depth.assign(count, 0.0f);
  image.normal.assign(count, glm::vec3(0.0f));
  image.hit.assign(count, 0);
  image.cellId.assign(count, -1);
  return image;
}

// Casts every pixel's ray with `cast` on worker threads (rows handed out in order).
template <class Cast>
ReferenceImage renderWith(const GridSpec& grid, const std::vector<Ray>& rays, const glm::mat4& view,
                          const glm::mat4& proj, glm::ivec2 size, const RenderOptions& options, const Cast& cast) {
  ReferenceImage image = emptyImage(size);
  const glm::dmat4 objectToClip = glm::dmat4(proj) * glm::dmat4(view) * glm::dmat4(options.model);
  const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(options.model)));
  const int n = grid.cellsPerAxis();
  std::atomic<int> nextRow{0};
  auto worker = [&] {
    for (int y = nextRow.fetch_add(1); y < size.y; y = nextRow.fetch_add(1))
      for (int x = 0; x < size.x; ++x) {
        const std::size_t p = image.pixel(x, y);
        const std::optional<RayHit> hit = cast(rays[p]);
        if (!hit) continue;
        const glm::dvec4 clip = objectToClip * glm::dvec4(hit->position, 1.0);
        image.depth[p] = float(clip.z / clip.w);
        const glm::dvec3 normal = normalMatrix * hit->normal;  // zero where the gradient vanishes
        image.normal[p] = glm::vec3(normal == glm::dvec3(0.0) ? normal : glm::normalize(normal));
        image.hit[p] = 1;
        image.cellId[p] = hit->cell.x + n * (hit->cell.y + n * hit->cell.z);
      }
  };
  const unsigned threads = std::min<unsigned>(
      options.threads != 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency()), unsigned(size.y));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& thread : pool) thread.join();
  return image;
}

}  // namespace

engine::Expected<ReferenceImage> renderReference(const HermiteField& field, const glm::mat4& view,
                                                 const glm::mat4& proj, glm::ivec2 imageSize,
                                                 const CellClassification* cells, const RenderOptions& options) {
  ENGINE_TRY(detail::validateField(field));
  if (cells != nullptr) ENGINE_TRY(detail::validateClassification(field.grid, *cells));
  ENGINE_TRY_ASSIGN(const std::vector<Ray> rays, cameraRays(view, proj, imageSize, options.model));
  // Without a classification, classify here: casting through the kept cells gives the same hits as
  // casting through all of them (reference.h), and most cells a ray crosses are proven empty.
  std::optional<CellClassification> own;
  if (cells == nullptr) {
    ENGINE_TRY_ASSIGN(own, classifyCells(field, ClassifyOptions{.refineDepth = 0, .threads = options.threads}));
    cells = &*own;
  }
  return renderWith(field.grid, rays, view, proj, imageSize, options, [&](const Ray& ray) {
    return detail::castHermiteUnchecked(field, ray, CastOptions{}, cells);
  });
}

engine::Expected<ReferenceImage> renderReference(const TrilinearField& field, const glm::mat4& view,
                                                 const glm::mat4& proj, glm::ivec2 imageSize,
                                                 const RenderOptions& options) {
  ENGINE_TRY(detail::validateField(field));
  ENGINE_TRY_ASSIGN(const std::vector<Ray> rays, cameraRays(view, proj, imageSize, options.model));
  return renderWith(field.grid, rays, view, proj, imageSize, options,
                    [&](const Ray& ray) { return detail::castTrilinearUnchecked(field, ray, CastOptions{}); });
}

engine::Status writeDepthPng(const ReferenceImage& image, const std::filesystem::path& path) {
  float nearest = 0.0f, farthest = HUGE_VALF;
  for (std::size_t p = 0; p < image.hit.size(); ++p)
    if (image.hit[p]) {
      nearest = std::max(nearest, image.depth[p]);  // reverse-Z: larger is nearer
      farthest = std::min(farthest, image.depth[p]);
    }
  const float range = nearest > farthest ? nearest - farthest : 1.0f;
  std::vector<std::uint8_t> grey(image.hit.size(), 0);
  for (std::size_t p = 0; p < grey.size(); ++p)
    if (image.hit[p]) grey[p] = std::uint8_t(std::lround(55.0f + 200.0f * (image.depth[p] - farthest) / range));
  return engine::writePng(path, grey, std::uint32_t(image.width), std::uint32_t(image.height), 1);
}

engine::Status writeNormalPng(const ReferenceImage& image, const std::filesystem::path& path) {
  std::vector<std::uint8_t> rgb(image.hit.size() * 3, 0);
  for (std::size_t p = 0; p < image.hit.size(); ++p) {
    if (!image.hit[p]) continue;
    for (int c = 0; c < 3; ++c)
      rgb[3 * p + std::size_t(c)] = std::uint8_t(std::lround(std::clamp(0.5f * image.normal[p][c] + 0.5f, 0.0f, 1.0f) * 255.0f));
  }
  return engine::writePng(path, rgb, std::uint32_t(image.width), std::uint32_t(image.height), 3);
}

}  // namespace hsdf
