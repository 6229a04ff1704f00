#pragma once
// The Viewer as the Viewer tests drive it: headless, validation layers on, on the test device
// (HSDF_TEST_DEVICE, lavapipe unless set), at a small size that keeps the tests fast.
#include <cstdint>
#include <memory>

#include <gtest/gtest.h>

#include "test_device.h"
#include "test_files.h"
#include "viewer.h"

namespace samples {

inline engine::Expected<std::unique_ptr<Viewer>> createTestViewer(std::uint32_t width, std::uint32_t height,
                                                                  const hsdf::BakeBudget& budget = {}) {
  ViewerDesc desc;
  desc.bakeBudget = budget;
  desc.width = width;
  desc.height = height;
  desc.headless = true;
  desc.validation = true;
  const auto device = hsdftest::testDevicePreference();
  if (!device) return device.error();
  desc.device = *device;
  return Viewer::create(desc);
}

// The same, or nullptr after a failed expectation naming why.
inline std::unique_ptr<Viewer> makeTestViewer(std::uint32_t width, std::uint32_t height,
                                              const hsdf::BakeBudget& budget = {}) {
  auto viewer = createTestViewer(width, height, budget);
  EXPECT_TRUE(viewer.ok()) << viewer.error().message;
  return viewer.ok() ? std::move(*viewer) : nullptr;
}

// `viewer` showing the glTF scene `gltf` without a ground plane (its meshes as separate SDF objects
// when `objects`), or nullptr after a failed expectation naming why.
inline std::unique_ptr<Viewer> withGltfScene(std::unique_ptr<Viewer> viewer, const std::filesystem::path& gltf,
                                             const TuningState& tuning, bool objects) {
  if (!viewer) return nullptr;
  SceneDesc scene;
  scene.gltf = gltf;
  scene.groundPlane = false;
  scene.objects = objects;
  const engine::Status loaded = viewer->loadScene(scene, tuning);
  EXPECT_TRUE(loaded.ok()) << loaded.error().message;
  return loaded.ok() ? std::move(viewer) : nullptr;
}

}  // namespace samples
