#include "hermite_sdf/render/orthographic_refusal.h"

#include <fmt/format.h>

namespace hsdf {

void OrthographicRefusal::beginFrame(const engine::render::FrameContext& frame) {
  if (!frame.camera.orthographic()) reported_.clear();
}

bool OrthographicRefusal::refuse(const engine::render::FrameContext& frame, const HermiteSdfRenderable& r) {
  if (!frame.camera.orthographic() || !r.asset || drawsOrthographic(r.method)) return false;
  const std::string key = fmt::format("{}/{}", renderMethodName(r.method), r.asset->name);
  if (reported_.insert(key).second)
    frame.reportDropped(fmt::format("'{}' is not drawn: the {} method does not draw through an orthographic camera",
                                    r.asset->name, renderMethodName(r.method)));
  return true;
}

}  // namespace hsdf
