#pragma once
// The window's swapchain. The renderer draws offscreen and blits into the acquired image, so the
// swapchain only needs TRANSFER_DST usage and any colour format.
#include <cstdint>
#include <memory>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/core/expected.h"

namespace engine::gpu {

class Context;

class Swapchain {
 public:
  static Expected<std::unique_ptr<Swapchain>> create(const Context& context, VkSurfaceKHR surface,
                                                     VkExtent2D desiredExtent, bool vsync);
  ~Swapchain();
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  // Rebuilds the images for a new window size (waits for the GPU). An error for a window of no
  // area (0x0 while minimised): the old swapchain stays.
  Status recreate(VkExtent2D desiredExtent);
  // V-sync (FIFO) or the fastest present mode the surface has, from the next recreate() on.
  void setVsync(bool vsync) { vsync_ = vsync; }
  // Acquires the next image, signalling `imageAvailable`. False when the swapchain is out of date.
  bool acquire(VkSemaphore imageAvailable, std::uint32_t& imageIndex);
  // Presents after renderFinished(imageIndex) is signalled. False when out of date or suboptimal.
  bool present(std::uint32_t imageIndex);

  VkImage image(std::uint32_t index) const { return images_[index]; }
  VkSemaphore renderFinished(std::uint32_t index) const { return renderFinished_[index]; }
  VkExtent2D extent() const { return extent_; }
  VkFormat format() const { return format_; }

 private:
  Swapchain(const Context& context, VkSurfaceKHR surface, bool vsync)
      : context_(context), surface_(surface), vsync_(vsync) {}
  void destroySemaphores();

  const Context& context_;
  VkSurfaceKHR surface_;
  bool vsync_;
  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkExtent2D extent_{};
  std::vector<VkImage> images_;
  std::vector<VkSemaphore> renderFinished_;
};

}  // namespace engine::gpu
