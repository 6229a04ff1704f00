// Fault injection at the checked-call boundary (engine/gpu/vk_check.h): what a lost device or a
// failing driver call looks like to the code above VK_CHECK, on a driver that never fails.
#include <gtest/gtest.h>

#include <string>

#include "engine/gpu/vk_check.h"
#include "gpu_fault_support.h"

namespace engine::gpu {
namespace {

struct FaultGuard {  // a failing test must not leave the fault armed for the next one
  ~FaultGuard() { clearInjectedFaults(); }
};

// Records nothing: a one-off submission is the smallest thing that reaches vkQueueSubmit2.
void submitEmpty(Context& context) {
  context.submitAndWait([](VkCommandBuffer) {});
}

// Tricky: the fault must hit vkQueueSubmit2 (not vkQueueSubmit, a prefix of it), the error must
// name the result and the call, a lost device must stay lost for every later checked call (as a
// real one does: vkDeviceWaitIdle reports it too), and the failed one-off submission must release
// its lock, fence and command buffer (the submission after clearing would deadlock otherwise).
TEST(FaultInjection, DeviceLostAtSubmitIsNamedAndStaysLost) {
  FaultGuard guard;
  auto context = test::makeTestContext();
  ASSERT_NE(context, nullptr);
  submitEmpty(*context);  // the path works without a fault
  injectFault({"vkQueueSubmit2", VK_ERROR_DEVICE_LOST, 0});
  try {
    submitEmpty(*context);
    FAIL() << "the injected VK_ERROR_DEVICE_LOST did not surface";
  } catch (const VulkanError& e) {
    EXPECT_EQ(e.result(), VK_ERROR_DEVICE_LOST);
    const std::string message = e.what();
    EXPECT_NE(message.find("vkQueueSubmit2(queue_, 1, &submit, fence) failed with VK_ERROR_DEVICE_LOST"),
              std::string::npos)
        << message;
  }
  EXPECT_TRUE(injectedDeviceLost());
  try {
    context->waitIdle();
    FAIL() << "a lost device must stay lost";
  } catch (const VulkanError& e) {
    EXPECT_EQ(e.result(), VK_ERROR_DEVICE_LOST);
    EXPECT_NE(std::string(e.what()).find("vkDeviceWaitIdle"), std::string::npos) << e.what();
  }
  clearInjectedFaults();
  EXPECT_FALSE(injectedDeviceLost());
  submitEmpty(*context);  // cleared: the (never really lost) device works again
  EXPECT_EQ(context->validationMessageCount(), 0u);
}

// Tricky: `skip` lets the first matching calls through and any result other than DEVICE_LOST
// fires once: the call after the fault succeeds again (a transient failure, e.g. out of host
// memory for one fence).
TEST(FaultInjection, OtherResultsFireOnceAfterSkippedCalls) {
  FaultGuard guard;
  auto context = test::makeTestContext();
  ASSERT_NE(context, nullptr);
  injectFault({"vkCreateFence", VK_ERROR_OUT_OF_HOST_MEMORY, 1});
  submitEmpty(*context);  // skipped
  try {
    submitEmpty(*context);
    FAIL() << "the second vkCreateFence should have failed";
  } catch (const VulkanError& e) {
    EXPECT_EQ(e.result(), VK_ERROR_OUT_OF_HOST_MEMORY);
    EXPECT_NE(std::string(e.what()).find("vkCreateFence"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(injectedDeviceLost());
  submitEmpty(*context);  // fired once: the next one works
  EXPECT_EQ(context->validationMessageCount(), 0u);
}

}  // namespace
}  // namespace engine::gpu
