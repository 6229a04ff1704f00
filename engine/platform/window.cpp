#include "engine/platform/window.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "engine/core/log.h"
#include "engine/gpu/vk_check.h"

namespace engine::platform {
namespace {

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
  glfwSetScrollCallback(window->window_, &Window::onScroll);
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

void Window::onScroll(GLFWwindow* window, double /*dx*/, double dy) {
  auto* self = static_cast<Window*>(glfwGetWindowUserPointer(window));
  if (self) self->pendingScroll_ += float(dy);
}

void Window::pollEvents() {
  glfwPollEvents();
  double x = 0.0, y = 0.0;
  glfwGetCursorPos(window_, &x, &y);
  const glm::vec2 cursor{float(x), float(y)};
  input_.cursorDelta = firstPoll_ ? glm::vec2(0.0f) : cursor - input_.cursor;
  input_.cursor = cursor;
  firstPoll_ = false;
  input_.scrollDelta = pendingScroll_;
  pendingScroll_ = 0.0f;
  input_.leftButton = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
  input_.rightButton = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  input_.middleButton = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS;
  for (int key = GLFW_KEY_SPACE; key <= GLFW_KEY_LAST && key < 512; ++key)
    input_.keys[key] = glfwGetKey(window_, key) == GLFW_PRESS;
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
