#include "hermite_sdf/render/renderable.h"

#include <iterator>

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

}  // namespace hsdf
