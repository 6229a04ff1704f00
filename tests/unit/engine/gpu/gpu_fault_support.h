#pragma once
// A lavapipe context with the validation layers on, for the engine_gpu fault tests.
#include <gtest/gtest.h>

#include <memory>

#include "engine/gpu/context.h"

namespace engine::gpu::test {

inline std::unique_ptr<Context> makeSoftwareContext() {
  ContextDesc desc;
  desc.device = DevicePreference::Software;
  desc.validation = true;
  auto context = Context::create(desc);
  EXPECT_TRUE(context.ok()) << context.error().message;
  return context.ok() ? std::move(*context) : nullptr;
}

}  // namespace engine::gpu::test
