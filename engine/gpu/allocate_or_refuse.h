#pragma once
// GPU memory refused -- by the allocator's budget (Allocator::setBudget), by the device, or for a
// buffer past the device's maxBufferSize -- reaches the code that asked as a VulkanError with
// VK_ERROR_OUT_OF_DEVICE_MEMORY, thrown by the constructors of Buffer and Image and by what makes
// them (createBufferWithData, appendToBuffers, ...): a constructor has no result to return. Code
// that does without what it could not allocate (drops the object, turns a stage off) makes the
// allocation through allocateOrRefuse, which turns exactly that refusal into an Error (its message:
// what the allocator said, naming the object and the sizes) and lets every other failure throw on.
#include <type_traits>
#include <utility>

#include "engine/core/expected.h"
#include "engine/gpu/vk_check.h"

namespace engine::gpu {

// Runs make(): its result as an Expected (a Status for a make() that returns nothing), or the
// refusal as its Error.
template <class Make>
auto allocateOrRefuse(Make&& make) {
  using Made = std::invoke_result_t<Make&>;
  using Result = std::conditional_t<std::is_void_v<Made>, Status, Expected<Made>>;
  try {
    if constexpr (std::is_void_v<Made>) {
      make();
      return Result{};
    } else {
      return Result(make());
    }
  } catch (const VulkanError& error) {
    if (error.result() != VK_ERROR_OUT_OF_DEVICE_MEMORY) throw;
    return Result(makeError(error.what()));
  }
}

}  // namespace engine::gpu
