#pragma once
// A context on the test device (HSDF_TEST_DEVICE, lavapipe unless set) with the validation layers
// on, for the engine_gpu fault tests.
#include <gtest/gtest.h>

#include <memory>

#include "engine/gpu/context.h"
#include "test_device.h"

namespace engine::gpu::test {

inline std::unique_ptr<Context> makeTestContext() {
  const auto device = hsdftest::testDevicePreference();
  EXPECT_TRUE(device.ok()) << device.error().message;
  if (!device) return nullptr;
  ContextDesc desc;
  desc.device = *device;
  desc.validation = true;
  auto context = Context::create(desc);
  EXPECT_TRUE(context.ok()) << hsdftest::describeTestDevice() << ": " << context.error().message;
  return context.ok() ? std::move(*context) : nullptr;
}

using hsdftest::messagesThroughDestruction;

}  // namespace engine::gpu::test
