#pragma once
// One frame step shared by every program that shows a scene: the scene runner's windowed and
// headless loops, the perf capture and the soak test. A Viewer owns the device, the renderer
// (mesh, Hermite cell and sphere-tracing features), the scene registry, the orbit camera and,
// when windowed or asked for, the window, swapchain and UI. Typical use:
//
//   auto viewer = Viewer::create(desc);                 // device, renderer, window/UI
//   (*viewer)->loadScene(scene, tuning);                // glTF / analytic shape / .hsdf
//   (*viewer)->setOrbitView(3);                         // or setCamera(eye, target)
//   for (int i = 0; i < n; ++i) (*viewer)->step();      // tuning -> transforms -> UI -> render
//   (*viewer)->setTuning(t);                            // new K re-bakes on a worker thread
//   (*viewer)->waitForBake();  (*viewer)->step();  (*viewer)->renderer().lastTimings();
//   (*viewer)->close();                                 // error if Vulkan validation complained
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/expected.h"
#include "engine/ecs/registry.h"
#include "engine/gpu/context.h"
#include "engine/platform/camera_controller.h"
#include "engine/render/renderer.h"
#include "hermite_sdf/bake_job.h"
#include "tuning.h"

namespace engine::gpu {
class Swapchain;
}
namespace engine::platform {
class Window;
}
namespace engine::render {
class MeshPool;
}
namespace engine::ui {
class UiLayer;
}

namespace samples {

// Scenes (bounding-box diagonal) and camera distances the viewer draws: the camera and the shaders
// work in 32-bit floats. Outside about 1e-19..1e19 squared distances underflow or overflow floats
// and frames come out empty; measured on lavapipe, cubes 1e-20..1e18 across draw correctly with
// every method and 1e20 draws nothing, so the range keeps a margin of 1e3 or more.
inline constexpr double kMinSceneSize = 1e-15;
inline constexpr double kMaxSceneSize = 1e15;

struct ViewerDesc {
  std::string title = "hermite_sdf";
  std::uint32_t width = 1280;  // headless: the image; windowed: the initial window
  std::uint32_t height = 720;
  bool headless = false;
  bool validation = false;  // also on with HSDF_VALIDATION=1 and in debug builds
  engine::gpu::DevicePreference device = engine::gpu::DevicePreference::Auto;
  bool headlessUi = false;  // draw the UI panels into headless frames (windowed: always)
};

// What to show. A glTF scene's meshes are drawn as triangles (Method::Mesh) or baked into one SDF
// through the module bake job (any other method), which replaces them or, with sideBySide, stands
// beside them. `shape` bakes an analytic shape (hsdf::analyticShapeNames()) instead, `sdfFile`
// draws a baked .hsdf file.
struct SceneDesc {
  std::filesystem::path gltf;
  std::string shape;
  std::filesystem::path sdfFile;
  bool sideBySide = false;
  bool groundPlane = true;
};

class Viewer {
 public:
  static engine::Expected<std::unique_ptr<Viewer>> create(const ViewerDesc& desc);
  ~Viewer();
  Viewer(const Viewer&) = delete;
  Viewer& operator=(const Viewer&) = delete;

  // Loads the scene with `tuning` (method, K, padding) and frames it with orbit view 0. Errors
  // name the file (unreadable, no meshes to bake, no surface, too large or small to draw).
  engine::Status loadScene(const SceneDesc& scene, const TuningState& tuning);

  // Camera: one of the 8 fixed orbit views of the scene bounds, or an explicit eye and target
  // (the orbit controller keeps working from there).
  void setOrbitView(int index);
  void setCamera(const glm::dvec3& eye, const glm::dvec3& target);
  engine::render::CameraView cameraView() const;

  const TuningState& tuning() const { return tuning_; }
  // Applied at the next step(). A new resolution or padding re-bakes the baked SDF on a worker
  // thread (hsdf::BakeJob); the old asset keeps drawing until the new one is ready.
  void setTuning(const TuningState& tuning);
  // The running re-bake (progress(), cancel()), or null.
  hsdf::BakeJob* bakeJob() { return bakeJob_.get(); }
  // Blocks until a running re-bake is done and in the scene; its error, if it failed.
  engine::Status waitForBake();

  // Windowed: the user closed the window. Headless: never.
  bool shouldClose() const;
  // One frame: (windowed: input, camera, resize; a minimised window waits and draws nothing) a
  // finished re-bake, tuning -> SDF components, world transforms, UI frame, render (recreating an
  // out-of-date swapchain).
  engine::Status step();
  std::uint64_t framesRendered() const { return frames_; }

  // Waits for the GPU and writes the last frame as a PNG.
  engine::Status writeScreenshot(const std::filesystem::path& path);

  engine::gpu::Context& context() { return *context_; }
  engine::render::Renderer& renderer() { return *renderer_; }
  engine::ecs::Registry& registry() { return registry_; }
  glm::vec3 boundsMin() const { return boundsMin_; }
  glm::vec3 boundsMax() const { return boundsMax_; }

  // Tears everything down in dependency order; an error when the validation layers reported
  // anything during the Viewer's life. The destructor does the same, silently.
  engine::Status close();

 private:
  Viewer() = default;
  engine::Status initialize(const ViewerDesc& desc);
  void addViewPanel();
  engine::Status handleWindow(bool& drawable);
  engine::Status recreateSwapchain();
  void applyTuningToScene();
  void startRebake();
  engine::Status finishBake();
  // Scene loading (viewer_scene.cpp).
  engine::Status addBakedSdf(hsdf::BakeSource source, const SceneDesc& scene, bool replaceMeshes,
                             const std::vector<engine::ecs::Entity>& meshes, const glm::vec4* color);
  engine::Status addSdfFile(const std::filesystem::path& file, bool frameIt);
  engine::Status loadGltf(const SceneDesc& scene);
  void addGroundPlane();
  engine::ecs::Entity addSdfEntity(std::shared_ptr<const hsdf::SdfAsset> asset, const glm::vec3& offset,
                                   const glm::vec4* color);

  std::unique_ptr<engine::gpu::Context> context_;
  std::unique_ptr<engine::platform::Window> window_;
  std::unique_ptr<engine::render::MeshPool> pool_;
  std::unique_ptr<engine::render::Renderer> renderer_;
  std::unique_ptr<engine::ui::UiLayer> ui_;
  std::unique_ptr<engine::gpu::Swapchain> swapchain_;
  engine::ecs::Registry registry_;

  glm::vec3 boundsMin_{-1.0f};
  glm::vec3 boundsMax_{1.0f};
  engine::platform::OrbitController orbit_;
  float fovY_ = 0.8f;
  float znear_ = 0.01f;
  double lastFrameTime_ = 0.0;  // seconds on the steady clock; windowed frames measure dt
  std::uint64_t frames_ = 0;
  TuningState tuning_;

  // The baked SDF entity, what it was baked from and at which K and padding it is drawn.
  std::optional<hsdf::BakeSource> bakeSource_;
  std::optional<engine::ecs::Entity> bakedEntity_;
  int bakedResolution_ = 0;
  int bakedPadding_ = 0;
  std::unique_ptr<hsdf::BakeJob> bakeJob_;
  bool closed_ = false;
};

}  // namespace samples
