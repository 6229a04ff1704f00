#pragma once
// What a scene puts on an entity to draw an SDF object: an immutable, shareable SdfAsset (the
// baked field and its sparse cells, hermite_sdf/core/sdf_asset.h) and a HermiteSdfRenderable
// component that says how to draw it. Every renderer of the module (Hermite cells, and the
// trilinear / dense Hermite sphere-tracing baselines) reads the same component, so one entity can
// switch method at run time.
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

#include <glm/glm.hpp>

#include "hermite_sdf/core/sdf_asset.h"

namespace engine::ecs {
class Registry;
}

namespace hsdf {

enum class RenderMethod : std::uint32_t {
  Cells = 0,                 // the paper's method: sparse Hermite cells, subdivision search
  TrilinearSphereTrace = 1,  // baseline: dense f in a 3D texture, hardware trilinear filtering
  HermiteSphereTrace = 2,    // baseline: dense Hermite 3D texture, manual tricubic evaluation
  // The cells, drawn as runs of kept cells along x (one box per run, at most
  // HermiteCellFeature::Settings::maxRunLength cells) walked cell by cell in the fragment shader,
  // records read by buffer device address: fewer, larger proxies than one box per cell.
  CellRuns = 3,
  // The cells, drawn as bricks of CELL_BRICK_SIZE^3 cells (one box per brick holding a kept cell)
  // walked along the ray in the fragment shader: fewer proxies still.
  CellBricks = 4,
};
// Every method, in the order of their values: the one list of SDF methods (the samples' method
// choice, their settings files and command lines, loop over it), with the one name table below.
inline constexpr RenderMethod kRenderMethods[] = {RenderMethod::Cells, RenderMethod::TrilinearSphereTrace,
                                                  RenderMethod::HermiteSphereTrace, RenderMethod::CellRuns,
                                                  RenderMethod::CellBricks};
// "cells", "trilinear", "hermite", "cells-runs", "cell-bricks": the names of the command lines and
// settings files. parseRenderMethod is case-sensitive, as the command line is.
const char* renderMethodName(RenderMethod method);
std::optional<RenderMethod> parseRenderMethod(std::string_view name);
// The methods that draw the asset's sparse cells (cells, cells-runs, cell-bricks); the others
// sphere-trace the dense field. The one test of it: the cell feature and the samples asked it each
// with a copy of this list, which a new method would have had to find.
constexpr bool drawsCells(RenderMethod method) {
  return method == RenderMethod::Cells || method == RenderMethod::CellRuns || method == RenderMethod::CellBricks;
}

enum class NormalMode : std::uint32_t {
  Exact = 0,               // analytic gradient of the interpolant
  CentralDifferences = 1,  // six extra field evaluations (the paper's default for trilinear)
};

// The component. The entity's engine::scene::WorldTransform places the asset's grid in the world:
// any invertible affine matrix (rotation, non-uniform scale, mirroring, shear) renders correctly,
// since every method works in object space, where the field is a distance (README, "Object
// transforms"). Objects whose matrix cannot be inverted (e.g. scaled to zero) are not drawn.
struct HermiteSdfRenderable {
  std::shared_ptr<const SdfAsset> asset;
  RenderMethod method = RenderMethod::Cells;
  std::uint32_t subdivisions = 3;  // n: equidistant evaluations per cell segment (paper: 2 or 3)
  std::uint32_t refineSteps = 1;   // safeguarded Newton steps after the linear interpolation
  NormalMode normals = NormalMode::Exact;
  // Cells: instead of the paper's n equidistant samples, a certified search (Bernstein subdivision
  // of F restricted to the ray) that never misses the first root of the interpolant, at a cost
  // measured in docs/root-finding.md. Without it a pair of roots between two samples is still found
  // when the samples show no sign change; only a pair before a later sign change can be passed over.
  bool certified = false;
  // fp16 cell records / R16F, RGBA16F textures; grids fp16 cannot hold faithfully
  // (!halfPrecisionFits(grid), cells.h: tiny or huge objects) are drawn from the fp32 data instead.
  bool halfPrecision = false;
  glm::vec4 color{0.85f, 0.55f, 0.4f, 1.0f};  // linear base colour
  float roughness = 0.45f;
};

// Whether `registry` holds an object some feature of the module may draw, in view or not, by any
// method: a HermiteSdfRenderable with an asset, placed by a WorldTransform. The one rule of when
// the cells and the tracers warm the pipelines a switch of method would bind: each warms for the
// objects the other draws, so a session that starts with either compiles nothing at the switch.
bool hasSdfObjects(const engine::ecs::Registry& registry);

}  // namespace hsdf
