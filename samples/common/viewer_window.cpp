#include "viewer_window.h"

#include <chrono>

#include <fmt/format.h>

#include "engine/core/log.h"
#include "engine/gpu/context.h"
#include "engine/gpu/swapchain.h"
#include "engine/platform/window.h"
#include "engine/render/renderer.h"

namespace samples {

using namespace engine;

namespace {

double nowSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// How long a script waits for the window system to apply a request (minimise, restore, resize).
constexpr double kWindowSystemSeconds = 2.0;

// Handles window events until `done()` or kWindowSystemSeconds have passed; whether it is done.
template <class Done>
bool waitForWindowSystem(platform::Window& window, Done done) {
  const double deadline = nowSeconds() + kWindowSystemSeconds;
  while (!done() && nowSeconds() < deadline) window.waitEvents(0.01);
  return done();
}

}  // namespace

Expected<std::unique_ptr<ViewerWindow>> ViewerWindow::create(const std::string& title, std::uint32_t width,
                                                             std::uint32_t height) {
  std::unique_ptr<ViewerWindow> window(new ViewerWindow());
  ENGINE_TRY_ASSIGN(window->window_, platform::Window::create(title, int(width), int(height)));
  return window;
}

ViewerWindow::~ViewerWindow() = default;

Status ViewerWindow::createSwapchain(gpu::Context& context) {
  ENGINE_TRY(window_->createSurface(context.instance()));
  ENGINE_TRY_ASSIGN(swapchain_, gpu::Swapchain::create(context, window_->surface(), window_->framebufferExtent(), true));
  return {};
}

void ViewerWindow::destroySwapchain(gpu::Context& context) {
  swapchain_.reset();
  window_->destroySurface(context.instance());
}

bool ViewerWindow::shouldClose() const { return window_->shouldClose(); }

void ViewerWindow::startFrameClock() { lastFrameTime_ = nowSeconds(); }

float ViewerWindow::secondsSinceLastFrame() {
  const double now = nowSeconds();
  const float dt = float(now - lastFrameTime_);
  lastFrameTime_ = now;
  return dt;
}

Status ViewerWindow::recreateSwapchain(render::Renderer& renderer) {
  swapchainStale_ = true;
  if (window_->minimized()) return {};
  ENGINE_TRY(swapchain_->recreate(window_->framebufferExtent()));
  swapchainStale_ = false;
  ++swapchainRecreations_;
  log::debug("swapchain recreated: {}x{}", swapchain_->extent().width, swapchain_->extent().height);
  renderer.resize(swapchain_->extent());
  return {};
}

bool ViewerWindow::pollEvents() {
  constexpr double kMinimizedWaitSeconds = 0.05;
  window_->pollEvents();
  if (window_->minimized()) {
    if (skippedSteps_++ == 0) {
      const VkExtent2D e = window_->framebufferExtent();
      log::info("window minimised (framebuffer {}x{}): drawing nothing until it is restored", e.width, e.height);
    }
    window_->waitEvents(kMinimizedWaitSeconds);
    return false;
  }
  if (skippedSteps_ > 0) {
    log::info("window restored after {} step(s) without a frame", skippedSteps_);
    skippedSteps_ = 0;
  }
  return true;
}

Status ViewerWindow::fitSwapchain(render::Renderer& renderer) {
  const VkExtent2D extent = window_->framebufferExtent();
  if (swapchainStale_ || extent.width != swapchain_->extent().width || extent.height != swapchain_->extent().height)
    ENGINE_TRY(recreateSwapchain(renderer));
  return {};
}

Status ViewerWindow::setVsync(bool vsync, render::Renderer& renderer) {
  if (!swapchain_ || vsync == vsync_) return {};
  swapchain_->setVsync(vsync);
  vsync_ = vsync;
  return recreateSwapchain(renderer);
}

void ViewerWindow::setFullscreen(bool fullscreen) { window_->setFullscreen(fullscreen); }

bool ViewerWindow::fullscreen() const { return window_->fullscreen(); }

Status ViewerWindow::setMinimized(bool minimized) {
  if (minimized) window_->iconify();
  else window_->restore();
  if (!waitForWindowSystem(*window_, [&] { return window_->minimized() == minimized; }))
    return makeError(fmt::format("the window system did not {} the window within {} s (X11 needs a window manager for this)",
                                 minimized ? "minimise" : "restore", kWindowSystemSeconds));
  return {};
}

void ViewerWindow::requestSize(std::uint32_t width, std::uint32_t height) {
  window_->setSize(int(width), int(height));
  requestedSize_ = {width, height};
}

Status ViewerWindow::waitForSize() {
  if (requestedSize_.width == 0) return {};
  auto reached = [this] {
    const VkExtent2D e = window_->framebufferExtent();
    return e.width == requestedSize_.width && e.height == requestedSize_.height;
  };
  if (!waitForWindowSystem(*window_, reached))
    return makeError(fmt::format("the window system did not resize the window to {}x{} within {} s", requestedSize_.width,
                                 requestedSize_.height, kWindowSystemSeconds));
  return {};
}

}  // namespace samples
