#pragma once
// Refusing the SDF methods that cannot draw through an orthographic camera (drawsOrthographic):
// each such object is reported once as dropped (FrameContext::reportDropped) while the camera stays
// orthographic, and reported again after a perspective frame, so that switching cameras back and
// forth says why each time without repeating the message every frame.
#include <string>
#include <unordered_set>

#include "engine/render/render_feature.h"
#include "hermite_sdf/render/renderable.h"

namespace hsdf {

class OrthographicRefusal {
 public:
  // True when `r` must not be drawn in this frame (its method cannot draw the frame's orthographic
  // camera); the first refusal of each asset is reported.
  bool refuse(const engine::render::FrameContext& frame, const HermiteSdfRenderable& r);
  // Called once per frame before refuse(): a perspective frame forgets what was reported.
  void beginFrame(const engine::render::FrameContext& frame);

 private:
  std::unordered_set<std::string> reported_;
};

}  // namespace hsdf
