#pragma once
// An immutable, shareable baked SDF: the dense field (when the bake kept one) and the sparse kept
// cells, in fp32 and fp16. The CPU half of what a scene draws; the component that draws it is
// hermite_sdf/render/renderable.h.
#include <cstdint>
#include <memory>
#include <string>

#include "engine/core/expected.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/core/field.h"
#include "hermite_sdf/core/materials.h"

namespace hsdf {

struct CellDerived;  // src/core/cells/cell_derived.h, private to the module

// A baked SDF, shared by every entity that draws it. GPU renderers cache their uploads per asset
// id; an asset never changes after creation (re-baking makes a new asset).
struct SdfAsset {
  std::string name;
  std::uint64_t id = 0;       // unique per process
  HermiteField field;         // dense samples (the sphere-tracing baselines need them); may be empty
  CellClassification classification;
  CellStream cells;           // kept cells, fp32
  CellStreamHalf cellsHalf;   // the same records in fp16
  // packProxyBox(cellProxyBox(...)) per record of cells and of cellsHalf (cells.h, "Proxy boxes").
  std::vector<std::uint16_t> proxyBoxes, proxyBoxesHalf;
  Aabb surfaceBounds;         // bounds of the source surface (grid bounds are field.grid.bounds())
  // The interpolant is positive on the whole grid boundary (normal_cone.h, boundaryIsPositive), so
  // a ray from outside the grid box starts outside the solid and brick normal-cone culling is
  // valid for it. Computed from the kept cells by every make*Asset (dense and sparse bakes, loaded
  // files); false (never cone-cull) when unknown.
  bool boundaryPositive = false;
  // A multi-material asset's palette (materials.h): the slots in field.materials, cells.materials
  // and cellsHalf.materials index it. Empty for one material: the entity's colour shades it.
  std::vector<SdfMaterial> palette;
  // What the cell renderers derive from `cells` (the cells' and bricks' normal cones, the bricks):
  // made with the asset by every make*Asset, so by the bake job on its worker thread, never by a
  // frame. Null for an asset made by hand, which the cell renderers draw unculled and not as bricks.
  std::shared_ptr<const CellDerived> derived;
};

// Classifies the field's cells, extracts the kept ones (fp32 and fp16, with their corners'
// material slots when the field has them) and assigns a new id. `palette`: the materials the
// field's slots index (checkMaterialSlots); empty with a field of one material.
engine::Expected<std::shared_ptr<const SdfAsset>> makeSdfAsset(std::string name, HermiteField field,
                                                               const Aabb& surfaceBounds,
                                                               const ClassifyOptions& options = {},
                                                               std::vector<SdfMaterial> palette = {});

// An asset from a sparse cell stream alone (e.g. a cells-only .hsdf file): drawable by the cell
// renderer only (the sphere-tracing baselines need the dense field). Errors: invalid grid.
engine::Expected<std::shared_ptr<const SdfAsset>> makeSdfAssetFromCells(std::string name, CellStream cells,
                                                                        std::vector<SdfMaterial> palette = {});

// An asset from a sparse bake (sparse_bake.h): the cells, their counts and refinement depth as
// classifyCells reports them, the source's bounds. No dense field (field.samples is empty,
// field.grid is the grid): drawable by the cell renderers only. `threads` and `cancel` as in
// ClassifyOptions, for the derived data.
engine::Expected<std::shared_ptr<const SdfAsset>> makeSdfAssetFromSparseBake(std::string name, CellStream cells,
                                                                             const CellStats& stats, int refineDepth,
                                                                             const Aabb& surfaceBounds,
                                                                             std::vector<SdfMaterial> palette = {},
                                                                             unsigned threads = 0,
                                                                             const engine::CancelToken* cancel = nullptr);

}  // namespace hsdf
