#include "runner.h"

#include <chrono>

#include <fmt/format.h>
#include <imgui.h>

#include "engine/core/image_io.h"
#include "engine/core/log.h"
#include "engine/ecs/registry.h"
#include "engine/gpu/context.h"
#include "engine/gpu/swapchain.h"
#include "engine/platform/camera_controller.h"
#include "engine/platform/window.h"
#include "engine/render/components.h"
#include "engine/render/mesh_feature.h"
#include "engine/render/renderer.h"
#include "engine/render/scene_instantiate.h"
#include "engine/scene/gltf_loader.h"
#include "engine/scene/transform.h"
#include "engine/ui/ui_layer.h"
#include "hermite_sdf/cell_feature.h"
#include "hermite_sdf/sphere_trace_feature.h"
#include "sdf_scene.h"

namespace runner {
namespace {

using namespace engine;

gpu::DevicePreference devicePreference(const std::string& name) {
  if (name == "gpu") return gpu::DevicePreference::Hardware;
  if (name == "lavapipe") return gpu::DevicePreference::Software;
  return gpu::DevicePreference::Auto;
}

// A thin box under the scene so that occlusion and the depth prepass have something to show.
void addGroundPlane(ecs::Registry& registry, render::MeshPool& pool, const glm::vec3& lo, const glm::vec3& hi) {
  const glm::vec3 size = hi - lo;
  const float extent = 1.5f * std::max(size.x, size.z);
  const glm::vec3 center(0.5f * (lo.x + hi.x), lo.y, 0.5f * (lo.z + hi.z));
  const glm::vec3 p[4] = {{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}};
  std::vector<glm::vec3> positions, normals;
  for (const glm::vec3& corner : p) {
    positions.push_back(corner);
    normals.emplace_back(0.0f, 1.0f, 0.0f);
  }
  const std::vector<std::uint32_t> indices = {0, 1, 2, 0, 2, 3};
  const ecs::Entity ground = registry.create();
  scene::Transform transform;
  transform.translation = center;
  transform.scale = glm::vec3(extent, 1.0f, extent);
  registry.emplace<scene::Transform>(ground, transform);
  render::MeshRenderable renderable;
  renderable.mesh = pool.add(positions, normals, indices);
  renderable.color = glm::vec4(0.35f, 0.37f, 0.4f, 1.0f);
  renderable.roughness = 0.9f;
  registry.emplace<render::MeshRenderable>(ground, renderable);
  registry.emplace<scene::Name>(ground, scene::Name{"ground"});
}

struct SceneState {
  ecs::Registry registry;
  glm::vec3 boundsMin{-1.0f};
  glm::vec3 boundsMax{1.0f};
};

// In double: the float length of a box 1e20 across overflows.
double diagonal(const glm::vec3& lo, const glm::vec3& hi) { return glm::length(glm::dvec3(hi) - glm::dvec3(lo)); }
double sceneDiagonal(const SceneState& scene) { return diagonal(scene.boundsMin, scene.boundsMax); }

// The range is documented with kMinSceneSize in runner_options.h.
Status checkDrawableSize(const std::filesystem::path& file, const glm::vec3& lo, const glm::vec3& hi) {
  const double size = diagonal(lo, hi);
  if (size >= kMinSceneSize && size <= kMaxSceneSize) return {};
  return makeError(fmt::format("{}: the scene is {:g} across (bounding-box diagonal); the scene runner draws scenes "
                               "{:g} to {:g} across (32-bit float camera and shaders)",
                               file.string(), size, kMinSceneSize, kMaxSceneSize));
}

// Replaces the scene's meshes by one SDF baked from them (or adds it beside them).
Status addSdfObject(const Options& options, const scene::SceneData& data, const render::InstantiatedScene& instantiated,
                    SceneState& state) {
  if (instantiated.renderables.empty()) return makeError(options.scene.string() + ": no triangle meshes to bake into an SDF");
  ENGINE_TRY_ASSIGN(std::shared_ptr<const hsdf::SdfAsset> asset,
                    bakeSceneSdf(data, options.resolution, options.padding).withContext(options.scene.string()));
  glm::vec3 offset(0.0f);
  if (options.sideBySide) {
    offset.x = 1.25f * (state.boundsMax.x - state.boundsMin.x);
    state.boundsMax.x += offset.x;
  } else {
    for (ecs::Entity e : instantiated.renderables) state.registry.remove<render::MeshRenderable>(e);
  }
  hsdf::HermiteSdfRenderable renderable = renderableFromOptions(options, std::move(asset));
  if (!data.materials.empty()) renderable.color = data.materials.front().baseColor;  // look like the mesh
  addSdfEntity(state.registry, renderable, offset);
  return {};
}

// Draws a baked .hsdf file; without a glTF scene its grid bounds frame the camera.
Status addSdfFile(const Options& options, bool hasScene, SceneState& state) {
  ENGINE_TRY_ASSIGN(std::shared_ptr<const hsdf::SdfAsset> asset, loadSdfFile(options.sdfFile));
  if (options.method != "cells" && asset->field.samples.empty())
    return makeError(options.sdfFile.string() + ": holds only cells; --method " + options.method +
                     " needs the dense field (bake without --cells)");
  const hsdf::Aabb bounds = asset->cells.grid.bounds();
  ENGINE_TRY(checkDrawableSize(options.sdfFile, glm::vec3(bounds.min), glm::vec3(bounds.max)));
  if (!hasScene) {
    state.boundsMin = glm::vec3(bounds.min);
    state.boundsMax = glm::vec3(bounds.max);
  }
  addSdfEntity(state.registry, renderableFromOptions(options, std::move(asset)), glm::vec3(0.0f));
  return {};
}

Status loadScene(const Options& options, SceneState& state, render::MeshPool& pool) {
  if (options.scene.empty()) {
    ENGINE_TRY(addSdfFile(options, false, state));
    if (options.groundPlane) addGroundPlane(state.registry, pool, state.boundsMin, state.boundsMax);
    scene::updateWorldTransforms(state.registry);
    return {};
  }
  if (!options.sdfFile.empty()) ENGINE_TRY(addSdfFile(options, true, state));
  ENGINE_TRY_ASSIGN(scene::SceneData data, scene::loadGltf(options.scene));
  const render::InstantiatedScene instantiated = render::instantiateScene(data, state.registry, pool);
  if (instantiated.renderables.empty())
    log::warn("{}: the scene has no triangle meshes", options.scene.string());
  else {
    state.boundsMin = instantiated.boundsMin;
    state.boundsMax = instantiated.boundsMax;
    ENGINE_TRY(checkDrawableSize(options.scene, state.boundsMin, state.boundsMax));
  }
  if (options.method != "mesh" && options.sdfFile.empty()) ENGINE_TRY(addSdfObject(options, data, instantiated, state));
  if (options.groundPlane) addGroundPlane(state.registry, pool, state.boundsMin, state.boundsMax);
  scene::updateWorldTransforms(state.registry);
  return {};
}

void logTimings(const render::Renderer& renderer) {
  for (const gpu::GpuTiming& t : renderer.lastTimings()) log::info("GPU {:>14}: {:8.3f} ms", t.name, t.milliseconds);
}

struct App {
  std::unique_ptr<gpu::Context> context;
  std::unique_ptr<platform::Window> window;
  std::unique_ptr<render::MeshPool> pool;
  std::unique_ptr<render::Renderer> renderer;
  std::unique_ptr<ui::UiLayer> ui;
  std::unique_ptr<gpu::Swapchain> swapchain;
  SceneState scene;
  platform::OrbitController orbit;
  float fovY = 0.8f;
  float znear = 0.01f;
  std::uint32_t debugView = 0;

  render::CameraView camera(VkExtent2D extent) const {
    const float aspect = float(extent.width) / float(std::max(extent.height, 1u));
    return render::CameraView::lookAt(orbit.eye(), orbit.target, fovY, znear, aspect);
  }
};

// --size is capped at 16384 by parseOptions; a device may allow less (Vulkan only promises 4096).
// Checked before the renderer allocates its images, since the options are what is wrong.
Status checkImageSize(const Options& options, const gpu::Context& context) {
  VkPhysicalDeviceProperties properties;
  vkGetPhysicalDeviceProperties(context.physicalDevice(), &properties);
  const std::uint32_t limit = properties.limits.maxImageDimension2D;
  if (options.width <= limit && options.height <= limit) return {};
  return makeError(fmt::format("--size {}x{}: the device '{}' supports images up to {} pixels per side "
                               "(maxImageDimension2D)",
                               options.width, options.height, context.capabilities().deviceName, limit));
}

Status createApp(const Options& options, App& app) {
  gpu::ContextDesc desc;
  desc.device = devicePreference(options.device);
  if (options.validation) desc.validation = true;
  if (!options.headless) {
    ENGINE_TRY_ASSIGN(app.window, platform::Window::create("hermite_sdf scene runner", int(options.width), int(options.height)));
    desc.instanceExtensions = platform::Window::requiredInstanceExtensions();
    desc.swapchain = true;
  }
  ENGINE_TRY_ASSIGN(app.context, gpu::Context::create(desc));
  ENGINE_TRY(checkImageSize(options, *app.context));
  app.pool = std::make_unique<render::MeshPool>(*app.context);
  ENGINE_TRY(loadScene(options, app.scene, *app.pool));
  app.orbit = platform::framingOrbit(app.scene.boundsMin, app.scene.boundsMax, app.fovY, options.view.value_or(0));
  if (options.camera) {
    // In double: parseOptions only promises that the distance fits a float, not its square.
    const auto& c = *options.camera;
    const glm::dvec3 eye(c[0], c[1], c[2]), target(c[3], c[4], c[5]);
    const double distance = glm::length(eye - target);
    const glm::dvec3 d = (eye - target) / distance;
    app.orbit.target = glm::vec3(target);
    app.orbit.radius = float(distance);
    app.orbit.minRadius = std::min(app.orbit.minRadius, app.orbit.radius);
    app.orbit.maxRadius = std::max(app.orbit.maxRadius, app.orbit.radius);
    app.orbit.pitch = float(std::asin(std::clamp(d.y, -1.0, 1.0)));
    app.orbit.yaw = float(std::atan2(d.x, d.z));
  }
  app.debugView = debugViewIndex(options.debugView);
  app.znear = float(0.01 * sceneDiagonal(app.scene));

  VkExtent2D extent{options.width, options.height};
  if (app.window) {
    ENGINE_TRY(app.window->createSurface(app.context->instance()));
    ENGINE_TRY_ASSIGN(app.swapchain, gpu::Swapchain::create(*app.context, app.window->surface(),
                                                             app.window->framebufferExtent(), true));
    extent = app.swapchain->extent();
  }
  app.renderer = std::make_unique<render::Renderer>(*app.context, render::RendererDesc{}, extent);
  ENGINE_TRY(app.renderer->addFeature(std::make_unique<render::MeshFeature>(*app.pool)));
  ENGINE_TRY(app.renderer->addFeature(std::make_unique<hsdf::HermiteCellFeature>()));
  app.renderer->feature<hsdf::HermiteCellFeature>()->settings().frontToBack = options.frontToBack;
  ENGINE_TRY(app.renderer->addFeature(std::make_unique<hsdf::SphereTraceFeature>()));
  if (app.window || options.headlessUi) {
    ENGINE_TRY_ASSIGN(app.ui, ui::UiLayer::create(*app.context, app.renderer->desc().formats.color,
                                                  app.renderer->desc().framesInFlight, app.window.get()));
    app.ui->addPanel("view", [&app] {
      ImGui::Text("%s", app.context->capabilities().deviceName.c_str());
      static const char* views[] = {"shaded", "normals", "depth", "cells", "evaluations", "cell boxes"};
      int view = int(app.debugView);
      if (ImGui::Combo("debug view", &view, views, 6)) app.debugView = std::uint32_t(view);
      if (ImGui::CollapsingHeader("GPU timings", ImGuiTreeNodeFlags_DefaultOpen))
        for (const gpu::GpuTiming& t : app.renderer->lastTimings()) ImGui::Text("%-14s %8.3f ms", t.name.c_str(), t.milliseconds);
    });
    app.ui->addFeaturePanels(*app.renderer);
  }
  return {};
}

Status writeScreenshot(App& app, const std::filesystem::path& path) {
  const std::vector<std::uint8_t> pixels = app.renderer->readbackColor();
  const VkExtent2D extent = app.renderer->extent();
  ENGINE_TRY(writePng(path, pixels, extent.width, extent.height, 4));
  log::info("screenshot: {}", path.string());
  return {};
}

Status runHeadless(const Options& options, App& app) {
  for (std::uint32_t frame = 0; frame < options.frames; ++frame) {
    if (app.ui) app.ui->buildFrame(app.renderer->extent(), 1.0f / 60.0f);
    render::FrameSettings settings;
    settings.debugView = app.debugView;
    settings.overlay = app.ui.get();
    app.renderer->renderFrame(app.scene.registry, app.camera(app.renderer->extent()), settings);
  }
  app.renderer->finish();
  logTimings(*app.renderer);
  if (!options.screenshot.empty()) ENGINE_TRY(writeScreenshot(app, options.screenshot));
  return {};
}

Status recreateSwapchain(App& app) {
  app.window->waitWhileMinimized();
  ENGINE_TRY(app.swapchain->recreate(app.window->framebufferExtent()));
  app.renderer->resize(app.swapchain->extent());
  return {};
}

Status runWindowed(const Options& options, App& app) {
  auto last = std::chrono::steady_clock::now();
  std::uint32_t frames = 0;
  while (!app.window->shouldClose() && (options.frames == 0 || frames < options.frames)) {
    app.window->pollEvents();
    if (app.window->minimized()) {
      app.window->waitWhileMinimized();
      continue;
    }
    const auto now = std::chrono::steady_clock::now();
    const float dt = std::chrono::duration<float>(now - last).count();
    last = now;
    platform::InputState& input = app.window->input();
    input.uiWantsMouse = app.ui && app.ui->wantsMouse();
    input.uiWantsKeyboard = app.ui && app.ui->wantsKeyboard();
    app.orbit.update(input);
    const VkExtent2D windowExtent = app.window->framebufferExtent();
    if (windowExtent.width != app.swapchain->extent().width || windowExtent.height != app.swapchain->extent().height)
      ENGINE_TRY(recreateSwapchain(app));
    scene::updateWorldTransforms(app.scene.registry);
    if (app.ui) app.ui->buildFrame(app.renderer->extent(), dt);
    render::FrameSettings settings;
    settings.debugView = app.debugView;
    settings.swapchain = app.swapchain.get();
    settings.overlay = app.ui.get();
    if (!app.renderer->renderFrame(app.scene.registry, app.camera(app.renderer->extent()), settings))
      ENGINE_TRY(recreateSwapchain(app));
    ++frames;
  }
  app.renderer->finish();
  logTimings(*app.renderer);
  if (!options.screenshot.empty()) ENGINE_TRY(writeScreenshot(app, options.screenshot));
  return {};
}

}  // namespace

Status run(const Options& options) {
  App app;
  ENGINE_TRY(createApp(options, app));
  Status status = options.headless ? runHeadless(options, app) : runWindowed(options, app);
  // Tear down in dependency order: everything that uses the device before the device.
  app.context->waitIdle();
  app.ui.reset();
  app.renderer.reset();
  app.swapchain.reset();
  if (app.window) app.window->destroySurface(app.context->instance());
  app.pool.reset();
  const std::uint32_t validationMessages = app.context->validationMessageCount();
  app.context.reset();
  if (status.ok() && validationMessages > 0)
    return makeError(std::to_string(validationMessages) + " Vulkan validation message(s); see the log above");
  return status;
}

}  // namespace runner
