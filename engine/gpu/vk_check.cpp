#include "engine/gpu/vk_check.h"

#include <string_view>

namespace engine::gpu {

const char* resultName(VkResult result) {
  switch (result) {
#define HSDF_RESULT_CASE(r) case r: return #r;
    HSDF_RESULT_CASE(VK_SUCCESS)
    HSDF_RESULT_CASE(VK_NOT_READY)
    HSDF_RESULT_CASE(VK_TIMEOUT)
    HSDF_RESULT_CASE(VK_INCOMPLETE)
    HSDF_RESULT_CASE(VK_SUBOPTIMAL_KHR)
    HSDF_RESULT_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    HSDF_RESULT_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    HSDF_RESULT_CASE(VK_ERROR_INITIALIZATION_FAILED)
    HSDF_RESULT_CASE(VK_ERROR_DEVICE_LOST)
    HSDF_RESULT_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    HSDF_RESULT_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    HSDF_RESULT_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    HSDF_RESULT_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    HSDF_RESULT_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    HSDF_RESULT_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    HSDF_RESULT_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    HSDF_RESULT_CASE(VK_ERROR_FRAGMENTED_POOL)
    HSDF_RESULT_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
    HSDF_RESULT_CASE(VK_ERROR_SURFACE_LOST_KHR)
    HSDF_RESULT_CASE(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR)
    HSDF_RESULT_CASE(VK_ERROR_OUT_OF_DATE_KHR)
#undef HSDF_RESULT_CASE
    default: return "VkResult(unknown)";
  }
}

std::string describeFailedCall(VkResult result, const char* call, const char* file, int line) {
  std::string_view path(file);
  if (auto slash = path.find("engine/"); slash != std::string_view::npos) path.remove_prefix(slash);
  return std::string(call) + " failed with " + resultName(result) + " (" + std::to_string(int(result)) +
         ") at " + std::string(path) + ":" + std::to_string(line);
}

}  // namespace engine::gpu
