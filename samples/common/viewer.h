#pragma once
// One frame step shared by every program that shows a scene: the scene runner's windowed and
// headless loops, the perf capture and the soak test. A Viewer owns the device, the renderer
// (mesh, Hermite cell and sphere-tracing features), the scene registry, the orbit camera and,
// when windowed or asked for, the window, swapchain and UI. Its other jobs are pieces of their own
// that it composes: ViewerWindow (viewer_window.h: window, swapchain), SdfBakes (sdf_bakes.h: the SDF
// entity's re-bakes, levels of detail, refused bakes), SdfObjects (sdf_objects.h), ComparedSide
// (compared_side.h: split screen, difference view), Screenshots (screenshots.h); scene loading is in
// viewer_scene.cpp. Typical use:
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
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/expected.h"
#include "engine/ecs/registry.h"
#include "engine/gpu/context.h"
#include "engine/gpu/memory.h"
#include "engine/platform/camera_controller.h"
#include "engine/render/components.h"
#include "engine/render/renderer.h"
#include "engine/render/scene_instantiate.h"
#include "animation_player.h"
#include "compared_side.h"
#include "difference_view.h"
#include "hermite_sdf/core/bake_job.h"
#include "screenshots.h"
#include "sdf_bakes.h"
#include "sdf_objects.h"
#include "sdf_stats.h"
#include "tuning.h"
#include "viewer_window.h"

namespace engine::render {
class MeshPool;
}
namespace engine::ui {
class UiLayer;
}
namespace engine::scene {
struct SceneData;
}

namespace samples {

// Scenes (bounding-box diagonal) and camera distances the viewer draws: the camera and the shaders
// work in 32-bit floats. Outside about 1e-19..1e19 squared distances underflow or overflow floats
// and frames come out empty; measured on lavapipe, cubes 1e-20..1e18 across draw correctly with
// every method and 1e20 draws nothing, so the range keeps a margin of 1e3 or more.
inline constexpr double kMinSceneSize = 1e-15;
inline constexpr double kMaxSceneSize = 1e15;

// The name the sample programs go by: their default window title, the Vulkan application and engine
// names and the UI window's title (the engine itself names no module).
inline constexpr const char* kProgramName = "hermite_sdf";

struct ViewerDesc {
  std::string title = kProgramName;
  std::uint32_t width = 1280;  // headless: the image; windowed: the initial window
  std::uint32_t height = 720;
  bool headless = false;
  bool validation = false;  // also on with HSDF_VALIDATION=1 and in debug builds
  engine::gpu::DevicePreference device = engine::gpu::DevicePreference::Auto;
  bool headlessUi = false;  // draw the UI panels into headless frames (windowed: always)
  std::filesystem::path uiIniFile;  // ImGui's window layout is loaded from / saved to it (empty: not kept)
  hsdf::BakeBudget bakeBudget;      // bakes past it are refused (the reason is in bakeError())
  // Device memory the renderer may hold (engine::gpu::Allocator::setBudget); a frame that needs
  // more fails with an error naming the resource and the budget (step()).
  std::uint64_t gpuMemoryBudget = engine::gpu::Allocator::kUnlimited;
  // The shader compiler's statistics of every pipeline (engine/gpu/shader_statistics.h); off by default.
  engine::gpu::ShaderStatisticsDesc shaderStatistics;
  // Compiled pipelines kept across runs (engine::gpu::ContextDesc::pipelineCacheFile; empty: not kept).
  std::filesystem::path pipelineCacheFile;
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
  // A glTF scene as separate objects: each mesh baked once into its own asset (at the tuning's K
  // and padding), drawn at every node that places it, except nodes drawn as triangles
  // (TuningState::nodeDraw, triangleNodes, the nodes' extras: hermite_sdf/render/scene_objects.h). A
  // new K, padding or shell bakes every mesh again (on the frame's thread); there is no comparison.
  bool objects = false;
  // The glTF animation played (animation_player.h: index or name, "none", empty: the first) from
  // `animationTime` seconds; each step moves it on by the frame's time (headless: 1/60 s). Played
  // with `objects` (rigid instances); the one SDF bakes the whole scene, so without `objects` the
  // scene is drawn (and baked) still, posed at `animationTime`.
  std::string animation;
  float animationTime = 0.0f;
};

class TuningPanel;

// Orbit: around the scene (drag rotates, right-drag/scroll zooms, middle-drag pans). Fly: WASD
// (Q/E down/up, Shift faster) and right-drag to look. Scene: through one of a glTF scene's camera
// nodes (Viewer::lookThroughSceneCamera), until the camera is moved.
enum class CameraMode { Orbit, Fly, Scene };

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
  // Orbit or fly from the eye and view direction of the camera now (F2 toggles; the first orbit or
  // fly gesture leaves a scene camera the same way). CameraMode::Scene is entered through
  // lookThroughSceneCamera, and ignored here.
  void setCameraMode(CameraMode mode);
  CameraMode cameraMode() const { return cameraMode_; }
  // The glTF scene's perspective and orthographic cameras, in the order of their nodes: each node's
  // name ("camera N" for a node without one).
  const std::vector<std::string>& sceneCameraNames() const { return sceneCameraNames_; }
  // Looks through a scene camera, named or given by its index in sceneCameraNames(): its node's
  // world pose (scale and shear dropped), its yfov and znear, the image's aspect ratio (a file's
  // aspectRatio is not letterboxed; the projection stays infinite), or for an orthographic camera
  // its ymag, znear and zfar (the view 2 ymag tall, as wide as the image's aspect: xmag is not
  // letterboxed either). The node's pose is read every
  // frame, so a camera node the scene moves is followed. Errors name the camera and why: no such
  // camera (the names are listed), a degenerate pose, a field of view not below pi, an eye farther
  // than kMaxSceneSize from the scene.
  engine::Status lookThroughSceneCamera(std::string_view nameOrIndex);
  engine::Status lookThroughSceneCamera(std::size_t index);
  // The index of a scene camera by name (first), else by index; the error lists the names.
  engine::Expected<std::size_t> findSceneCamera(std::string_view nameOrIndex) const;
  // The index of the scene camera looked through (meaningful while cameraMode() is Scene).
  std::size_t sceneCamera() const { return sceneCamera_; }

  const TuningState& tuning() const { return tuning_; }
  // Applied at the next step(). A new resolution or padding re-bakes the baked SDF on a worker
  // thread (hsdf::BakeJob); the old asset keeps drawing until the new one is ready.
  void setTuning(const TuningState& tuning);
  // What this scene cannot draw, said before it is asked for (a script, a settings file loaded
  // while running, the panel; the command line refuses the same before a Viewer exists): the mesh
  // method without triangles, a new K, padding or levels of detail without a source to bake (a
  // .hsdf file), a comparison of a scene of separate objects, another choice of the nodes drawn as
  // triangles (made when the scene loads).
  engine::Status checkTuning(const TuningState& tuning) const;
  // The running re-bake (progress(), cancel()), or null.
  hsdf::BakeJob* bakeJob() { return bakes_.job(); }
  // The level of detail being baked (TuningState::lod; coarser levels one after another), or null.
  hsdf::BakeJob* levelBakeJob() { return bakes_.levelJob(); }
  // Blocks until a running re-bake is done and in the scene, and with TuningState::lod until its
  // levels of detail are (they bake on worker threads too); the re-bake's error, if it failed.
  engine::Status waitForBake();
  // Cancels the running re-bake (the old field keeps drawing; K goes back to the drawn one), else
  // the level of detail being baked (the levels baked so far stay; levels of detail stay on).
  void cancelBake();
  // Why the last bake failed or was refused (budget, cancelled), or empty.
  const std::string& bakeError() const { return bakes_.error(); }

  // Split screen and difference view (TuningState::split, difference): the compared side is drawn
  // from its own bake at effectiveCompareResolution (on the worker thread too; until it is ready,
  // the main asset stands in). waitForBake() and cancelBake() cover this bake as well.
  hsdf::BakeJob* compareBakeJob() { return compare_.bakeJob(); }
  const std::string& compareBakeError() const { return compare_.bakeError(); }
  // The K the main side is drawn with now (the level the view picked with levels of detail) and
  // the K the compared side is drawn with now (0: no SDF).
  int resolutionDrawn() const;
  int compareResolutionDrawn() const;
  // The numbers of the last difference-view frame (empty when the view is off).
  const std::optional<NormalDifference>& difference() const { return compare_.difference(); }
  // Degrees shown red in the heat map.
  float differenceRange() const { return compare_.range(); }
  void setDifferenceRange(float degrees) { compare_.setRange(degrees); }

  // Recreates every render feature's pipelines from the SPIR-V on disk (the panel's "Reload
  // shaders", F5, the script's reload-shaders). A feature that fails keeps drawing with its old
  // pipelines; the report (shaderReloadReport()) and the log say which and why.
  std::vector<engine::render::Renderer::ShaderReload> reloadShaders();
  // The panel's button and F5: the build tree's shader target first (shader_build.h), then
  // reloadShaders(). A failed build reloads nothing: the old pipelines stay and the report holds
  // the compiler's output.
  void rebuildAndReloadShaders();
  const std::string& shaderReloadReport() const { return shaderReloadReport_; }
  // The SDF in the scene (shown or hidden by the method), or null.
  const hsdf::SdfAsset* sdfAsset() const;
  // Whether a new K can be baked (a glTF scene, its separate objects or an analytic shape; not a
  // .hsdf file).
  bool canRebake() const { return bakes_.source() != nullptr || sceneObjects_.loaded(); }
  // Whether Method::Mesh has triangles to show (a glTF scene).
  bool hasMeshes() const { return sceneTriangles_; }
  // SceneDesc::objects: the entities drawing a mesh's shared asset (one per SDF node), and the
  // bakes that made those assets (one per mesh they use).
  const std::vector<engine::ecs::Entity>& sdfObjects() const { return sceneObjects_.entities(); }
  int objectBakes() const { return sceneObjects_.bakes(); }

  // Windowed: the user closed the window. Headless: never.
  bool shouldClose() const;
  // One frame: (windowed: input, camera, resize; a minimised window waits for events at most 50 ms
  // and draws nothing, framesRendered() stays) a
  // finished re-bake, tuning -> SDF components, world transforms, UI frame, render (recreating an
  // out-of-date swapchain). Errors: a lost device (every later step fails too); GPU memory running
  // out while the frame was recorded (that frame is skipped; the next step draws again); an object
  // a feature dropped because its new GPU buffers did not fit (the frame drew the rest of the
  // scene; the object stays undrawn, later steps succeed).
  engine::Status step();
  std::uint64_t framesRendered() const { return frames_; }
  // Whether a step found the device lost: every later step fails with that error.
  bool deviceLost() const { return deviceLost_; }

  // The root-search work of the scene as it stands: one more frame (not presented, no panel, its
  // image the same as the last one's) drawn with the renderer's work counters (counting pipeline
  // variants). Sums over the frame: field evaluations, and sphere-tracing rays that ran out of
  // steps (drawn as misses; 0 unless something is wrong).
  struct FrameWork {
    std::uint64_t evaluations = 0;
    std::uint32_t raysOutOfSteps = 0;
    // Tiled cells (zero without tiles): the non-empty tiles drawn, the list entries they needed,
    // and the entries the fragments read and ray-box tested (the tiles' walk, beside the search).
    std::uint32_t tilesDrawn = 0;
    std::uint32_t tileEntries = 0;
    bool tilesOverflowed = false;  // the lists needed more entries than allowed: boxes were drawn
    std::uint64_t tileEntriesWalked = 0;
    std::uint64_t tileEntriesTested = 0;
    std::uint64_t tileMaskWordsRead = 0;
  };
  engine::Expected<FrameWork> countWork();

  // Waits for the GPU and writes the last frame as a PNG, the TuningState beside it as a settings
  // file (same name, .json: --settings loads it) and the SDF statistics to the log.
  engine::Status writeScreenshot(const std::filesystem::path& path);
  // writeScreenshot after the next frame is drawn (the panel's button; the UI is in the image).
  void requestScreenshot(std::filesystem::path path) { screenshots_.request(std::move(path)); }
  // What the last requested screenshot or settings file operation said ("wrote x.png", an error).
  const std::string& statusLine() const { return screenshots_.statusLine(); }
  void setStatusLine(std::string line) { screenshots_.setStatusLine(std::move(line)); }

  // The UI panels on or off (F1); off leaves only the scene in windowed screenshots.
  void setUiVisible(bool visible) { uiVisible_ = visible; }
  // Window only (no-ops headless, where resize() sets the image size): V-sync (recreates the
  // swapchain with FIFO or the fastest mode the surface has), full screen (F11).
  engine::Status setVsync(bool vsync);
  bool vsync() const;
  void setFullscreen(bool fullscreen);
  bool fullscreen() const;
  // Minimises (iconifies) or restores the window and waits (at most 2 s) until the window system
  // has done it; an error when it did not (X11 without a window manager) or headless. While
  // minimised, step() draws nothing and returns after a short wait for events.
  engine::Status setMinimized(bool minimized);
  // Swapchains created after the first (resize, out of date, suboptimal, restore).
  std::uint64_t swapchainRecreations() const;
  // Windowed: asks for a new window size (applied asynchronously by the window system; several
  // requests in a row may arrive as one); headless: resizes the render targets now.
  void resize(std::uint32_t width, std::uint32_t height);
  // Windowed: waits (at most 2 s) until the window has the size last asked for; an error if the
  // window system did not apply it. Headless: nothing to wait for.
  engine::Status waitForWindowSize();
  bool windowed() const { return window_ != nullptr; }
  // Seconds the last windowed frame took (headless: 1/60).
  float frameSeconds() const { return frameSeconds_; }

  engine::gpu::Context& context() { return *context_; }
  engine::render::Renderer& renderer() { return *renderer_; }
  // The meshes of the registry's MeshRenderables (a renderer drawing the registry needs them).
  engine::render::MeshPool& meshPool() { return *pool_; }
  engine::ecs::Registry& registry() { return registry_; }
  glm::vec3 boundsMin() const { return boundsMin_; }
  glm::vec3 boundsMax() const { return boundsMax_; }

  // Tears everything down in dependency order; an error when the validation layers reported
  // anything during the Viewer's life (objects left at device destruction included) or the final
  // wait for the GPU failed. Never throws for a failed Vulkan call; the destructor does the same
  // and logs the error.
  engine::Status close();

 private:
  Viewer() = default;
  engine::Status initialize(const ViewerDesc& desc);
  void handleInput(float dt);
  // The camera (viewer_camera.cpp): this frame's gestures; the scene's camera nodes at load.
  void moveCamera(const engine::platform::InputState& input, float dt);
  void collectSceneCameras(const std::vector<engine::ecs::Entity>& cameras);
  engine::Expected<engine::render::CameraView> sceneCameraView(std::size_t index) const;
  void handleKeys(const engine::platform::InputState& input);
  void updateVisibility(Method method, bool meshes = true);
  void finishStep();
  void showState(const TuningState& tuning, const std::shared_ptr<const hsdf::SdfAsset>& asset);
  std::vector<engine::render::ViewRegion> splitRegions(const std::shared_ptr<const hsdf::SdfAsset>& main);
  void updateCompareBake();
  void warnIfCellsOnly();
  engine::Expected<bool> renderFrame(const engine::render::FrameSettings& settings);
  engine::Status droppedObjectsError(std::uint64_t frame);
  void applyTuningToScene();
  void updateLevelsOfDetail(bool wait);
  // Scene loading (viewer_scene.cpp).
  engine::Status addBakedSdf(hsdf::BakeSource source, const SceneDesc& scene, const glm::vec3& origin = glm::vec3(0.0f));
  static glm::vec3 bakeOrigin(const glm::vec3& lo, const glm::vec3& hi);
  engine::Status addSdfFile(const std::filesystem::path& file, bool frameIt);
  engine::Status loadGltf(const SceneDesc& scene);
  engine::Expected<std::optional<AnimationPlayer>> startAnimation(const SceneDesc& scene, engine::scene::SceneData& data);
  engine::Expected<engine::scene::SceneData> oneSdfPart(const engine::scene::SceneData& data,
                                                        const engine::render::InstantiatedScene& instantiated,
                                                        const std::filesystem::path& file);
  void addGroundPlane();

  std::unique_ptr<engine::gpu::Context> context_;
  std::unique_ptr<ViewerWindow> window_;
  std::unique_ptr<engine::render::MeshPool> pool_;
  std::unique_ptr<engine::render::Renderer> renderer_;
  std::unique_ptr<engine::ui::UiLayer> ui_;
  std::unique_ptr<TuningPanel> panel_;
  engine::ecs::Registry registry_;

  glm::vec3 boundsMin_{-1.0f};
  glm::vec3 boundsMax_{1.0f};
  engine::platform::OrbitController orbit_;
  engine::platform::FlyController fly_;
  CameraMode cameraMode_ = CameraMode::Orbit;
  std::vector<std::string> sceneCameraNames_;      // lookThroughSceneCamera
  std::optional<AnimationPlayer> animation_;      // SceneDesc::animation, played with SceneDesc::objects
  std::vector<engine::ecs::Entity> sceneCameras_;  // their nodes, same order
  std::size_t sceneCamera_ = 0;
  float fovY_ = 0.8f;
  float znear_ = 0.01f;
  std::uint64_t frames_ = 0;
  TuningState tuning_;

  // The SDF entity (baked or from a .hsdf file) and its bakes. A glTF scene keeps its mesh
  // entities: the method shows one or the other (a hidden mesh's renderable waits in hiddenMeshes_).
  SdfBakes bakes_{registry_, tuning_};
  bool sideBySide_ = false;
  bool warnedCellsOnly_ = false;  // warnIfCellsOnly said it for the current request
  // The mesh parts the SDF stands for (hidden while it draws); the parts of triangle nodes (a
  // see-through mesh: hsdf::oneSdfScene, SdfObjects) are not among them and always draw.
  std::vector<engine::ecs::Entity> meshEntities_;
  bool sceneTriangles_ = false;  // the glTF scene has triangle meshes (Method::Mesh draws them)
  std::vector<std::pair<engine::ecs::Entity, engine::render::MeshRenderable>> hiddenMeshes_;
  SdfObjects sceneObjects_{registry_, tuning_, bakes_};  // SceneDesc::objects

  // The split screen's / difference view's other side; its view regions show it with showState.
  ComparedSide compare_{[this](const TuningState& tuning, const std::shared_ptr<const hsdf::SdfAsset>& asset) {
    showState(tuning, asset);
  }};
  std::string shaderReloadReport_;

  Screenshots screenshots_;
  bool uiVisible_ = true;
  float frameSeconds_ = 1.0f / 60.0f;
  bool closed_ = false;
  bool deviceLost_ = false;   // a checked call reported VK_ERROR_DEVICE_LOST
  std::string frameFailure_;  // why the scene cannot continue (device lost)
};

}  // namespace samples
