// Fault injection at the checked-call boundary (engine/gpu/vk_check.h): what a lost device or a
// failing driver call looks like to the code above VK_CHECK, on a driver that never fails.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <future>
#include <stdexcept>
#include <string>
#include <thread>

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

// Runs `work` on its own thread; if it has not finished within `seconds` (a lock never given
// back), the test fails and the process ends at once: a hung test would otherwise only be stopped
// by ctest's timeout, and the thread cannot be joined.
template <class F>
void finishesWithin(int seconds, const char* what, F&& work) {
  std::promise<void> done;
  std::future<void> finished = done.get_future();
  std::thread thread([&work, &done] {
    try {
      work();
      done.set_value();
    } catch (...) {
      done.set_exception(std::current_exception());
    }
  });
  if (finished.wait_for(std::chrono::seconds(seconds)) != std::future_status::ready) {
    std::fprintf(stderr, "FAILED: %s did not finish within %d s (deadlocked)\n", what, seconds);
    std::fflush(stderr);
    std::_Exit(1);
  }
  thread.join();
  finished.get();
}

// Tricky: each failure happens before the submission (the command buffer's allocation or begin)
// or inside the caller's recording, where the one-off path used to hold its mutex with no owner
// to release it: the next upload from any thread then waited for ever. The error must name the
// call (or be the caller's own), and the next submission must go through.
TEST(FaultInjection, FailedOneOffBeforeSubmitReleasesItsLock) {
  FaultGuard guard;
  auto context = test::makeTestContext();
  ASSERT_NE(context, nullptr);
  for (const char* call : {"vkAllocateCommandBuffers", "vkBeginCommandBuffer"}) {
    SCOPED_TRACE(call);
    injectFault({call, VK_ERROR_OUT_OF_HOST_MEMORY, 0});
    try {
      submitEmpty(*context);
      ADD_FAILURE() << "the injected fault did not surface";
    } catch (const VulkanError& e) {
      EXPECT_EQ(e.result(), VK_ERROR_OUT_OF_HOST_MEMORY);
      EXPECT_NE(std::string(e.what()).find(call), std::string::npos) << e.what();
    }
    finishesWithin(30, "the one-off submission after the fault", [&] { submitEmpty(*context); });
  }
  try {
    context->submitAndWait([](VkCommandBuffer) { throw std::runtime_error("recording failed"); });
    ADD_FAILURE() << "the recording's exception did not surface";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "recording failed");
  }
  finishesWithin(30, "the one-off submission after a throwing recording", [&] { submitEmpty(*context); });
  EXPECT_EQ(test::messagesThroughDestruction(context), 0u);
}

// Tricky: the two-call enumeration of layers and extensions ran unchecked, so a failed call read
// as "nothing installed" (the validation layer or debug utils silently missing, or a device
// refused as having no VK_KHR_swapchain). Each one, at either of its two calls, must now fail the
// context's creation naming the call.
TEST(FaultInjection, FailedEnumerationFailsTheContextByName) {
  const auto device = hsdftest::testDevicePreference();
  ASSERT_TRUE(device.ok()) << device.error().message;
  for (const char* call : {"vkEnumerateInstanceLayerProperties", "vkEnumerateInstanceExtensionProperties",
                           "vkEnumerateDeviceExtensionProperties"}) {
    for (std::uint32_t skip : {0u, 1u}) {
      SCOPED_TRACE(std::string(call) + " skip " + std::to_string(skip));
      FaultGuard guard;
      ContextDesc desc;
      desc.device = *device;
      desc.validation = true;
      desc.swapchain = true;  // the device extensions are asked for VK_KHR_swapchain
      injectFault({call, VK_ERROR_OUT_OF_HOST_MEMORY, skip});
      const auto context = Context::create(desc);
      ASSERT_FALSE(context.ok()) << "created with a failed " << call;
      EXPECT_NE(context.error().message.find(std::string(call) + "("), std::string::npos) << context.error().message;
      EXPECT_NE(context.error().message.find("VK_ERROR_OUT_OF_HOST_MEMORY"), std::string::npos)
          << context.error().message;
    }
  }
}

VkResult fakeSwapchainCall(VkResult result) { return result; }

// Tricky: the swapchain's calls pass two results that are not VK_SUCCESS (suboptimal, out of
// date) back to their caller and must throw for the rest, naming the call, not the variable that
// held its result; and the acquire must go through fault injection as the present does.
TEST(FaultInjection, SwapchainResultsPassOrThrowNamingTheCall) {
  FaultGuard guard;
  EXPECT_EQ(VK_CHECK_SWAPCHAIN(fakeSwapchainCall(VK_SUCCESS)), VK_SUCCESS);
  EXPECT_EQ(VK_CHECK_SWAPCHAIN(fakeSwapchainCall(VK_SUBOPTIMAL_KHR)), VK_SUBOPTIMAL_KHR);
  EXPECT_EQ(VK_CHECK_SWAPCHAIN(fakeSwapchainCall(VK_ERROR_OUT_OF_DATE_KHR)), VK_ERROR_OUT_OF_DATE_KHR);
  injectFault({"fakeSwapchainCall", VK_ERROR_OUT_OF_DATE_KHR, 0});
  EXPECT_EQ(VK_CHECK_SWAPCHAIN(fakeSwapchainCall(VK_SUCCESS)), VK_ERROR_OUT_OF_DATE_KHR);
  injectFault({"fakeSwapchainCall", VK_ERROR_SURFACE_LOST_KHR, 0});
  try {
    (void)VK_CHECK_SWAPCHAIN(fakeSwapchainCall(VK_SUCCESS));
    FAIL() << "VK_ERROR_SURFACE_LOST_KHR passed";
  } catch (const VulkanError& e) {
    EXPECT_EQ(e.result(), VK_ERROR_SURFACE_LOST_KHR);
    EXPECT_NE(std::string(e.what()).find("fakeSwapchainCall(VK_SUCCESS) failed with VK_ERROR_SURFACE_LOST_KHR"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace engine::gpu
