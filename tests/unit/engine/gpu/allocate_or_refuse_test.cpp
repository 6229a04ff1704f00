// The one way code that does without a refused allocation hears of it (engine/gpu/allocate_or_refuse.h):
// the refusal the allocator and the buffer and image constructors throw becomes an Error, and
// nothing else does (no device: the throws stand in for the constructors').
#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/gpu/allocate_or_refuse.h"

namespace engine::gpu {
namespace {

// Tricky: the value (or nothing, for a make() without one) must come through untouched when
// nothing is refused, moved rather than copied for a move-only result such as a list of buffers.
TEST(AllocateOrRefuse, PassesTheResultThrough) {
  const Expected<std::vector<int>> values = allocateOrRefuse([] { return std::vector<int>{1, 2, 3}; });
  ASSERT_TRUE(values.ok());
  EXPECT_EQ(*values, (std::vector<int>{1, 2, 3}));
  int calls = 0;
  const Status done = allocateOrRefuse([&] { ++calls; });
  EXPECT_TRUE(done.ok());
  EXPECT_EQ(calls, 1);
  const auto moved = allocateOrRefuse([] { return std::make_unique<int>(7); });
  ASSERT_TRUE(moved.ok());
  EXPECT_EQ(**moved, 7);
}

// Tricky: out of device memory is the refusal (budget, device, past maxBufferSize: the message
// says which, and must reach the user as the allocator wrote it); the make() that refused ran.
TEST(AllocateOrRefuse, OutOfDeviceMemoryIsAnError) {
  const std::string what = "Buffer 'kept cells' (1024 bytes): over the GPU memory budget";
  const Expected<int> refused = allocateOrRefuse([&]() -> int { throw VulkanError(VK_ERROR_OUT_OF_DEVICE_MEMORY, what); });
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().message, what);
  const Status refusedVoid = allocateOrRefuse([&] { throw VulkanError(VK_ERROR_OUT_OF_DEVICE_MEMORY, what); });
  ASSERT_FALSE(refusedVoid.ok());
  EXPECT_EQ(refusedVoid.error().message, what);
}

// Tricky: a lost device or host memory running out is not a refusal to do without: skipping the
// object would hide it, so it must still throw, as must anything that is not a VulkanError.
TEST(AllocateOrRefuse, OtherFailuresStillThrow) {
  EXPECT_THROW((void)allocateOrRefuse([] { throw VulkanError(VK_ERROR_DEVICE_LOST, "lost"); }), VulkanError);
  EXPECT_THROW((void)allocateOrRefuse([] { throw VulkanError(VK_ERROR_OUT_OF_HOST_MEMORY, "host"); }), VulkanError);
  EXPECT_THROW((void)allocateOrRefuse([]() -> int { throw std::invalid_argument("size 0"); }), std::invalid_argument);
}

}  // namespace
}  // namespace engine::gpu
