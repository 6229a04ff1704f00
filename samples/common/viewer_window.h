#pragma once
// The Viewer's window and its swapchain (windowed viewers only): events, the time between frames,
// minimise and restore, resize requests, v-sync, full screen, and a new swapchain whenever the old
// one is out of date or the framebuffer has another size.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/core/expected.h"

namespace engine::gpu {
class Context;
class Swapchain;
}  // namespace engine::gpu
namespace engine::platform {
class Window;
}
namespace engine::render {
class Renderer;
}

namespace samples {

class ViewerWindow {
 public:
  // The window comes before the device: the device needs its instance extensions.
  static engine::Expected<std::unique_ptr<ViewerWindow>> create(const std::string& title, std::uint32_t width,
                                                               std::uint32_t height);
  ~ViewerWindow();
  ViewerWindow(const ViewerWindow&) = delete;
  ViewerWindow& operator=(const ViewerWindow&) = delete;

  // The surface on `context` and its swapchain (whose extent the renderer is created with).
  engine::Status createSwapchain(engine::gpu::Context& context);
  // Before the device goes: the swapchain and the surface.
  void destroySwapchain(engine::gpu::Context& context);
  engine::gpu::Swapchain& swapchain() { return *swapchain_; }
  engine::platform::Window& window() { return *window_; }
  bool shouldClose() const;

  // Starts the clock of secondsSinceLastFrame() (at the end of the viewer's creation).
  void startFrameClock();
  float secondsSinceLastFrame();

  // Handles the window's events; whether the window can be drawn. While minimised it waits for
  // events (at most 50 ms) instead, so that the caller's loop (scripts, finished bakes, closing)
  // goes on without spinning.
  bool pollEvents();
  // A new swapchain when the old one is stale or the framebuffer has another size.
  engine::Status fitSwapchain(engine::render::Renderer& renderer);
  // A minimised window (or a 0x0 framebuffer) gets no swapchain: the old one waits, marked stale,
  // and the first drawable frame recreates it (an out-of-date swapchain may report the old size).
  engine::Status recreateSwapchain(engine::render::Renderer& renderer);
  // Swapchains created after the first (resize, out of date, suboptimal, restore).
  std::uint64_t swapchainRecreations() const { return swapchainRecreations_; }

  // The present mode is fixed at swapchain creation: a new swapchain (later, when minimised).
  engine::Status setVsync(bool vsync, engine::render::Renderer& renderer);
  bool vsync() const { return vsync_; }
  void setFullscreen(bool fullscreen);
  bool fullscreen() const;
  // Asks the window system and waits (at most 2 s) until it has done it; an error when it did not
  // (X11 without a window manager).
  engine::Status setMinimized(bool minimized);
  // Asks for a new size (applied asynchronously by the window system); waitForSize() waits (at most
  // 2 s) until the window has the size last asked for, an error if the window system did not apply it.
  void requestSize(std::uint32_t width, std::uint32_t height);
  engine::Status waitForSize();

 private:
  ViewerWindow() = default;

  std::unique_ptr<engine::platform::Window> window_;
  std::unique_ptr<engine::gpu::Swapchain> swapchain_;
  double lastFrameTime_ = 0.0;  // seconds on the steady clock
  bool vsync_ = true;
  VkExtent2D requestedSize_{0, 0};  // the last requestSize()
  bool swapchainStale_ = false;  // out of date or resized while it could not be recreated (minimised)
  std::uint64_t swapchainRecreations_ = 0;
  std::uint64_t skippedSteps_ = 0;  // polls of the current minimised spell
};

}  // namespace samples
