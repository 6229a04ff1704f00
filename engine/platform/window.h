#pragma once
// A GLFW window with a Vulkan surface, and the input state the camera controllers read
// (gathered from the window's events: input_events.h).
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/core/expected.h"
#include "engine/platform/input_events.h"

struct GLFWwindow;

namespace engine::platform {

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

  // Polls events and makes the input state from the key, button, cursor and scroll events since
  // the last call (a key tapped or a button clicked between two calls counts as pressed; a drag is
  // only the motion while its button was down). The events arrive through GLFW callbacks that
  // create() installs; a UI backend installed later must chain to them (ImGui's GLFW backend
  // does: it calls the callbacks installed before its own) or the input stops changing.
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
  static void onKey(GLFWwindow* window, int key, int scancode, int action, int mods);
  static void onMouseButton(GLFWwindow* window, int button, int action, int mods);
  static void onCursorPos(GLFWwindow* window, double x, double y);
  static void onScroll(GLFWwindow* window, double dx, double dy);

  GLFWwindow* window_ = nullptr;
  VkSurfaceKHR surface_ = VK_NULL_HANDLE;
  InputState input_;
  InputEvents events_;  // what the callbacks saw since the last pollEvents()
  int windowedRect_[4] = {0, 0, 0, 0};  // x, y, width, height before going full screen
};

}  // namespace engine::platform
