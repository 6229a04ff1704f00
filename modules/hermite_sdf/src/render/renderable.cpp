#include "hermite_sdf/render/renderable.h"

namespace hsdf {

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

}  // namespace hsdf
