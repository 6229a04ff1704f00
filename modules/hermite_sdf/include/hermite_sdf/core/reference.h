#pragma once
// Reference ray caster: the exact FIRST hit of the field's interpolant along a ray, in double.
// Ground truth for the GPU renderers and for image comparisons.
//
// Algorithm. The ray is clipped to the grid box and walked cell by cell (3D DDA; an origin inside
// the grid starts in its own cell). In each cell the interpolant restricted to the ray segment is a
// polynomial in the segment parameter s in [0,1] (degree 9 for the tricubic, 3 for the trilinear
// interpolant), converted exactly to Bernstein form (restrictToSegment in hermite.h). Its first
// root is found by subdivision, left half first:
//   - an interval whose Bernstein coefficients are all above the contact tolerance, or all below
//     its negative, has no root (convex hull); coefficients within it are not a proof, since a
//     root on a face two cells share is a rounding error from the end of one segment and the start
//     of the next and may round to the wrong side in both (docs/root-finding.md);
//   - an interval whose value at its start is within the contact tolerance is a hit there;
//   - an interval with end values of opposite sign and one sign variation in its coefficients has
//     exactly one root (Descartes' rule for Bernstein form): it is found by bisection in double;
//   - otherwise the interval is split, down to a width of 2^-44 of the segment; an interval that
//     small which still straddles zero is a tangential contact if |F| at its midpoint is within the
//     contact tolerance, and is root-free otherwise.
// So no sign change is ever skipped (intervals are dropped only by proof), and a double root or a
// grazing touch is reported at the touching point.
//
// Contact tolerance: |F| <= 1e-13 * scale, scale = max over the cell's corners of
// |f| + (h/3)(|fx|+|fy|+|fz|) (Hermite) or |f| (trilinear): a few hundred ulps of the cell's
// magnitudes, so it only catches contacts that rounding cannot resolve. It is 10x below the
// classification's zero band (cells.h), which is why casting through only the kept cells gives
// exactly the same hits as casting through all cells:
//   - a cell the plain test drops has all 64 coefficients of one sign and beyond the zero band
//     (>= 2^-149 * 1e-12 since some corner value is a nonzero float). Each coefficient of the
//     restriction is a sum of products of them with non-negative weights (de Casteljau with t and
//     1-t in [0,1], binomial ratios), so in floating point it keeps that sign without underflow,
//     and the first step of the root search would drop the whole segment;
//   - a cell only refinement drops has F beyond the zero band everywhere in it, far above the
//     contact tolerance plus the rounding of the restriction: no sign change and no contact.
// castRay is the straightforward path (every cell the ray crosses is searched); castRayKeptCells
// and renderReference skip the dropped cells. renderReference classifies the field itself (plain
// test, as classifyCells with refineDepth 0) when no classification is given: most cells a ray
// crosses are dropped, and that is most of the work of the straightforward path.
//
// Hits are reported for t in [tMin, tMax] along origin + t * direction (direction need not be
// unit length; t is in units of it). A ray starting inside the surface hits where it leaves.
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/expected.h"
#include "engine/core/math.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/core/field.h"

namespace hsdf {

using Ray = engine::math::Ray;

inline constexpr double kContactTolerance = 1e-13;

struct RayHit {
  double t = 0.0;
  glm::dvec3 position{0.0};
  glm::dvec3 normal{0.0};  // normalized exact gradient of the interpolant; (0,0,0) where it vanishes
  glm::ivec3 cell{0};
  bool contact = false;    // reported as a tangential contact (no sign change resolved)
};

struct CastOptions {
  double tMin = 0.0;
  double tMax = std::numeric_limits<double>::infinity();
};

// Errors: field samples not matching its grid, invalid grid, non-finite origin, zero or
// non-finite direction, tMin > tMax or NaN. A miss is an empty optional.
engine::Expected<std::optional<RayHit>> castRay(const HermiteField& field, const Ray& ray, const CastOptions& options = {});
engine::Expected<std::optional<RayHit>> castRay(const TrilinearField& field, const Ray& ray,
                                                const CastOptions& options = {});
// The same caster visiting only the cells a classification keeps (what the GPU cell renderer
// draws). Gives the same hits as castRay(field, ...), see the tolerance note above.
engine::Expected<std::optional<RayHit>> castRayKeptCells(const HermiteField& field, const CellClassification& cells,
                                                         const Ray& ray, const CastOptions& options = {});

// A CPU rendering of a field, ground truth for GPU images. Pixel (x, y), row-major from the top.
struct ReferenceImage {
  int width = 0;
  int height = 0;
  std::vector<float> depth;            // reverse-Z depth as the GPU writes it (clip z / clip w); 0 on a miss
  std::vector<glm::vec3> normal;       // world-space unit normal; (0,0,0) on a miss
  std::vector<std::uint8_t> hit;       // 1 where the ray hit the surface
  std::vector<std::int32_t> cellId;    // cx + n (cy + n cz) with n = K-1; -1 on a miss
  std::size_t pixel(int x, int y) const { return std::size_t(y) * std::size_t(width) + std::size_t(x); }
};

struct RenderOptions {
  unsigned threads = 0;  // 0: all hardware threads
  // Where the object stands: the field lies in object space, the camera in world space. Each
  // pixel's world ray is taken into object space (in double) and cast there; depth and normals are
  // reported in world space (normals by the inverse transpose). Any invertible affine matrix:
  // mirroring, non-uniform scale and shear included.
  glm::mat4 model{1.0f};
};

// Casts one ray per pixel centre with engine::math::pixelRayFromNearPlane(view, proj, (x+0.5, y+0.5),
// size): from the near plane, as a rasterizer clips what is nearer.
// `cells` (optional) restricts the cast to kept cells. Errors: image size outside 1..16384,
// invalid field or matrices (non-finite, singular view-projection, model not invertible affine).
engine::Expected<ReferenceImage> renderReference(const HermiteField& field, const glm::mat4& view,
                                                 const glm::mat4& proj, glm::ivec2 imageSize,
                                                 const CellClassification* cells = nullptr,
                                                 const RenderOptions& options = {});
engine::Expected<ReferenceImage> renderReference(const TrilinearField& field, const glm::mat4& view,
                                                 const glm::mat4& proj, glm::ivec2 imageSize,
                                                 const RenderOptions& options = {});

// PNGs for inspection: depth as grey scaled to the image's depth range (nearest hit 255, farthest
// 55, misses 0); normals as rgb = 0.5 * n + 0.5 (misses black).
engine::Status writeDepthPng(const ReferenceImage& image, const std::filesystem::path& path);
engine::Status writeNormalPng(const ReferenceImage& image, const std::filesystem::path& path);

}  // namespace hsdf
