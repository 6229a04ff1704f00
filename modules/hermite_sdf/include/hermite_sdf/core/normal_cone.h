#pragma once
// Normal cones of Hermite cells and bricks, and the brick culling tests: the C++ side of
// shaders/hermite/normal_cone.glsl, whose tests repeat the float maths of brickConeCulls and
// boxOutsideFrustum below operation for operation (brick_cull.comp keeps exactly the bricks these
// keep; tests/gpu/brick_cull_test.cpp checks it).
//
// The cone. The gradient of a cell's tricubic interpolant, with each component degree-elevated to
// the tensor-product cubic Bernstein basis, is sum_abc V_abc B_a(ux) B_b(uy) B_c(uz): a convex
// combination of 64 control vectors V_abc (hermite.h's Bernstein coefficients b give
// V = 3 (elevated forward differences of b) / h). A cone (a convex set) that holds every V holds
// every gradient in the cell. CellBrickCone::axisCutoff = (axis, w) with
//   w = sin(theta) = cos(90 deg - theta), theta the cone's half-angle: every gradient direction n
//   satisfies angle(n, axis) <= theta. w >= 1 is a cone that never culls (kNeverCullCutoff): the
//   control vectors are not all within an open half-space (theta >= 90 deg) or one is (nearly) zero.
//
// The cull test. A ray that starts where F > 0 has its first root at an entering crossing
// (grad F . ray direction <= 0): F cannot fall to 0 while rising. If grad F . (p - eye) > 0 for
// every gradient of the brick's cells and every point p of the brick, no ray from the eye has its
// first root in the brick. The gradients lie within theta of the axis, so this holds when every
// p - eye lies within 90 deg - theta of the axis: axis . (p - eye) > w |p - eye|. That set of p is
// a convex cone, so the box lies in it when its 8 corners do (exact for the box, tighter than
// niagara's bounding-sphere test). Exact in object space for any affine model matrix: the ray and
// p - eye transform alike, and grad F . d is the ray's dF/dt. The proxies' dilation and the search
// margin beyond a cell (proxy_dilation.glsl) are not covered: a root found there lies outside the
// cell, in the polynomial's extension, not in the interpolant the argument is about.
// Valid only where rays start outside the solid: see SdfAsset::raysStartOutside (renderable.h) and
// brickConeCullAllowed.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/expected.h"
#include "engine/core/progress.h"
#include "hermite/hermite_host_device.h"
#include "hermite_sdf/core/cells.h"

namespace hsdf {

inline constexpr float kNeverCullCutoff = 2.0f;
// A cone that never culls (also what a cone that cannot be built is replaced by).
inline shader::CellBrickCone neverCullCone() { return {glm::vec4(0.0f, 0.0f, 1.0f, kNeverCullCutoff)}; }
// Added to theta (radians): the GPU evaluates the interpolant in float (its gradient differs from
// the double control vectors by a few ulp) and the records are rounded; 1e-3 rad is far above both.
inline constexpr double kConeAngleMargin = 1e-3;

// The cone of every gradient of one kept cell (grid spacing h), object space.
shader::CellBrickCone cellGradientCone(const CellRecord& record, double h);

// cellGradientCone of every record of the stream, in record order, on worker threads (`threads`,
// 0: all hardware threads): the cell culling pass's cones, a few microseconds a cell (seconds at
// K >= 1024 on one thread), which is why the bake job makes them (cell_derived.h), not a frame.
// Errors: "cancelled" (the token).
engine::Expected<std::vector<shader::CellBrickCone>> cellGradientCones(const CellStream& cells, unsigned threads = 0,
                                                                       const engine::CancelToken* cancel = nullptr);

// The cone of every gradient of several cells (the union of their control vectors, so at least as
// tight as merging their cell cones). No cells: a cone that never culls.
shader::CellBrickCone brickGradientCone(const CellStream& cells, std::span<const std::uint32_t> recordIndices);

// One cone per brick, on worker threads as cellGradientCones: brick i's cells are the
// popcount(mask) record indices from indices[bricks[i].firstIndex] (hermite_host_device.h,
// CellBrickGpu). Errors: a brick whose cells run past the index list, an index past the stream's
// records (both named, checked before any cone is built), "cancelled".
engine::Expected<std::vector<shader::CellBrickCone>> brickGradientCones(const CellStream& cells,
                                                                        std::span<const shader::CellBrickGpu> bricks,
                                                                        std::span<const std::uint32_t> indices,
                                                                        unsigned threads = 0,
                                                                        const engine::CancelToken* cancel = nullptr);

// The cones cellGradientCones and brickGradientCones have built for calls made on the calling
// thread (their worker threads count for it): what shows that a thread, such as the render
// thread, left that work to the bake job.
std::uint64_t gradientConesBuiltOnThisThread();

// Whether the interpolant of these kept cells is positive on the whole grid boundary. The boundary
// is a connected union of cell faces, and f is continuous on it. Each empty cell (any cell missing
// from the stream, as the renderers treat them) is strictly of one sign, so the boundary faces of
// empty cells that share an edge have one sign; a kept cell touching the boundary must have all 16
// Bernstein coefficients of each of its boundary faces > 0. If some kept cell touches the boundary,
// that makes every face positive; if none does, the sign is read from the record with the lowest
// index (the first kept cell of its x row: the empty cell before it shares its corner 0).
bool boundaryIsPositive(const CellStream& cells);

// The brick's box in object space: cells [4 xyz, 4 xyz + 4) of the grid (origin, spacing h).
struct BrickBox {
  glm::vec3 lo{0.0f};
  glm::vec3 hi{0.0f};
};
BrickBox brickBox(std::uint32_t packedXyz, const glm::vec3& gridOrigin, float h);
// The cell's box (cell culling, cell_cull.comp): cell (x, y, z) of the grid. The twin of
// normal_cone.glsl's gridBlockBox with side h, as brickBox is with side 4h.
BrickBox cellBox(const glm::uvec3& cell, const glm::vec3& gridOrigin, float h);

// True if no ray from `eye` can have its first root in the box, gradients in `cone` (all object
// space). The twin of normal_cone.glsl's coneCullsBox.
bool coneCullsBox(const shader::CellBrickCone& cone, const BrickBox& box, const glm::vec3& eye);

// True if the box lies wholly outside one plane of the reverse-Z frustum (-w <= x, y <= w, z <= w;
// no far plane), objectToClip = viewProj * model. The twin of normal_cone.glsl's boxOutsideFrustum.
bool boxOutsideFrustum(const glm::mat4& objectToClip, const BrickBox& box);

// What the culling pass does with a brick: frustum test first, then (coneTest) the cone test.
// The twin of normal_cone.glsl's brickSurvives.
enum class BrickVerdict { Kept, FrustumCulled, ConeCulled };
BrickVerdict brickVerdict(const glm::mat4& objectToClip, const BrickBox& box, const shader::CellBrickCone& cone,
                          const glm::vec3& eye, bool coneTest);

// Whether the cone test may run for an object: its asset's rays start outside (positive boundary)
// and the near plane, reaching nearPlaneReachObject object units around the eye, stays out of the
// grid box.
bool brickConeCullAllowed(bool boundaryPositive, const glm::dvec3& eyeObject, double nearPlaneReachObject,
                          const GridSpec& grid);

}  // namespace hsdf
