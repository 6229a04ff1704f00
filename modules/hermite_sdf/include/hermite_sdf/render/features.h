#pragma once
// The module's render features, added to a renderer in one call: the Hermite cells (the paper's
// method, with its runs and bricks) and the trilinear / dense Hermite sphere tracers (the paper's
// baselines). Every program draws every RenderMethod with the same list: the Viewer, the perf
// capture's measurement renderer, the GPU tests that compare methods. Meshes are the engine's
// (engine::render::MeshFeature): addSceneFeatures puts them first, for scenes that have any.
#include "engine/core/expected.h"
#include "engine/render/mesh_pool.h"
#include "engine/render/renderer.h"
#include "hermite_sdf/render/sphere_trace_feature.h"

namespace hsdf {

// Adds HermiteCellFeature, then SphereTraceFeature (with `tracerOptions`). Errors: the first
// feature that fails to initialize (its pipelines), named by the renderer.
engine::Status addRenderFeatures(engine::render::Renderer& renderer,
                                 const SphereTraceFeature::Options& tracerOptions = {});

// What a scene of triangles and SDF objects draws with: the engine's MeshFeature (meshes from
// `meshes`), then addRenderFeatures. The one list of the Viewer, the perf capture's measurement
// and the GPU tests that draw meshes beside SDF objects.
engine::Status addSceneFeatures(engine::render::Renderer& renderer, engine::render::MeshPool& meshes,
                                const SphereTraceFeature::Options& tracerOptions = {});

}  // namespace hsdf
