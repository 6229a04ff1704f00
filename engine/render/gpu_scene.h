#pragma once
// The GPU scene buffer: per-object data (transform, material, feature payload address) for every
// drawn object, rebuilt on the CPU each frame by the render features and reached by the shaders
// through a buffer device address in the push constants. A drawn instance finds its record with
// gl_InstanceIndex (= firstInstance of its indirect command + instance).
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/render/per_frame_buffer.h"
#include "shared/host_device.h"

namespace engine::render {

// Whether an object placed by `model` can be drawn: a finite affine matrix whose linear part can be
// inverted. Features skip other objects (e.g. scaled to zero): their normals and rays would be NaN.
bool drawableTransform(const glm::mat4& model);

// Whether `model` mirrors (negative determinant): triangles that face the camera then wind
// clockwise on screen instead of counter-clockwise.
bool mirrors(const glm::mat4& model);

// The eye relative to the object placed by `model`, in its own space, computed in double: float
// matrices far from the origin (a world position of 5000 holds only ~5e-4) would move it.
glm::dvec3 eyeInObject(const glm::mat4& model, const glm::vec3& eye);

class GpuScene {
 public:
  GpuScene(const gpu::Context& context, std::uint32_t framesInFlight);

  void beginFrame() { objects_.clear(); }
  // Camera-relative rendering: the shaders see world space shifted by -origin (the renderer sets
  // the frame's eye), the frame globals and every object's model matrix alike, each made in double.
  // Positions near the eye then keep float's precision however far from the world origin the
  // scene is; before, objects 1e4-1e5 units away showed cracks between cells (rasterized in float
  // world space, searched in exact cell space). Features pass world matrices as before.
  void setOrigin(const glm::dvec3& origin) { origin_ = origin; }
  const glm::dvec3& origin() const { return origin_; }
  // Appends an object (its world matrices, shifted here by -origin) and returns its index.
  std::uint32_t addObject(const shader::ObjectData& object);
  // An object added this frame, e.g. to set its payload address once the payload is uploaded.
  shader::ObjectData& object(std::uint32_t index) { return objects_.at(index); }
  // Uploads this frame's objects into the buffer of frame slot `frame`.
  void upload(std::uint32_t frame);
  VkDeviceAddress address(std::uint32_t frame) const { return buffer_.address(frame); }

  // Fills model, inverse model, OBJECT_FLAG_MIRRORED and material fields from a world matrix and a
  // colour. The matrix must be drawable (see drawableTransform).
  static shader::ObjectData makeObject(const glm::mat4& model, const glm::vec4& color, float roughness,
                                       float metallic, std::uint32_t feature);

 private:
  std::vector<shader::ObjectData> objects_;
  glm::dvec3 origin_{0.0};
  PerFrameBuffer buffer_;
};

}  // namespace engine::render
