#include "hermite_sdf/render/renderable.h"

#include <algorithm>
#include <iterator>

#include "engine/ecs/registry.h"
#include "engine/scene/transform.h"

namespace hsdf {

static_assert(std::size(kRenderMethods) == std::size_t(RenderMethod::CellBricks) + 1,
              "kRenderMethods lists every RenderMethod");

const char* renderMethodName(RenderMethod method) {
  switch (method) {
    case RenderMethod::Cells: return "cells";
    case RenderMethod::TrilinearSphereTrace: return "trilinear";
    case RenderMethod::HermiteSphereTrace: return "hermite";
    case RenderMethod::CellRuns: return "cells-runs";
    case RenderMethod::CellBricks: return "cell-bricks";
  }
  return "?";
}

std::optional<RenderMethod> parseRenderMethod(std::string_view name) {
  for (const RenderMethod method : kRenderMethods)
    if (name == renderMethodName(method)) return method;
  return std::nullopt;
}

bool hasSdfObjects(const engine::ecs::Registry& registry) {
  const auto objects = registry.view<HermiteSdfRenderable, engine::scene::WorldTransform>();
  return std::any_of(objects.begin(), objects.end(), [&](engine::ecs::Entity entity) {
    return objects.get<HermiteSdfRenderable>(entity).asset != nullptr;
  });
}

}  // namespace hsdf
