#pragma once
// What a scene puts on an entity to draw an SDF object: an immutable, shareable SdfAsset (the
// baked field and its sparse cells) and a HermiteSdfRenderable component that says how to draw it.
// Every renderer of the module (Hermite cells, and the trilinear / dense Hermite sphere-tracing
// baselines) reads the same component, so one entity can switch method at run time.
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include <glm/glm.hpp>

#include "engine/core/expected.h"
#include "hermite_sdf/cells.h"
#include "hermite_sdf/field.h"

namespace hsdf {

enum class RenderMethod : std::uint32_t {
  Cells = 0,                 // the paper's method: sparse Hermite cells, subdivision search
  TrilinearSphereTrace = 1,  // baseline: dense f in a 3D texture, hardware trilinear filtering
  HermiteSphereTrace = 2,    // baseline: dense Hermite 3D texture, manual tricubic evaluation
  // The cells, drawn as runs of kept cells along x (one box per run, at most
  // HermiteCellFeature::Settings::maxRunLength cells) walked cell by cell in the fragment shader,
  // records read by buffer device address: fewer, larger proxies than one box per cell (issue 13).
  CellRuns = 3,
  // The cells, drawn as bricks of CELL_BRICK_SIZE^3 cells (one box per brick holding a kept cell)
  // walked along the ray in the fragment shader: fewer proxies still (issue 20, step 3).
  CellBricks = 4,
};
const char* renderMethodName(RenderMethod method);

enum class NormalMode : std::uint32_t {
  Exact = 0,               // analytic gradient of the interpolant
  CentralDifferences = 1,  // six extra field evaluations (the paper's default for trilinear)
};

// A baked SDF, shared by every entity that draws it. GPU renderers cache their uploads per asset
// id; an asset never changes after creation (re-baking makes a new asset).
struct SdfAsset {
  std::string name;
  std::uint64_t id = 0;       // unique per process
  HermiteField field;         // dense samples (the sphere-tracing baselines need them); may be empty
  CellClassification classification;
  CellStream cells;           // kept cells, fp32
  CellStreamHalf cellsHalf;   // the same records in fp16
  Aabb surfaceBounds;         // bounds of the source surface (grid bounds are field.grid.bounds())
  // The interpolant is positive on the whole grid boundary (normal_cone.h, boundaryIsPositive), so
  // a ray from outside the grid box starts outside the solid and brick normal-cone culling is
  // valid for it. Computed from the kept cells by every make*Asset (dense and sparse bakes, loaded
  // files); false (never cone-cull) when unknown.
  bool boundaryPositive = false;
};

// Classifies the field's cells, extracts the kept ones (fp32 and fp16) and assigns a new id.
engine::Expected<std::shared_ptr<const SdfAsset>> makeSdfAsset(std::string name, HermiteField field,
                                                               const Aabb& surfaceBounds,
                                                               const ClassifyOptions& options = {});

// An asset from a sparse cell stream alone (e.g. a cells-only .hsdf file): drawable by the cell
// renderer only (the sphere-tracing baselines need the dense field). Errors: invalid grid.
engine::Expected<std::shared_ptr<const SdfAsset>> makeSdfAssetFromCells(std::string name, CellStream cells);

// An asset from a sparse bake (sparse_bake.h): the cells, their counts and refinement depth as
// classifyCells reports them, the source's bounds. No dense field (field.samples is empty,
// field.grid is the grid): drawable by the cell renderers only.
engine::Expected<std::shared_ptr<const SdfAsset>> makeSdfAssetFromSparseBake(std::string name, CellStream cells,
                                                                             const CellStats& stats, int refineDepth,
                                                                             const Aabb& surfaceBounds);

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

}  // namespace hsdf
