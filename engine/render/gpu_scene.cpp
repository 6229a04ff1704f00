#include "engine/render/gpu_scene.h"

#include <cmath>

namespace engine::render {

namespace {
bool finite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}
}  // namespace

bool drawableTransform(const glm::mat4& model) {
  if (!finite(model)) return false;
  if (model[0][3] != 0.0f || model[1][3] != 0.0f || model[2][3] != 0.0f || model[3][3] != 1.0f) return false;
  // The shaders use the float inverse: it must exist and be finite.
  return glm::determinant(glm::dmat3(model)) != 0.0 && finite(glm::inverse(model));
}

bool mirrors(const glm::mat4& model) { return glm::determinant(glm::dmat3(model)) < 0.0; }

GpuScene::GpuScene(const gpu::Context& context, std::uint32_t framesInFlight)
    : buffer_(context, framesInFlight, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "gpu scene objects") {}

glm::dvec3 eyeInObject(const glm::mat4& model, const glm::vec3& eye) {
  return glm::dvec3(glm::inverse(glm::dmat4(model)) * glm::dvec4(glm::dvec3(eye), 1.0));
}

std::uint32_t GpuScene::addObject(const shader::ObjectData& object) {
  // An affine model: its inverse is the linear part's, with the shifted translation brought back.
  const glm::dmat3 inverseLinear = glm::inverse(glm::dmat3(object.model));
  const glm::dvec3 translation = glm::dvec3(object.model[3]) - origin_;
  glm::dmat4 model{glm::dmat3(object.model)}, inverse{inverseLinear};
  model[3] = glm::dvec4(translation, 1.0);
  inverse[3] = glm::dvec4(-(inverseLinear * translation), 1.0);
  shader::ObjectData shifted = object;
  shifted.model = glm::mat4(model);
  shifted.invModel = glm::mat4(inverse);
  objects_.push_back(shifted);
  return static_cast<std::uint32_t>(objects_.size() - 1);
}

void GpuScene::upload(std::uint32_t frame) {
  // Always upload at least one record so the buffer (and its address) exists.
  if (objects_.empty()) {
    const shader::ObjectData empty{};
    buffer_.upload(frame, &empty, sizeof(empty));
    return;
  }
  buffer_.upload(frame, objects_);
}

shader::ObjectData GpuScene::makeObject(const glm::mat4& model, const glm::vec4& color, float roughness,
                                        float metallic, std::uint32_t feature) {
  shader::ObjectData object{};
  object.model = model;
  object.invModel = glm::inverse(model);
  object.color = color;
  object.material = glm::vec4(roughness, metallic, 0.0f, 0.0f);
  object.payload = 0;
  object.feature = feature;
  object.flags = mirrors(model) ? OBJECT_FLAG_MIRRORED : 0u;
  return object;
}

}  // namespace engine::render
