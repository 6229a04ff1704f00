#pragma once
// The window's swapchain. The renderer draws offscreen and blits into the acquired image, so the
// swapchain only needs TRANSFER_DST usage and any colour format.
#include <cstdint>
#include <memory>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/core/expected.h"
#include "engine/gpu/device_handle.h"

namespace engine::gpu {

class Context;

class Swapchain {
 public:
  static Expected<std::unique_ptr<Swapchain>> create(const Context& context, VkSurfaceKHR surface,
                                                     VkExtent2D desiredExtent, bool vsync);
  ~Swapchain();
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  // Rebuilds the images for a new window size (waits for the GPU). On an error that comes before
  // the new swapchain is asked for (a window of no area, 0x0 while minimised; a surface query that
  // failed) the old swapchain stays as it was and still presents. From the request on, Vulkan has
  // retired the old swapchain even if the new one fails: then what was made of the new one and the
  // retired old one are destroyed, and the swapchain needs a recreate (no images; extent() and
  // format() stay the old ones): acquire() reports it out of date, as the surface's own
  // out-of-date does, until a recreate() succeeds.
  Status recreate(VkExtent2D desiredExtent);
  bool needsRecreate() const { return needsRecreate_; }
  // V-sync (FIFO) or the fastest present mode the surface has, from the next recreate() on.
  void setVsync(bool vsync) { vsync_ = vsync; }
  // Acquires the next image, signalling `imageAvailable`. False when the swapchain is out of date
  // or needs a recreate (nothing is signalled then).
  bool acquire(VkSemaphore imageAvailable, std::uint32_t& imageIndex);
  // Presents after renderFinished(imageIndex) is signalled. False when out of date or suboptimal.
  bool present(std::uint32_t imageIndex);

  VkImage image(std::uint32_t index) const { return parts_.images[index]; }
  VkSemaphore renderFinished(std::uint32_t index) const { return parts_.renderFinished[index].get(); }
  VkExtent2D extent() const { return parts_.extent; }
  VkFormat format() const { return parts_.format; }

 private:
  Swapchain(const Context& context, VkSurfaceKHR surface, bool vsync)
      : context_(context), surface_(surface), vsync_(vsync) {}
  // Everything one swapchain is made of, each handle owned from its creation: a recreate builds a
  // new one aside and swaps it in only when all of it was made.
  struct Parts {
    SwapchainHandle swapchain;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkExtent2D extent{};
    std::vector<VkImage> images;
    std::vector<SemaphoreHandle> renderFinished;  // one per image
  };
  Expected<VkSwapchainCreateInfoKHR> chooseSettings(VkExtent2D desiredExtent) const;
  Expected<Parts> makeParts(const VkSwapchainCreateInfoKHR& info) const;
  Status addImages(Parts& parts) const;
  void dropRetired() noexcept;

  const Context& context_;
  VkSurfaceKHR surface_;
  bool vsync_;
  Parts parts_;
  bool needsRecreate_ = false;
};

}  // namespace engine::gpu
