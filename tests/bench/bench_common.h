#pragma once
// The bunny and its grids, loaded once per benchmark process and shared by the benchmarks.
#include <string>

#include "engine/scene/scene_data.h"
#include "hermite_sdf/core/field.h"
#include "hermite_sdf/core/mesh_source.h"

namespace hsdf::bench {

// Default padding of hsdf_bake: one cell of margin on each side of the bunny's bounding box.
inline constexpr int kDefaultPaddingCells = 1;

// World-space triangles of samples/assets/bunny.glb; aborts the process with a message if the
// asset cannot be loaded (a benchmark without its input has nothing to measure).
const engine::scene::TriangleSoup& bunnySoup();
const MeshSource& bunnySource();
// The grid hsdf_bake fits by default: cube around the bunny, K samples per axis, padding 1.
GridSpec bunnyGrid(int resolution);
// Dense Hermite field of the bunny at K (baked on first use, cached per K).
const HermiteField& bunnyField(int resolution);

// Aborts with the error's message when `result` is not ok.
void require(bool ok, const std::string& what);

}  // namespace hsdf::bench
