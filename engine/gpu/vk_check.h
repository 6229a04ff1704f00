#pragma once
// Checked Vulkan calls. VK_CHECK names the call, the file and the line and throws
// engine::gpu::VulkanError: an unexpected VkResult from the driver is not something a frame can
// recover from, and the sample's main() reports it. Functions that can fail on user input return
// engine::Expected instead (VK_TRY converts a failed call into an Error there).
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

}  // namespace engine::gpu

#define VK_CHECK(call)                                                                        \
  do {                                                                                        \
    const VkResult vk_check_result_ = (call);                                                 \
    if (vk_check_result_ != VK_SUCCESS)                                                       \
      throw ::engine::gpu::VulkanError(                                                       \
          vk_check_result_,                                                                   \
          ::engine::gpu::describeFailedCall(vk_check_result_, #call, __FILE__, __LINE__));    \
  } while (0)

#define VK_TRY(call)                                                                          \
  do {                                                                                        \
    const VkResult vk_try_result_ = (call);                                                   \
    if (vk_try_result_ != VK_SUCCESS)                                                         \
      return ::engine::makeError(                                                             \
          ::engine::gpu::describeFailedCall(vk_try_result_, #call, __FILE__, __LINE__));      \
  } while (0)
