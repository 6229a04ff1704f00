#pragma once
// One owned Vulkan object of a device: destroyed with its vkDestroy* call when the holder goes.
// A constructor that makes several objects keeps each in a holder from the moment it is created,
// so a throw or an error return half-way gives back what was made (a constructor that throws runs
// no destructor of its own class, but does run its members' and locals').
#include <utility>

#include <vulkan/vulkan.h>

namespace engine::gpu {

template <class Handle, void (*Destroy)(VkDevice, Handle, const VkAllocationCallbacks*)>
class DeviceHandle {
 public:
  DeviceHandle() = default;
  DeviceHandle(VkDevice device, Handle handle) : device_(device), handle_(handle) {}
  ~DeviceHandle() { reset(); }
  DeviceHandle(DeviceHandle&& other) noexcept
      : device_(std::exchange(other.device_, VK_NULL_HANDLE)), handle_(std::exchange(other.handle_, VK_NULL_HANDLE)) {}
  DeviceHandle& operator=(DeviceHandle&& other) noexcept {
    if (this != &other) {
      reset();
      device_ = std::exchange(other.device_, VK_NULL_HANDLE);
      handle_ = std::exchange(other.handle_, VK_NULL_HANDLE);
    }
    return *this;
  }
  DeviceHandle(const DeviceHandle&) = delete;
  DeviceHandle& operator=(const DeviceHandle&) = delete;

  Handle get() const { return handle_; }
  explicit operator bool() const { return handle_ != VK_NULL_HANDLE; }
  // For vkCreate*'s output parameter: the holder owns what the call writes, even when the call
  // (or fault injection, for a call the driver completed) then reports a failure.
  Handle* receive(VkDevice device) {
    reset();
    device_ = device;
    return &handle_;
  }
  void reset() noexcept {
    if (handle_ != VK_NULL_HANDLE) Destroy(device_, handle_, nullptr);
    handle_ = VK_NULL_HANDLE;
  }

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  Handle handle_ = VK_NULL_HANDLE;
};

// Plain functions with the destroy signature: the vkDestroy* prototypes carry VKAPI_CALL, which
// need not be the default calling convention (32-bit Windows).
inline void destroyQueryPool(VkDevice d, VkQueryPool h, const VkAllocationCallbacks* a) { vkDestroyQueryPool(d, h, a); }
inline void destroySampler(VkDevice d, VkSampler h, const VkAllocationCallbacks* a) { vkDestroySampler(d, h, a); }
inline void destroySemaphore(VkDevice d, VkSemaphore h, const VkAllocationCallbacks* a) { vkDestroySemaphore(d, h, a); }
inline void destroySwapchain(VkDevice d, VkSwapchainKHR h, const VkAllocationCallbacks* a) {
  vkDestroySwapchainKHR(d, h, a);
}

using QueryPoolHandle = DeviceHandle<VkQueryPool, destroyQueryPool>;
using SamplerHandle = DeviceHandle<VkSampler, destroySampler>;
using SemaphoreHandle = DeviceHandle<VkSemaphore, destroySemaphore>;
using SwapchainHandle = DeviceHandle<VkSwapchainKHR, destroySwapchain>;

}  // namespace engine::gpu
