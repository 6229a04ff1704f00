// The allocator's budget (engine/gpu/memory.h): a request past it fails before any Vulkan memory
// is touched, with an error naming the resource, its size and the budget, and leaves nothing
// behind (no half-made buffer or image, unchanged totals).
#include <gtest/gtest.h>

#include <string>

#include "engine/gpu/buffer.h"
#include "engine/gpu/image.h"
#include "engine/gpu/memory.h"
#include "engine/gpu/vk_check.h"
#include "gpu_fault_support.h"

namespace engine::gpu {
namespace {

// Tricky: the budget must be checked against what is already in use (not just the request), the
// failed Buffer constructor must destroy its VkBuffer (a constructor that throws runs no
// destructor: a leak would show as a validation message at device destruction and as a changed
// allocation count), and raising the budget must let the same request through.
TEST(AllocatorBudget, BufferPastTheBudgetFailsNamedAndLeavesNothing) {
  auto context = test::makeTestContext();
  ASSERT_NE(context, nullptr);
  Allocator& allocator = context->allocator();
  EXPECT_EQ(allocator.budget(), Allocator::kUnlimited);
  Buffer first(*context, 4096, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUsage::GpuOnly, "first buffer");
  const AllocatorStats before = allocator.stats();
  ASSERT_GE(before.usedBytes, 4096u);

  allocator.setBudget(before.usedBytes + 32768);  // room for 32 KiB more, not for 64 KiB
  try {
    Buffer tooBig(*context, 65536, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUsage::GpuOnly, "field samples");
    FAIL() << "a 64 KiB buffer fit a budget with 32 KiB left";
  } catch (const VulkanError& e) {
    EXPECT_EQ(e.result(), VK_ERROR_OUT_OF_DEVICE_MEMORY);
    const std::string message = e.what();
    EXPECT_NE(message.find("GPU memory budget: 'field samples' needs 65536 B"), std::string::npos) << message;
    EXPECT_NE(message.find("the budget is " + std::to_string(before.usedBytes + 32768) + " B"), std::string::npos)
        << message;
  }
  const AllocatorStats after = allocator.stats();
  EXPECT_EQ(after.usedBytes, before.usedBytes);
  EXPECT_EQ(after.allocationCount, before.allocationCount);

  Buffer fits(*context, 16384, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUsage::GpuOnly, "fits");
  allocator.setBudget(Allocator::kUnlimited);
  Buffer nowFits(*context, 65536, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUsage::GpuOnly, "field samples");
  EXPECT_EQ(allocator.stats().allocationCount, before.allocationCount + 2);
  EXPECT_EQ(context->validationMessageCount(), 0u);
}

// Tricky: images take the same path through their own constructor (an image and its view); a
// budget of 0 refuses even the smallest request, and the arithmetic must not overflow when the
// budget is below what is in use.
TEST(AllocatorBudget, ImagePastTheBudgetFailsNamedAndLeavesNothing) {
  auto context = test::makeTestContext();
  ASSERT_NE(context, nullptr);
  Allocator& allocator = context->allocator();
  Buffer inUse(*context, 4096, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUsage::GpuOnly, "in use");
  const AllocatorStats before = allocator.stats();
  ImageDesc desc;
  desc.extent = {16, 16, 1};
  desc.format = VK_FORMAT_R8G8B8A8_UNORM;
  desc.usage = VK_IMAGE_USAGE_SAMPLED_BIT;
  desc.name = "color target";
  for (VkDeviceSize budget : {VkDeviceSize(0), before.usedBytes / 2}) {
    allocator.setBudget(budget);
    try {
      Image image(*context, desc);
      FAIL() << "an image fit a budget of " << budget << " B";
    } catch (const VulkanError& e) {
      EXPECT_EQ(e.result(), VK_ERROR_OUT_OF_DEVICE_MEMORY);
      EXPECT_NE(std::string(e.what()).find("'color target' needs"), std::string::npos) << e.what();
    }
    EXPECT_EQ(allocator.stats().allocationCount, before.allocationCount);
  }
  allocator.setBudget(Allocator::kUnlimited);
  Image image(*context, desc);
  EXPECT_EQ(allocator.stats().allocationCount, before.allocationCount + 1);
  EXPECT_EQ(context->validationMessageCount(), 0u);
}

// Tricky: a buffer sized by the scene (one entry per cell of every instance) can pass the
// device's maxBufferSize long before its memory: creating it is invalid usage (a validation
// message, on lavapipe VK_ERROR_OUT_OF_DEVICE_MEMORY); the constructor must refuse it with an error
// naming it, its size and the limit, and create nothing. The limit itself is read from the device.
TEST(BufferLimits, PastMaxBufferSizeFailsNamedAndCreatesNothing) {
  auto context = test::makeTestContext();
  ASSERT_NE(context, nullptr);
  const VkDeviceSize limit = context->capabilities().maxBufferSize;
  EXPECT_GE(limit, VkDeviceSize(1) << 30);  // Vulkan 1.3's minimum
  const AllocatorStats before = context->allocator().stats();
  try {
    Buffer tooBig(*context, limit + 1, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUsage::GpuOnly, "kept cells");
    FAIL() << "a buffer of maxBufferSize + 1 bytes was created";
  } catch (const VulkanError& e) {
    EXPECT_EQ(e.result(), VK_ERROR_OUT_OF_DEVICE_MEMORY);
    const std::string message = e.what();
    EXPECT_NE(message.find("Buffer 'kept cells' (" + std::to_string(limit + 1) + " bytes)"), std::string::npos)
        << message;
    EXPECT_NE(message.find("maxBufferSize (" + std::to_string(limit) + " bytes)"), std::string::npos) << message;
  }
  EXPECT_EQ(context->allocator().stats().allocationCount, before.allocationCount);
  EXPECT_EQ(context->validationMessageCount(), 0u);
}

}  // namespace
}  // namespace engine::gpu
