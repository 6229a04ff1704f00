#include "engine/gpu/swapchain.h"

#include <algorithm>

#include "engine/gpu/context.h"
#include "engine/gpu/vk_check.h"

namespace engine::gpu {
namespace {

VkSurfaceFormatKHR chooseFormat(const std::vector<VkSurfaceFormatKHR>& formats) {
  for (const auto& f : formats)
    if ((f.format == VK_FORMAT_B8G8R8A8_SRGB || f.format == VK_FORMAT_R8G8B8A8_SRGB) &&
        f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR)
      return f;
  return formats.front();
}

}  // namespace

Expected<std::unique_ptr<Swapchain>> Swapchain::create(const Context& context, VkSurfaceKHR surface,
                                                       VkExtent2D desiredExtent, bool vsync) {
  VkBool32 supported = VK_FALSE;
  VK_TRY(vkGetPhysicalDeviceSurfaceSupportKHR(context.physicalDevice(), context.queueFamily(), surface, &supported));
  if (!supported) return makeError("the graphics queue cannot present to this window surface");
  std::unique_ptr<Swapchain> swapchain(new Swapchain(context, surface, vsync));
  ENGINE_TRY(swapchain->recreate(desiredExtent));
  return swapchain;
}

Swapchain::~Swapchain() {
  vkDeviceWaitIdle(context_.device());  // the parts' holders then destroy the semaphores and the swapchain
}

Status Swapchain::recreate(VkExtent2D desiredExtent) {
  VK_TRY(vkDeviceWaitIdle(context_.device()));
  ENGINE_TRY_ASSIGN(VkSwapchainCreateInfoKHR info, chooseSettings(desiredExtent));
  info.oldSwapchain = parts_.swapchain.get();
  // From here on the old swapchain is retired, made anew or not (vkCreateSwapchainKHR).
  needsRecreate_ = true;
  Expected<Parts> made = makeParts(info);
  if (!made) {
    dropRetired();
    return makeError("the swapchain could not be recreated (out of date until a recreate succeeds): " +
                     made.error().message);
  }
  parts_ = std::move(*made);  // the old parts are destroyed here: the device is idle
  needsRecreate_ = false;
  return {};
}

// A retired swapchain gives no more images and cannot be the oldSwapchain of the next one: it and
// its semaphores go now (the device is idle); the size and format stay as they were.
void Swapchain::dropRetired() noexcept {
  parts_.renderFinished.clear();
  parts_.images.clear();
  parts_.swapchain.reset();
}

Expected<VkSwapchainCreateInfoKHR> Swapchain::chooseSettings(VkExtent2D desiredExtent) const {
  VkPhysicalDevice physical = context_.physicalDevice();
  VkSurfaceCapabilitiesKHR caps{};
  VK_TRY(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(physical, surface_, &caps));
  std::uint32_t count = 0;
  VK_TRY(vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface_, &count, nullptr));
  std::vector<VkSurfaceFormatKHR> formats(count);
  VK_TRY(vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface_, &count, formats.data()));
  if (formats.empty()) return makeError("the window surface offers no formats");
  if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
    return makeError("the window surface does not accept transfers (TRANSFER_DST)");
  const VkSurfaceFormatKHR format = chooseFormat(formats);

  VkExtent2D extent = caps.currentExtent;
  if (extent.width == ~0u) {
    extent.width = std::clamp(desiredExtent.width, caps.minImageExtent.width, caps.maxImageExtent.width);
    extent.height = std::clamp(desiredExtent.height, caps.minImageExtent.height, caps.maxImageExtent.height);
  }
  // A minimised window (Windows) reports 0x0: such a swapchain is invalid; the caller waits.
  if (extent.width == 0 || extent.height == 0)
    return makeError("cannot make a swapchain of " + std::to_string(extent.width) + "x" + std::to_string(extent.height) +
                     ": the window has no area (minimised)");
  std::uint32_t imageCount = std::max(caps.minImageCount + 1, 2u);
  if (caps.maxImageCount) imageCount = std::min(imageCount, caps.maxImageCount);

  VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  info.surface = surface_;
  info.minImageCount = imageCount;
  info.imageFormat = format.format;
  info.imageColorSpace = format.colorSpace;
  info.imageExtent = extent;
  info.imageArrayLayers = 1;
  info.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
  info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.preTransform = caps.currentTransform;
  info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
  if (!(caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR))
    info.compositeAlpha = VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR;
  info.presentMode = vsync_ ? VK_PRESENT_MODE_FIFO_KHR : VK_PRESENT_MODE_IMMEDIATE_KHR;
  if (!vsync_) {
    std::uint32_t modeCount = 0;
    VK_TRY(vkGetPhysicalDeviceSurfacePresentModesKHR(physical, surface_, &modeCount, nullptr));
    std::vector<VkPresentModeKHR> modes(modeCount);
    VK_TRY(vkGetPhysicalDeviceSurfacePresentModesKHR(physical, surface_, &modeCount, modes.data()));
    modes.resize(modeCount);
    if (std::find(modes.begin(), modes.end(), info.presentMode) == modes.end())
      info.presentMode = VK_PRESENT_MODE_FIFO_KHR;
  }
  info.clipped = VK_TRUE;
  return info;
}

// Every failure returns an error with what was made destroyed by its holder; a name the debug
// utils refused (a throwing VK_CHECK) becomes such an error too.
Expected<Swapchain::Parts> Swapchain::makeParts(const VkSwapchainCreateInfoKHR& info) const {
  Parts parts;
  parts.format = info.imageFormat;
  parts.extent = info.imageExtent;
  try {
    VK_TRY(vkCreateSwapchainKHR(context_.device(), &info, nullptr, parts.swapchain.receive(context_.device())));
    context_.setName(parts.swapchain.get(), VK_OBJECT_TYPE_SWAPCHAIN_KHR, "swapchain");
    ENGINE_TRY(addImages(parts));
  } catch (const VulkanError& error) {
    return makeError(error.what());
  }
  return parts;
}

Status Swapchain::addImages(Parts& parts) const {
  const VkDevice device = context_.device();
  std::uint32_t count = 0;
  VK_TRY(vkGetSwapchainImagesKHR(device, parts.swapchain.get(), &count, nullptr));
  parts.images.resize(count);
  VK_TRY(vkGetSwapchainImagesKHR(device, parts.swapchain.get(), &count, parts.images.data()));
  parts.images.resize(count);
  for (std::uint32_t i = 0; i < count; ++i) {
    const VkSemaphoreCreateInfo semaphoreInfo{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    SemaphoreHandle& semaphore = parts.renderFinished.emplace_back();
    VK_TRY(vkCreateSemaphore(device, &semaphoreInfo, nullptr, semaphore.receive(device)));
    context_.setName(semaphore.get(), VK_OBJECT_TYPE_SEMAPHORE, "render finished " + std::to_string(i));
    context_.setName(parts.images[i], VK_OBJECT_TYPE_IMAGE, "swapchain image " + std::to_string(i));
  }
  return {};
}

bool Swapchain::acquire(VkSemaphore imageAvailable, std::uint32_t& imageIndex) {
  if (needsRecreate_) return false;  // a retired swapchain: asking it for an image may fail
  const VkSwapchainKHR swapchain = parts_.swapchain.get();
  const VkResult result = VK_CHECK_SWAPCHAIN(
      vkAcquireNextImageKHR(context_.device(), swapchain, UINT64_MAX, imageAvailable, VK_NULL_HANDLE, &imageIndex));
  return result != VK_ERROR_OUT_OF_DATE_KHR;
}

bool Swapchain::present(std::uint32_t imageIndex) {
  VkPresentInfoKHR info{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  info.waitSemaphoreCount = 1;
  const VkSemaphore renderFinished = parts_.renderFinished[imageIndex].get();
  const VkSwapchainKHR swapchain = parts_.swapchain.get();
  info.pWaitSemaphores = &renderFinished;
  info.swapchainCount = 1;
  info.pSwapchains = &swapchain;
  info.pImageIndices = &imageIndex;
  // Through vk_check.h's fault injection: a test can have a present that the driver completed
  // report out of date or suboptimal (an X server that resizes synchronously never does).
  const VkResult result = VK_CHECK_SWAPCHAIN(vkQueuePresentKHR(context_.queue(), &info));
  return result == VK_SUCCESS;
}

}  // namespace engine::gpu
