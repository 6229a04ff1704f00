// The Viewer's camera (viewer.h): the orbit and fly controllers, and the glTF scene's cameras.
#include <algorithm>
#include <charconv>
#include <cmath>

#include <GLFW/glfw3.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/render/components.h"
#include "engine/scene/transform.h"
#include "viewer.h"

namespace samples {

using namespace engine;

namespace {

// What the first gesture in a scene camera's view turns into: fly for the fly camera's keys and
// right-drag look, orbit for the orbit gestures, nothing (Scene) while nothing moves.
CameraMode gestureMode(const platform::InputState& input) {
  if (!input.uiWantsKeyboard)
    for (int key : {GLFW_KEY_W, GLFW_KEY_A, GLFW_KEY_S, GLFW_KEY_D, GLFW_KEY_Q, GLFW_KEY_E})
      if (input.keys[key]) return CameraMode::Fly;
  if (input.uiWantsMouse) return CameraMode::Scene;
  // Drags: motion while the button was down (a click after moving the mouse is not one).
  auto dragged = [](glm::vec2 d) { return d.x != 0.0f || d.y != 0.0f; };
  if (dragged(input.rightDrag)) return CameraMode::Fly;
  if (dragged(input.leftDrag) || input.middleButton || input.scrollDelta != 0.0f) return CameraMode::Orbit;
  return CameraMode::Scene;
}

std::string cameraList(const std::vector<std::string>& names) {
  return names.empty() ? "the scene has none" : fmt::format("the scene's cameras: {}", fmt::join(names, ", "));
}

}  // namespace

void Viewer::setOrbitView(int index) {
  cameraMode_ = CameraMode::Orbit;
  const VkExtent2D extent = renderer_ ? renderer_->extent() : VkExtent2D{1, 1};
  orbit_ = platform::framingOrbit(boundsMin_, boundsMax_, fovY_, index,
                                  float(extent.width) / float(std::max(extent.height, 1u)));
}

void Viewer::setCamera(const glm::dvec3& eye, const glm::dvec3& target) {
  cameraMode_ = CameraMode::Orbit;
  // In double: a distance that fits a float may have a square that does not.
  const double distance = glm::length(eye - target);
  const glm::dvec3 d = (eye - target) / distance;
  orbit_.target = glm::vec3(target);
  orbit_.radius = float(distance);
  orbit_.minRadius = std::min(orbit_.minRadius, orbit_.radius);
  orbit_.maxRadius = std::max(orbit_.maxRadius, orbit_.radius);
  orbit_.pitch = float(std::asin(std::clamp(d.y, -1.0, 1.0)));
  orbit_.yaw = float(std::atan2(d.x, d.z));
}

render::CameraView Viewer::cameraView() const {
  const VkExtent2D extent = renderer_->extent();
  const float aspect = float(extent.width) / float(std::max(extent.height, 1u));
  if (cameraMode_ == CameraMode::Scene) {
    // A camera node the scene has since removed or collapsed leaves the view where the orbit was.
    if (Expected<render::CameraView> view = sceneCameraView(sceneCamera_); view) return *view;
  }
  if (cameraMode_ == CameraMode::Fly)
    return render::CameraView::lookAt(fly_.position, fly_.position + fly_.forward(), fovY_, znear_, aspect);
  return render::CameraView::lookAt(orbit_.eye(), orbit_.target, fovY_, znear_, aspect);
}

void Viewer::setCameraMode(CameraMode mode) {
  if (mode == cameraMode_ || mode == CameraMode::Scene) return;
  // The eye and view direction of the camera now, whichever controller or node placed it.
  const render::CameraView now = cameraView();
  const glm::vec3 eye = now.position;
  const glm::vec3 d = -glm::normalize(glm::vec3(glm::inverse(now.view)[2]));
  if (mode == CameraMode::Orbit) {  // around the point as far ahead as the orbit's radius
    setCamera(glm::dvec3(eye), glm::dvec3(eye + d * orbit_.radius));
    return;
  }
  cameraMode_ = mode;
  fly_.position = eye;
  fly_.pitch = std::asin(std::clamp(d.y, -1.0f, 1.0f));
  fly_.yaw = std::atan2(-d.x, -d.z);  // FlyController::forward() inverted
  fly_.speed = 0.5f * glm::length(boundsMax_ - boundsMin_);  // half the scene per second
}

void Viewer::moveCamera(const platform::InputState& input, float dt) {
  if (cameraMode_ == CameraMode::Scene) setCameraMode(gestureMode(input));
  if (cameraMode_ == CameraMode::Orbit) orbit_.update(input);
  else if (cameraMode_ == CameraMode::Fly)
    fly_.update(input, std::min(dt, 0.1f));  // a stall does not throw the camera across the scene
}

void Viewer::collectSceneCameras(const std::vector<ecs::Entity>& cameras) {
  sceneCameraNames_.clear();
  sceneCameras_.clear();
  if (cameraMode_ == CameraMode::Scene) cameraMode_ = CameraMode::Orbit;
  for (const ecs::Entity entity : cameras) {
    const scene::Name* name = registry_.tryGet<scene::Name>(entity);
    sceneCameraNames_.push_back(name && !name->value.empty() ? name->value
                                                             : fmt::format("camera {}", sceneCameraNames_.size()));
    sceneCameras_.push_back(entity);
  }
}

Expected<render::CameraView> Viewer::sceneCameraView(std::size_t index) const {
  if (index >= sceneCameras_.size()) return makeError("no such scene camera");
  const ecs::Entity entity = sceneCameras_[index];
  const auto* world = registry_.tryGet<scene::WorldTransform>(entity);
  const auto* camera = registry_.tryGet<render::Camera>(entity);
  if (!world || !camera) return makeError("its node is no longer in the scene");
  const VkExtent2D extent = renderer_->extent();
  const float aspect = float(extent.width) / float(std::max(extent.height, 1u));
  return render::CameraView::fromWorld(world->matrix, *camera, aspect);
}

// A node's name first, then a camera's own name (exporters name both; Blender's camera data is
// "Camera.001" under the node "Camera"), then an index.
Expected<std::size_t> Viewer::findSceneCamera(std::string_view nameOrIndex) const {
  const auto named = std::find(sceneCameraNames_.begin(), sceneCameraNames_.end(), nameOrIndex);
  if (named != sceneCameraNames_.end()) return std::size_t(named - sceneCameraNames_.begin());
  for (std::size_t i = 0; i < sceneCameras_.size(); ++i)
    if (const auto* camera = registry_.tryGet<render::Camera>(sceneCameras_[i]); camera && !camera->name.empty() && camera->name == nameOrIndex)
      return i;
  std::size_t index = 0;  // not a name: an index
  const char* end = nameOrIndex.data() + nameOrIndex.size();
  const auto parsed = std::from_chars(nameOrIndex.data(), end, index);
  if (parsed.ec != std::errc() || parsed.ptr != end || index >= sceneCameraNames_.size())
    return makeError(fmt::format("scene camera '{}': no camera of that name or index ({})", nameOrIndex,
                                 cameraList(sceneCameraNames_)));
  return index;
}

Status Viewer::lookThroughSceneCamera(std::string_view nameOrIndex) {
  ENGINE_TRY_ASSIGN(const std::size_t index, findSceneCamera(nameOrIndex));
  return lookThroughSceneCamera(index);
}

Status Viewer::lookThroughSceneCamera(std::size_t index) {
  if (index >= sceneCameraNames_.size())
    return makeError(fmt::format("scene camera {}: no camera of that index ({})", index, cameraList(sceneCameraNames_)));
  scene::updateWorldTransforms(registry_);  // a node moved since the last frame is seen where it is now
  const std::string& name = sceneCameraNames_[index];
  ENGINE_TRY_ASSIGN(const render::CameraView view, sceneCameraView(index).withContext("scene camera '" + name + "'"));
  const double reach = glm::length(glm::dvec3(view.position) - 0.5 * (glm::dvec3(boundsMin_) + glm::dvec3(boundsMax_)));
  if (!(reach <= kMaxSceneSize))
    return makeError(fmt::format("scene camera '{}': its eye is {:g} from the scene's centre, more than the {:g} "
                                 "the viewer draws",
                                 name, reach, kMaxSceneSize));
  sceneCamera_ = index;
  cameraMode_ = CameraMode::Scene;
  return {};
}

}  // namespace samples
