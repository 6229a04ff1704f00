#pragma once
// Pieces of the reference caster shared by the single-ray API and the image renderer.
#include <optional>

#include "hermite_sdf/core/reference.h"

namespace hsdf::detail {

// Cell-local coordinates of p in `cell`, clamped to [0,1]^3 (rounding at cell faces).
glm::dvec3 cellLocal(const GridSpec& grid, const glm::ivec3& cell, const glm::dvec3& p);

engine::Status validateRay(const Ray& ray, const CastOptions& options);
engine::Status validateField(const HermiteField& field);
engine::Status validateField(const TrilinearField& field);
engine::Status validateClassification(const GridSpec& grid, const CellClassification& cells);

// Casts assuming validated inputs. `cells` may be null (all cells).
std::optional<RayHit> castHermiteUnchecked(const HermiteField& field, const Ray& ray, const CastOptions& options,
                                           const CellClassification* cells);
std::optional<RayHit> castTrilinearUnchecked(const TrilinearField& field, const Ray& ray, const CastOptions& options);

}  // namespace hsdf::detail
