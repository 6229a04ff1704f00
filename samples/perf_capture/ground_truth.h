#pragma once
// Ground truth for the capture's quality metrics, on the CPU in double, from the same camera as
// the GPU frame (each pixel centre's ray from its point on the near plane,
// engine::math::pixelRayFromNearPlane: the GPU draws nothing nearer):
//   analytic shapes: the exact surface (sphere tracing of the exact distance to 1e-9 of the
//                    shape's bounding-box diagonal) and its exact normal (the analytic gradient);
//                    a ray that starts inside the shape hits where it leaves, as on the GPU;
//   meshes:          the triangle mesh itself, with geometric (face) normals: the SDF of a
//                    triangle mesh is faceted, so interpolated vertex normals are not what any SDF
//                    converges to.
// Rows of pixels are cast in parallel.
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/math.h"
#include "engine/render/camera_view.h"
#include "engine/scene/scene_data.h"
#include "hermite_sdf/core/source.h"

namespace capture {

struct TruthImage {
  int width = 0;
  int height = 0;
  std::vector<float> distance;     // along the pixel's unit ray from the eye; < 0 on a miss
  // World-space unit normal, facing the ray (an analytic shape's outward gradient where the ray
  // starts inside it, as the GPU draws it); 0 on a miss.
  std::vector<glm::vec3> normal;
  std::vector<std::int32_t> part;  // the object hit (a glTF scene's node index); -1 on a miss or unknown
  bool hit(std::size_t i) const { return distance[i] >= 0.0f; }
};

struct TruthHit {
  double distance = 0.0;
  glm::dvec3 normal{0.0};
  std::int32_t part = -1;  // the object hit, where the surface knows its objects
};

// A surface the truth can be cast against.
class TruthSurface {
 public:
  virtual ~TruthSurface() = default;
  virtual std::optional<TruthHit> cast(const engine::math::Ray& ray) const = 0;
};

// The triangle mesh (world space), in a bounding volume hierarchy of its own (median splits); a hit
// names its triangle's node (TriangleSoup::triangleNodes) where the soup has them.
std::unique_ptr<TruthSurface> meshSurface(const engine::scene::TriangleSoup& soup);
// An analytic source whose value is an exact signed distance (sphere, box, torus, capsule).
std::unique_ptr<TruthSurface> analyticSurface(std::unique_ptr<hsdf::SdfSource> source);

TruthImage castTruth(const TruthSurface& surface, const engine::render::CameraView& camera, int width, int height);

}  // namespace capture
