#include "engine/platform/window.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "engine/core/log.h"
#include "engine/gpu/vk_check.h"

namespace engine::platform {
namespace {

static_assert(int(KeyAction::Release) == GLFW_RELEASE && int(KeyAction::Press) == GLFW_PRESS &&
              int(KeyAction::Repeat) == GLFW_REPEAT);
static_assert(kMouseLeft == GLFW_MOUSE_BUTTON_LEFT && kMouseRight == GLFW_MOUSE_BUTTON_RIGHT &&
              kMouseMiddle == GLFW_MOUSE_BUTTON_MIDDLE);

Window* owner(GLFWwindow* window) { return static_cast<Window*>(glfwGetWindowUserPointer(window)); }

int& glfwUsers() {
  static int users = 0;
  return users;
}

}  // namespace

Expected<std::unique_ptr<Window>> Window::create(const std::string& title, int width, int height) {
  if (glfwUsers() == 0) {
    glfwSetErrorCallback([](int code, const char* text) { log::warn("GLFW error {}: {}", code, text); });
    if (!glfwInit()) return makeError("cannot start GLFW (no display? run with --headless)");
    if (!glfwVulkanSupported()) {
      glfwTerminate();
      return makeError("GLFW finds no Vulkan loader");
    }
  }
  ++glfwUsers();
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
  std::unique_ptr<Window> window(new Window());
  window->window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window->window_) return makeError("cannot create a " + std::to_string(width) + "x" + std::to_string(height) + " window");
  glfwSetWindowUserPointer(window->window_, window.get());
  // Input by events, not by the state at the poll: a tap or click shorter than a frame is seen,
  // and a drag is the motion while the button is down. Installed now, before the UI layer starts:
  // ImGui's GLFW backend (installed after) calls these from its own callbacks.
  glfwSetKeyCallback(window->window_, &Window::onKey);
  glfwSetMouseButtonCallback(window->window_, &Window::onMouseButton);
  glfwSetCursorPosCallback(window->window_, &Window::onCursorPos);
  glfwSetScrollCallback(window->window_, &Window::onScroll);
  double x = 0.0, y = 0.0;
  glfwGetCursorPos(window->window_, &x, &y);
  window->events_.setCursor({float(x), float(y)});
  return window;
}

Window::~Window() {
  if (window_) glfwDestroyWindow(window_);
  if (--glfwUsers() == 0) glfwTerminate();
}

std::vector<std::string> Window::requiredInstanceExtensions() {
  std::uint32_t count = 0;
  const char** names = glfwGetRequiredInstanceExtensions(&count);
  return std::vector<std::string>(names, names + count);
}

Status Window::createSurface(VkInstance instance) {
  VK_TRY(glfwCreateWindowSurface(instance, window_, nullptr, &surface_));
  return {};
}

void Window::destroySurface(VkInstance instance) {
  if (surface_) vkDestroySurfaceKHR(instance, surface_, nullptr);
  surface_ = VK_NULL_HANDLE;
}

void Window::onKey(GLFWwindow* window, int key, int /*scancode*/, int action, int /*mods*/) {
  if (Window* self = owner(window)) self->events_.onKey(key, KeyAction(action));
}

void Window::onMouseButton(GLFWwindow* window, int button, int action, int /*mods*/) {
  if (Window* self = owner(window)) self->events_.onButton(button, KeyAction(action));
}

void Window::onCursorPos(GLFWwindow* window, double x, double y) {
  if (Window* self = owner(window)) self->events_.onCursor({float(x), float(y)});
}

void Window::onScroll(GLFWwindow* window, double /*dx*/, double dy) {
  if (Window* self = owner(window)) self->events_.onScroll(float(dy));
}

void Window::pollEvents() {
  glfwPollEvents();  // runs the callbacks above (also for events waitEvents() took in)
  const bool uiWantsMouse = input_.uiWantsMouse, uiWantsKeyboard = input_.uiWantsKeyboard;
  input_ = events_.endFrame();
  input_.uiWantsMouse = uiWantsMouse;
  input_.uiWantsKeyboard = uiWantsKeyboard;
}

bool Window::shouldClose() const { return glfwWindowShouldClose(window_); }

VkExtent2D Window::framebufferExtent() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  return {std::uint32_t(w), std::uint32_t(h)};
}

bool Window::minimized() const {
  const VkExtent2D e = framebufferExtent();
  return e.width == 0 || e.height == 0 || glfwGetWindowAttrib(window_, GLFW_ICONIFIED);
}

void Window::waitEvents(double seconds) { glfwWaitEventsTimeout(seconds); }

void Window::iconify() { glfwIconifyWindow(window_); }

void Window::restore() { glfwRestoreWindow(window_); }

void Window::setSize(int width, int height) { glfwSetWindowSize(window_, width, height); }

bool Window::fullscreen() const { return glfwGetWindowMonitor(window_) != nullptr; }

void Window::setFullscreen(bool on) {
  if (on == fullscreen()) return;
  if (!on) {
    const int* r = windowedRect_;
    glfwSetWindowMonitor(window_, nullptr, r[0], r[1], r[2], r[3], GLFW_DONT_CARE);
    return;
  }
  GLFWmonitor* monitor = glfwGetPrimaryMonitor();
  const GLFWvidmode* mode = monitor ? glfwGetVideoMode(monitor) : nullptr;
  if (!mode) return;  // no monitor to fill (the caller reads fullscreen() back)
  glfwGetWindowPos(window_, &windowedRect_[0], &windowedRect_[1]);
  glfwGetWindowSize(window_, &windowedRect_[2], &windowedRect_[3]);
  glfwSetWindowMonitor(window_, monitor, 0, 0, mode->width, mode->height, mode->refreshRate);
}

}  // namespace engine::platform
