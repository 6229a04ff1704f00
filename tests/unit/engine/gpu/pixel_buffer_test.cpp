// engine::gpu::PixelBuffer (engine/gpu/pixel_buffer.h): one uint per pixel plus trailing bytes,
// made for an extent, kept while the extent stays, made again when it changes, and an old buffer
// retired (engine/gpu/deferred_release.h), freed only once no submitted work uses it (validation
// on: freeing a buffer in use is a message).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "engine/gpu/buffer.h"
#include "engine/gpu/pixel_buffer.h"
#include "engine/gpu/vk_check.h"
#include "gpu_fault_support.h"

namespace engine::gpu {
namespace {

constexpr VkDeviceSize kTrailing = 24;

// Tricky: the same extent must keep the very buffer (an address a shader was handed stays valid),
// a changed extent of the same pixel count (8x4 -> 4x8) must still make a new one (rows differ),
// and the trailing bytes must lie after the pixels, writable and readable at pixelBytes().
TEST(PixelBuffer, SizedForTheExtentKeptWhileItStaysRemadeWhenItChanges) {
  auto context = test::makeTestContext();
  ASSERT_NE(context, nullptr);
  PixelBuffer pixels("test pixels", VK_BUFFER_USAGE_TRANSFER_SRC_BIT, kTrailing);
  DeferredRelease retired;
  EXPECT_FALSE(pixels);
  EXPECT_TRUE(pixels.ensure(*context, {8, 4}, retired, 0));
  ASSERT_TRUE(pixels);
  EXPECT_EQ(pixels.pixelBytes(), 8u * 4u * 4u);
  EXPECT_EQ(pixels.buffer().size(), 8u * 4u * 4u + kTrailing);
  EXPECT_NE(pixels.address(), 0u);
  const VkBuffer first = pixels.handle();
  const VkDeviceAddress firstAddress = pixels.address();

  EXPECT_FALSE(pixels.ensure(*context, {8, 4}, retired, 0));
  EXPECT_EQ(pixels.handle(), first);
  EXPECT_EQ(pixels.address(), firstAddress);

  EXPECT_TRUE(pixels.ensure(*context, {4, 8}, retired, 0));
  EXPECT_EQ(pixels.extent().width, 4u);
  EXPECT_EQ(pixels.extent().height, 8u);
  EXPECT_TRUE(pixels.ensure(*context, {5, 3}, retired, 0));
  EXPECT_EQ(pixels.buffer().size(), 5u * 3u * 4u + kTrailing);

  context->submitAndWait([&](VkCommandBuffer cmd) {
    vkCmdFillBuffer(cmd, pixels.handle(), 0, pixels.pixelBytes(), 0x11111111u);
    vkCmdFillBuffer(cmd, pixels.handle(), pixels.pixelBytes(), kTrailing, 0xC0FFEE00u);
  });
  const auto bytes = readbackBuffer(*context, pixels.buffer());
  ASSERT_EQ(bytes.size(), 5u * 3u * 4u + kTrailing);
  std::uint32_t lastPixel = 0, trailing = 0;
  std::memcpy(&lastPixel, bytes.data() + pixels.pixelBytes() - 4, 4);
  std::memcpy(&trailing, bytes.data() + bytes.size() - 4, 4);
  EXPECT_EQ(lastPixel, 0x11111111u);
  EXPECT_EQ(trailing, 0xC0FFEE00u);
  EXPECT_EQ(context->validationMessageCount(), 0u);
}

// Tricky: the old buffer is still used by submitted, unfinished work (64 ordered fills) when the
// extent changes; it may be freed only once that work is done (a buffer destroyed in use is a
// validation error), and without waiting for the device: it waits in the release list.
TEST(PixelBuffer, OldBufferOutlivesTheWorkInFlight) {
  auto context = test::makeTestContext();
  ASSERT_NE(context, nullptr);
  PixelBuffer pixels("in-flight pixels");
  DeferredRelease retired;
  constexpr std::uint64_t kFrame = 5;  // the frame that submits work on the buffer
  constexpr std::uint32_t kInFlight = 2;
  ASSERT_TRUE(pixels.ensure(*context, {64, 64}, retired, kFrame));

  VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  poolInfo.queueFamilyIndex = context->queueFamily();
  VkCommandPool pool = VK_NULL_HANDLE;
  VK_CHECK(vkCreateCommandPool(context->device(), &poolInfo, nullptr, &pool));
  VkCommandBufferAllocateInfo allocInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  allocInfo.commandPool = pool;
  allocInfo.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocInfo.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VK_CHECK(vkAllocateCommandBuffers(context->device(), &allocInfo, &cmd));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
  // Ordered fills (a barrier between each two: synchronization validation checks the test too).
  VkMemoryBarrier between{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  between.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  between.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  for (int i = 0; i < 64; ++i) {
    if (i > 0)
      vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &between, 0, nullptr,
                           0, nullptr);
    vkCmdFillBuffer(cmd, pixels.handle(), 0, VK_WHOLE_SIZE, std::uint32_t(i));
  }
  VK_CHECK(vkEndCommandBuffer(cmd));
  VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence = VK_NULL_HANDLE;
  VK_CHECK(vkCreateFence(context->device(), &fenceInfo, nullptr, &fence));
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  VK_CHECK(vkQueueSubmit(context->queue(), 1, &submit, fence));

  EXPECT_TRUE(pixels.ensure(*context, {32, 32}, retired, kFrame));  // the 64x64 buffer the submit still uses
  EXPECT_EQ(retired.pending(), 1u) << "the old buffer was not retired";
  retired.collect(kFrame + kInFlight - 1, kInFlight);  // frame 5 may still run while frame 6 is prepared
  EXPECT_EQ(retired.pending(), 1u);
  VK_CHECK(vkWaitForFences(context->device(), 1, &fence, VK_TRUE, UINT64_MAX));  // as frame 7's slot does
  retired.collect(kFrame + kInFlight, kInFlight);
  EXPECT_EQ(retired.pending(), 0u);
  vkDestroyFence(context->device(), fence, nullptr);
  vkDestroyCommandPool(context->device(), pool, nullptr);
  EXPECT_EQ(context->validationMessageCount(), 0u) << ::testing::PrintToString(context->validationMessages());
}

// Tricky: an allocation past the budget must leave the helper empty (no half-made buffer, no
// stale extent a later ensure() would trust), and an empty extent is refused by name.
TEST(PixelBuffer, FailedAllocationLeavesItEmptyAndBadExtentIsRefused) {
  auto context = test::makeTestContext();
  ASSERT_NE(context, nullptr);
  PixelBuffer pixels("budget pixels");
  DeferredRelease retired;
  ASSERT_TRUE(pixels.ensure(*context, {4, 4}, retired, 0));
  context->allocator().setBudget(context->allocator().stats().usedBytes);
  EXPECT_THROW(pixels.ensure(*context, {1024, 1024}, retired, 0), VulkanError);
  EXPECT_FALSE(pixels);
  EXPECT_EQ(pixels.extent().width, 0u);
  context->allocator().setBudget(Allocator::kUnlimited);
  EXPECT_TRUE(pixels.ensure(*context, {4, 4}, retired, 0));
  try {
    pixels.ensure(*context, {0, 7}, retired, 0);
    FAIL() << "a 0x7 extent was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'budget pixels': extent 0x7"), std::string::npos) << e.what();
  }
  EXPECT_EQ(context->validationMessageCount(), 0u);
}

}  // namespace
}  // namespace engine::gpu
