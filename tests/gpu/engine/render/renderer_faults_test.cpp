// The Renderer's constructor failing half-way (engine/render/renderer.h): it makes raw Vulkan
// handles (the depth sampler, the scene set's layout and pool, per frame a command pool, a fence
// and a semaphore) between members that clean up after themselves; a constructor that throws runs
// no destructor, so the handles made before the failing call must be given back by the constructor.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "engine/gpu/vk_check.h"
#include "engine/render/renderer.h"
#include "gpu_test_support.h"
#include "test_device.h"

namespace {

using namespace engine;

struct FaultGuard {  // a failing test must not leave the fault armed for the next one
  ~FaultGuard() { gpu::clearInjectedFaults(); }
};

// Tricky: each call is made more than once in one construction (a command pool, a fence and a
// semaphore per frame in flight, a fence for the one-off upload of the targets' layouts), and a
// failure at the last frame leaks the most: every skip count is tried until the construction gets
// past all the calls of that name. A leak shows only as the validation layer's report at
// vkDestroyDevice, counted through the context's destruction.
TEST(RendererFaults, ConstructorFailingAtAnyCallLeavesNothing) {
  const std::vector<const char*> calls = {"vkCreateSampler",       "vkCreateDescriptorSetLayout",
                                          "vkCreateDescriptorPool", "vkAllocateDescriptorSets",
                                          "vkCreateCommandPool",   "vkAllocateCommandBuffers",
                                          "vkCreateFence",         "vkCreateSemaphore"};
  render::RendererDesc desc;
  desc.framesInFlight = 2;
  for (const char* call : calls) {
    std::uint32_t failures = 0;
    for (std::uint32_t skip = 0; skip < 8; ++skip) {
      SCOPED_TRACE(std::string(call) + " skip " + std::to_string(skip));
      FaultGuard guard;
      auto context = gputest::createTestContext();
      ASSERT_NE(context, nullptr);
      gpu::injectFault({call, VK_ERROR_OUT_OF_HOST_MEMORY, skip});
      bool made = false;
      try {
        render::Renderer renderer(*context, desc, VkExtent2D{16, 16});
        made = true;
      } catch (const gpu::VulkanError& e) {
        ++failures;
        EXPECT_EQ(e.result(), VK_ERROR_OUT_OF_HOST_MEMORY);
        EXPECT_NE(std::string(e.what()).find(call), std::string::npos) << e.what();
      }
      gpu::clearInjectedFaults();
      EXPECT_EQ(hsdftest::messagesThroughDestruction(context), 0u) << "see the log for the objects left";
      if (made) break;  // every call of this name got through: the fault never fired
    }
    EXPECT_GT(failures, 0u) << call << " was never reached";
  }
}

}  // namespace
