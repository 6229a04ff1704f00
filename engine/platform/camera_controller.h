#pragma once
// Camera controllers driven by InputState: orbit (drag to rotate, right-drag/scroll to zoom,
// middle-drag to pan) and fly (WASD + mouse look while the right button is held). Drags read the
// per-button drag deltas (motion while that button was down), never cursorDelta: the motion before
// a click is not a drag.
#include <glm/glm.hpp>

#include "engine/platform/input_events.h"

namespace engine::platform {

struct OrbitController {
  glm::vec3 target{0.0f};
  float radius = 3.0f;
  float yaw = 0.6f;     // radians around +Y
  float pitch = 0.35f;  // radians above the horizon
  float rotateSpeed = 0.006f;
  float zoomSpeed = 0.1f;
  // Zooming stops at these radii (framingOrbit sets them relative to the scene, so that a scene in
  // millimetres or one a micrometre across is not snapped to a fixed range).
  float minRadius = 1e-3f;
  float maxRadius = 1e5f;

  // Applies this frame's input; returns true when the camera moved.
  bool update(const InputState& input);
  glm::vec3 eye() const;
};

// An orbit that frames the box [lo, hi] for a vertical field of view fovY and an image of
// width / height `aspect`: below 1 (a portrait image) the horizontal field of view is the narrower
// and frames it. viewIndex 0..7 picks one of 8 fixed views around it (yaw in 45 degree steps, pitch
// alternating 20 and 35 degrees); the scene runner's --view and the perf capture use the same
// views. The radius is proportional to the box at any scale (a box without extent is framed as if
// it were 1 across); zooming is limited to 1e-3..1e3 times it.
OrbitController framingOrbit(const glm::vec3& lo, const glm::vec3& hi, float fovY, int viewIndex = 0,
                             float aspect = 1.0f);

struct FlyController {
  glm::vec3 position{0.0f, 0.0f, 3.0f};
  float yaw = 0.0f;
  float pitch = 0.0f;
  float speed = 1.0f;  // world units per second
  float lookSpeed = 0.004f;

  bool update(const InputState& input, float dt);
  glm::vec3 forward() const;
};

}  // namespace engine::platform
