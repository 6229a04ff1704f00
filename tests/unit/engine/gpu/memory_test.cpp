// The allocator's budget (engine/gpu/memory.h): a request past it fails before any Vulkan memory
// is touched, with an error naming the resource, its size and the budget, and leaves nothing
// behind (no half-made buffer or image, unchanged totals).
#include <gtest/gtest.h>

#include <memory>
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

// Tricky: a refused upload must be retried when it may now fit and not before (else a full GPU is
// asked, and the refusal reported, every frame): not while the memory in use is unchanged or
// higher, not for a freed amount that still leaves it over the budget, yes once enough is given
// back or the budget raised or lifted; without a budget (the device ran out) once anything is
// given back, the device's free memory being unknown.
TEST(MemoryRefusal, RetriesOnlyOnceMemoryGivenBackOrTheBudgetRaisedMayFitIt) {
  auto context = test::makeTestContext();
  ASSERT_NE(context, nullptr);
  Allocator& allocator = context->allocator();
  const auto buffer = [&](VkDeviceSize bytes) {
    return std::make_unique<Buffer>(*context, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUsage::GpuOnly, "held");
  };
  auto small = buffer(65536);
  auto large = buffer(262144);
  allocator.setBudget(allocator.stats().usedBytes + 4096);
  const MemoryRefusal refusal(allocator, 131072);  // 128 KiB did not fit in 4 KiB
  EXPECT_FALSE(refusal.mayRetry(allocator)) << "nothing changed";
  auto more = buffer(4096);
  EXPECT_FALSE(refusal.mayRetry(allocator)) << "more in use";
  small.reset();
  EXPECT_FALSE(refusal.mayRetry(allocator)) << "64 KiB given back: 128 KiB still does not fit";
  large.reset();
  EXPECT_TRUE(refusal.mayRetry(allocator)) << "320 KiB given back";

  const MemoryRefusal underBudget(allocator, VkDeviceSize(1) << 20);
  EXPECT_FALSE(underBudget.mayRetry(allocator));
  allocator.setBudget(allocator.stats().usedBytes + (VkDeviceSize(1) << 19));
  EXPECT_FALSE(underBudget.mayRetry(allocator)) << "raised, not enough";
  allocator.setBudget(allocator.stats().usedBytes + (VkDeviceSize(1) << 20));
  EXPECT_TRUE(underBudget.mayRetry(allocator)) << "raised by what it needs";
  allocator.setBudget(allocator.stats().usedBytes + 4096);
  const MemoryRefusal lifted(allocator, VkDeviceSize(1) << 20);
  allocator.setBudget(Allocator::kUnlimited);
  EXPECT_TRUE(lifted.mayRetry(allocator)) << "the budget lifted";

  auto other = buffer(65536);
  const MemoryRefusal deviceFull(allocator, 131072);  // no budget: the device refused it
  EXPECT_FALSE(deviceFull.mayRetry(allocator));
  other.reset();
  EXPECT_TRUE(deviceFull.mayRetry(allocator)) << "memory given back";
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
