#pragma once
// Checked Vulkan calls. VK_CHECK names the call, the file and the line and throws
// engine::gpu::VulkanError: an unexpected VkResult from the driver is not something a frame can
// recover from, and the sample's main() reports it. Functions that can fail on user input return
// engine::Expected instead (VK_TRY converts a failed call into an Error there).
#include <atomic>
#include <cstdint>
#include <stdexcept>
#include <string>

#include <vulkan/vulkan.h>

#include "engine/core/expected.h"

namespace engine::gpu {

class VulkanError : public std::runtime_error {
 public:
  VulkanError(VkResult result, const std::string& what) : std::runtime_error(what), result_(result) {}
  VkResult result() const { return result_; }

 private:
  VkResult result_;
};

const char* resultName(VkResult result);
std::string describeFailedCall(VkResult result, const char* call, const char* file, int line);

// Fault injection at the wrapper boundary, for tests: the driver cannot be made to fail on demand
// (lavapipe has no VK_EXT_device_fault and never loses its device), so VK_CHECK / VK_TRY can be
// told to report `result` for a call the driver completed. The call itself still runs: fences
// still signal, so a test that survives the fault can tear down without hanging.
struct InjectedFault {
  std::string call;            // the Vulkan function, e.g. "vkQueueSubmit2" (exact name)
  VkResult result = VK_ERROR_DEVICE_LOST;
  std::uint32_t skip = 0;      // matching calls to let through first
  // VK_ERROR_DEVICE_LOST stays: from the fault on, every checked call reports it, as a lost device
  // does. Any other result is reported once.
};
void injectFault(InjectedFault fault);
void clearInjectedFaults();
// Whether an injected VK_ERROR_DEVICE_LOST has fired (and not been cleared).
bool injectedDeviceLost();

namespace detail {
inline std::atomic<bool> faultArmed{false};  // one relaxed load per checked call when unarmed
VkResult applyInjectedFault(const char* callText, VkResult real);
inline VkResult checkedResult(const char* callText, VkResult real) {
  return faultArmed.load(std::memory_order_relaxed) ? applyInjectedFault(callText, real) : real;
}
inline VkResult checkedSwapchainResult(const char* callText, VkResult real, const char* file, int line) {
  const VkResult result = checkedResult(callText, real);
  if (result == VK_SUCCESS || result == VK_SUBOPTIMAL_KHR || result == VK_ERROR_OUT_OF_DATE_KHR) return result;
  throw VulkanError(result, describeFailedCall(result, callText, file, line));
}
}  // namespace detail

}  // namespace engine::gpu

#define VK_CHECK(call)                                                                        \
  do {                                                                                        \
    const VkResult vk_check_result_ = ::engine::gpu::detail::checkedResult(#call, (call));   \
    if (vk_check_result_ != VK_SUCCESS)                                                       \
      throw ::engine::gpu::VulkanError(                                                       \
          vk_check_result_,                                                                   \
          ::engine::gpu::describeFailedCall(vk_check_result_, #call, __FILE__, __LINE__));    \
  } while (0)

#define VK_TRY(call)                                                                          \
  do {                                                                                        \
    const VkResult vk_try_result_ = ::engine::gpu::detail::checkedResult(#call, (call));     \
    if (vk_try_result_ != VK_SUCCESS)                                                         \
      return ::engine::makeError(                                                             \
          ::engine::gpu::describeFailedCall(vk_try_result_, #call, __FILE__, __LINE__));      \
  } while (0)

// For vkAcquireNextImageKHR and vkQueuePresentKHR, whose caller handles a swapchain that no longer
// matches its surface: evaluates to VK_SUCCESS, VK_SUBOPTIMAL_KHR or VK_ERROR_OUT_OF_DATE_KHR and
// throws as VK_CHECK does for anything else, naming the call (fault injection applies).
#define VK_CHECK_SWAPCHAIN(call) ::engine::gpu::detail::checkedSwapchainResult(#call, (call), __FILE__, __LINE__)
