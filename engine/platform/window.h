#pragma once
// A GLFW window with a Vulkan surface, and the input state the camera controllers read.
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <vulkan/vulkan.h>

#include "engine/core/expected.h"

struct GLFWwindow;

namespace engine::platform {

struct InputState {
  glm::vec2 cursor{0.0f};
  glm::vec2 cursorDelta{0.0f};
  float scrollDelta = 0.0f;
  bool leftButton = false;
  bool rightButton = false;
  bool middleButton = false;
  bool keys[512] = {};        // GLFW key codes
  bool uiWantsMouse = false;  // set by the UI layer: the camera ignores the mouse then
  bool uiWantsKeyboard = false;
};

class Window {
 public:
  // Fails with a clear error when there is no display or GLFW cannot start.
  static Expected<std::unique_ptr<Window>> create(const std::string& title, int width, int height);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  // Instance extensions the surface needs (pass to gpu::ContextDesc::instanceExtensions).
  static std::vector<std::string> requiredInstanceExtensions();
  Status createSurface(VkInstance instance);
  void destroySurface(VkInstance instance);
  VkSurfaceKHR surface() const { return surface_; }

  // Polls events and updates the input state (deltas are per call).
  void pollEvents();
  bool shouldClose() const;
  VkExtent2D framebufferExtent() const;  // {0,0} while minimised (Windows; X11 keeps the size)
  // Iconified, or a framebuffer of 0 width or height: nothing can be drawn (a swapchain of 0x0 is
  // invalid).
  bool minimized() const;
  // Waits for window events, at most `seconds` (a minimised window's frame loop sleeps here
  // instead of spinning, and still runs scripted commands and finished bakes).
  void waitEvents(double seconds);
  // Asks the window system to minimise (iconify) or restore the window; like setSize, applied
  // asynchronously (X11: by the window manager; without one nothing happens).
  void iconify();
  void restore();
  // Asks the window system for a new client size (applied asynchronously: framebufferExtent()
  // reports it once the window system has resized the window).
  void setSize(int width, int height);
  // Full screen on the primary monitor at its current video mode, or back to the windowed
  // position and size it had before.
  void setFullscreen(bool fullscreen);
  bool fullscreen() const;
  GLFWwindow* handle() const { return window_; }
  InputState& input() { return input_; }

 private:
  Window() = default;
  static void onScroll(GLFWwindow* window, double dx, double dy);

  GLFWwindow* window_ = nullptr;
  VkSurfaceKHR surface_ = VK_NULL_HANDLE;
  InputState input_;
  float pendingScroll_ = 0.0f;
  bool firstPoll_ = true;
  int windowedRect_[4] = {0, 0, 0, 0};  // x, y, width, height before going full screen
};

}  // namespace engine::platform
