#include "viewer.h"

#include <chrono>

#include <fmt/format.h>
#include <imgui.h>

#include "engine/core/image_io.h"
#include "engine/core/log.h"
#include "engine/gpu/swapchain.h"
#include "engine/platform/window.h"
#include "engine/render/components.h"
#include "engine/render/mesh_feature.h"
#include "engine/scene/transform.h"
#include "engine/ui/ui_layer.h"
#include "hermite_sdf/cell_feature.h"
#include "hermite_sdf/sphere_trace_feature.h"

namespace samples {

using namespace engine;

namespace {

// Vulkan only promises 4096 pixels per side; checked before the renderer allocates its images so
// that the message names the size that was asked for.
Status checkImageSize(const ViewerDesc& desc, const gpu::Context& context) {
  VkPhysicalDeviceProperties properties;
  vkGetPhysicalDeviceProperties(context.physicalDevice(), &properties);
  const std::uint32_t limit = properties.limits.maxImageDimension2D;
  if (desc.width <= limit && desc.height <= limit) return {};
  return makeError(fmt::format("--size {}x{}: the device '{}' supports images up to {} pixels per side "
                               "(maxImageDimension2D)",
                               desc.width, desc.height, context.capabilities().deviceName, limit));
}

double nowSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

Expected<std::unique_ptr<Viewer>> Viewer::create(const ViewerDesc& desc) {
  std::unique_ptr<Viewer> viewer(new Viewer());
  ENGINE_TRY(viewer->initialize(desc));
  return viewer;
}

Viewer::~Viewer() { (void)close(); }

Status Viewer::initialize(const ViewerDesc& desc) {
  gpu::ContextDesc contextDesc;
  contextDesc.device = desc.device;
  if (desc.validation) contextDesc.validation = true;
  if (!desc.headless) {
    ENGINE_TRY_ASSIGN(window_, platform::Window::create(desc.title, int(desc.width), int(desc.height)));
    contextDesc.instanceExtensions = platform::Window::requiredInstanceExtensions();
    contextDesc.swapchain = true;
  }
  ENGINE_TRY_ASSIGN(context_, gpu::Context::create(contextDesc));
  ENGINE_TRY(checkImageSize(desc, *context_));
  pool_ = std::make_unique<render::MeshPool>(*context_);

  VkExtent2D extent{desc.width, desc.height};
  if (window_) {
    ENGINE_TRY(window_->createSurface(context_->instance()));
    ENGINE_TRY_ASSIGN(swapchain_, gpu::Swapchain::create(*context_, window_->surface(), window_->framebufferExtent(), true));
    extent = swapchain_->extent();
  }
  renderer_ = std::make_unique<render::Renderer>(*context_, render::RendererDesc{}, extent);
  ENGINE_TRY(renderer_->addFeature(std::make_unique<render::MeshFeature>(*pool_)));
  ENGINE_TRY(renderer_->addFeature(std::make_unique<hsdf::HermiteCellFeature>()));
  ENGINE_TRY(renderer_->addFeature(std::make_unique<hsdf::SphereTraceFeature>()));
  if (window_ || desc.headlessUi) {
    ENGINE_TRY_ASSIGN(ui_, ui::UiLayer::create(*context_, renderer_->desc().formats.color,
                                               renderer_->desc().framesInFlight, window_.get()));
    addViewPanel();
    ui_->addFeaturePanels(*renderer_);
  }
  lastFrameTime_ = nowSeconds();
  return {};
}

// The runner's one inline panel (the tuning panel of issue 11 replaces it).
void Viewer::addViewPanel() {
  ui_->addPanel("view", [this] {
    ImGui::Text("%s", context_->capabilities().deviceName.c_str());
    static const char* views[] = {"shaded", "normals", "depth", "cells", "evaluations", "cell boxes"};
    int view = int(tuning_.debugView);
    if (ImGui::Combo("debug view", &view, views, 6)) tuning_.debugView = DebugView(view);
    if (ImGui::CollapsingHeader("GPU timings", ImGuiTreeNodeFlags_DefaultOpen))
      for (const gpu::GpuTiming& t : renderer_->lastTimings()) ImGui::Text("%-14s %8.3f ms", t.name.c_str(), t.milliseconds);
  });
}

void Viewer::setOrbitView(int index) { orbit_ = platform::framingOrbit(boundsMin_, boundsMax_, fovY_, index); }

void Viewer::setCamera(const glm::dvec3& eye, const glm::dvec3& target) {
  // In double: a distance that fits a float may have a square that does not.
  const double distance = glm::length(eye - target);
  const glm::dvec3 d = (eye - target) / distance;
  orbit_.target = glm::vec3(target);
  orbit_.radius = float(distance);
  orbit_.minRadius = std::min(orbit_.minRadius, orbit_.radius);
  orbit_.maxRadius = std::max(orbit_.maxRadius, orbit_.radius);
  orbit_.pitch = float(std::asin(std::clamp(d.y, -1.0, 1.0)));
  orbit_.yaw = float(std::atan2(d.x, d.z));
}

render::CameraView Viewer::cameraView() const {
  const VkExtent2D extent = renderer_->extent();
  const float aspect = float(extent.width) / float(std::max(extent.height, 1u));
  return render::CameraView::lookAt(orbit_.eye(), orbit_.target, fovY_, znear_, aspect);
}

void Viewer::setTuning(const TuningState& tuning) {
  tuning_ = tuning;
  if (!bakeSource_) return;
  // Compared with what is being baked, else with what is drawn.
  const int resolution = bakeJob_ ? bakeJob_->settings().resolution : bakedResolution_;
  const int padding = bakeJob_ ? bakeJob_->settings().padding : bakedPadding_;
  if (tuning.resolution != resolution || tuning.padding != padding) startRebake();
}

void Viewer::startRebake() {
  hsdf::BakeSettings settings;
  settings.resolution = tuning_.resolution;
  settings.padding = tuning_.padding;
  bakeJob_.reset();  // cancels a re-bake for settings that are already outdated
  bakeJob_ = std::make_unique<hsdf::BakeJob>(*bakeSource_, settings);
}

// Swaps the re-bake's asset into the entity (waiting for it); a failed one leaves the old asset.
Status Viewer::finishBake() {
  hsdf::BakeJob::Result result = bakeJob_->wait();
  const hsdf::BakeSettings settings = bakeJob_->settings();
  bakeJob_.reset();
  if (!result) return result.error().withContext(fmt::format("re-baking at resolution {}", settings.resolution));
  registry_.get<hsdf::HermiteSdfRenderable>(*bakedEntity_).asset = std::move(*result);
  bakedResolution_ = settings.resolution;
  bakedPadding_ = settings.padding;
  return {};
}

Status Viewer::waitForBake() { return bakeJob_ ? finishBake() : Status{}; }

void Viewer::applyTuningToScene() {
  registry_.view<hsdf::HermiteSdfRenderable>().each(
      [this](ecs::Entity, hsdf::HermiteSdfRenderable& renderable) { applyTuning(tuning_, renderable); });
  renderer_->feature<hsdf::HermiteCellFeature>()->settings().frontToBack = tuning_.frontToBack;
}

bool Viewer::shouldClose() const { return window_ && window_->shouldClose(); }

Status Viewer::recreateSwapchain() {
  window_->waitWhileMinimized();
  ENGINE_TRY(swapchain_->recreate(window_->framebufferExtent()));
  renderer_->resize(swapchain_->extent());
  return {};
}

Status Viewer::handleWindow(bool& drawable) {
  window_->pollEvents();
  drawable = !window_->minimized();
  if (!drawable) {
    window_->waitWhileMinimized();
    return {};
  }
  platform::InputState& input = window_->input();
  input.uiWantsMouse = ui_ && ui_->wantsMouse();
  input.uiWantsKeyboard = ui_ && ui_->wantsKeyboard();
  orbit_.update(input);
  const VkExtent2D extent = window_->framebufferExtent();
  if (extent.width != swapchain_->extent().width || extent.height != swapchain_->extent().height)
    ENGINE_TRY(recreateSwapchain());
  return {};
}

Status Viewer::step() {
  float dt = 1.0f / 60.0f;  // headless frames are deterministic
  if (window_) {
    bool drawable = true;
    ENGINE_TRY(handleWindow(drawable));
    if (!drawable) return {};
    const double now = nowSeconds();
    dt = float(now - lastFrameTime_);
    lastFrameTime_ = now;
  }
  if (bakeJob_ && bakeJob_->done())
    if (Status baked = finishBake(); !baked) log::warn("{}", baked.error().message);
  applyTuningToScene();
  scene::updateWorldTransforms(registry_);
  if (ui_) ui_->buildFrame(renderer_->extent(), dt);
  render::FrameSettings settings;
  settings.debugView = std::uint32_t(tuning_.debugView);
  settings.swapchain = swapchain_.get();
  settings.overlay = ui_.get();
  if (!renderer_->renderFrame(registry_, cameraView(), settings)) ENGINE_TRY(recreateSwapchain());
  ++frames_;
  return {};
}

Status Viewer::writeScreenshot(const std::filesystem::path& path) {
  renderer_->finish();
  const std::vector<std::uint8_t> pixels = renderer_->readbackColor();
  const VkExtent2D extent = renderer_->extent();
  ENGINE_TRY(writePng(path, pixels, extent.width, extent.height, 4));
  log::info("screenshot: {}", path.string());
  return {};
}

Status Viewer::close() {
  if (closed_ || !context_) return {};
  closed_ = true;
  bakeJob_.reset();
  context_->waitIdle();
  ui_.reset();
  renderer_.reset();
  swapchain_.reset();
  if (window_) window_->destroySurface(context_->instance());
  registry_.clear();
  pool_.reset();
  const std::uint32_t messages = context_->validationMessageCount();
  context_.reset();
  window_.reset();
  if (messages > 0) return makeError(std::to_string(messages) + " Vulkan validation message(s); see the log above");
  return {};
}

}  // namespace samples
