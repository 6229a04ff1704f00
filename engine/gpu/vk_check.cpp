#include "engine/gpu/vk_check.h"

#include <mutex>
#include <optional>
#include <string_view>
#include <utility>

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

namespace {

struct FaultState {
  std::mutex mutex;
  std::optional<InjectedFault> pending;
  bool deviceLost = false;
};

FaultState& faultState() {
  static FaultState state;
  return state;
}

// "vkQueueSubmit2(queue_, 1, &submit, fence)" names vkQueueSubmit2, not vkQueueSubmit.
bool callsFunction(std::string_view callText, std::string_view function) {
  return callText.size() > function.size() && callText.substr(0, function.size()) == function &&
         callText[function.size()] == '(';
}

}  // namespace

void injectFault(InjectedFault fault) {
  FaultState& state = faultState();
  std::lock_guard lock(state.mutex);
  state.pending = std::move(fault);
  state.deviceLost = false;
  detail::faultArmed.store(true, std::memory_order_relaxed);
}

void clearInjectedFaults() {
  FaultState& state = faultState();
  std::lock_guard lock(state.mutex);
  state.pending.reset();
  state.deviceLost = false;
  detail::faultArmed.store(false, std::memory_order_relaxed);
}

bool injectedDeviceLost() {
  FaultState& state = faultState();
  std::lock_guard lock(state.mutex);
  return state.deviceLost;
}

VkResult detail::applyInjectedFault(const char* callText, VkResult real) {
  FaultState& state = faultState();
  std::lock_guard lock(state.mutex);
  if (state.deviceLost) return VK_ERROR_DEVICE_LOST;
  if (!state.pending || !callsFunction(callText, state.pending->call)) return real;
  if (state.pending->skip > 0) {
    --state.pending->skip;
    return real;
  }
  const VkResult injected = state.pending->result;
  state.pending.reset();
  state.deviceLost = injected == VK_ERROR_DEVICE_LOST;
  if (!state.deviceLost) faultArmed.store(false, std::memory_order_relaxed);
  return injected;
}

}  // namespace engine::gpu
