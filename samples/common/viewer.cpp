#include "viewer.h"

#include <chrono>

#include <GLFW/glfw3.h>

#include <fmt/format.h>
#include <imgui.h>

#include "engine/core/image_io.h"
#include "engine/core/log.h"
#include "engine/gpu/swapchain.h"
#include "engine/gpu/vk_check.h"
#include "engine/platform/window.h"
#include "engine/render/components.h"
#include "engine/render/mesh_feature.h"
#include "engine/scene/transform.h"
#include "engine/ui/ui_layer.h"
#include "hermite_sdf/cell_feature.h"
#include "hermite_sdf/sphere_trace_feature.h"
#include "tuning_panel.h"

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
  try {  // a GPU memory budget too small for the render targets is an error, like a bad option
    ENGINE_TRY(viewer->initialize(desc));
  } catch (const gpu::VulkanError& e) {
    if (e.result() != VK_ERROR_OUT_OF_DEVICE_MEMORY) throw;
    return makeError(fmt::format("creating the renderer: out of GPU memory ({})", e.what()));
  }
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
  bakeBudget_ = desc.bakeBudget;
  ENGINE_TRY_ASSIGN(context_, gpu::Context::create(contextDesc));
  context_->allocator().setBudget(desc.gpuMemoryBudget);
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
    if (!desc.uiIniFile.empty()) ui_->setIniFile(desc.uiIniFile.string());
    panel_ = std::make_unique<TuningPanel>(*this);
    ui_->addPanel("tuning", [this] { panel_->draw(); });
    ui_->addFeaturePanels(*renderer_);
  }
  lastFrameTime_ = nowSeconds();
  return {};
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
  if (cameraMode_ == CameraMode::Fly)
    return render::CameraView::lookAt(fly_.position, fly_.position + fly_.forward(), fovY_, znear_, aspect);
  return render::CameraView::lookAt(orbit_.eye(), orbit_.target, fovY_, znear_, aspect);
}

void Viewer::setCameraMode(CameraMode mode) {
  if (mode == cameraMode_) return;
  cameraMode_ = mode;
  if (mode == CameraMode::Orbit) {  // orbit around the point the fly camera looked at
    setCamera(glm::dvec3(fly_.position), glm::dvec3(fly_.position + fly_.forward() * orbit_.radius));
    return;
  }
  const glm::vec3 eye = orbit_.eye();
  const glm::vec3 d = glm::normalize(orbit_.target - eye);
  fly_.position = eye;
  fly_.pitch = std::asin(std::clamp(d.y, -1.0f, 1.0f));
  fly_.yaw = std::atan2(-d.x, -d.z);  // FlyController::forward() inverted
  fly_.speed = 0.5f * glm::length(boundsMax_ - boundsMin_);  // half the scene per second
}

void Viewer::setTuning(const TuningState& tuning) {
  tuning_ = tuning;
  if (!bakeSource_ || (!bakedEntity_ && !isSdfMethod(tuning.method))) return;
  // A scene loaded as meshes bakes its SDF when an SDF method is first picked.
  if (!bakedEntity_) {
    if (!bakeJob_) startRebake();
    return;
  }
  // Compared with what is being baked, else with what is drawn.
  const int resolution = bakeJob_ ? bakeJob_->settings().resolution : bakedResolution_;
  const int padding = bakeJob_ ? bakeJob_->settings().padding : bakedPadding_;
  if (tuning.resolution != resolution || tuning.padding != padding) startRebake();
}

void Viewer::startRebake() {
  hsdf::BakeSettings settings;
  settings.resolution = tuning_.resolution;
  settings.padding = tuning_.padding;
  settings.budget = bakeBudget_;
  bakeError_.clear();
  bakeJob_.reset();  // cancels a re-bake for settings that are already outdated
  bakeJob_ = std::make_unique<hsdf::BakeJob>(*bakeSource_, settings);
}

void Viewer::cancelBake() {
  if (bakeJob_) bakeJob_->cancel();
}

// Swaps the re-bake's asset into the entity (waiting for it). A failed one leaves the old asset
// and puts the tuning back to the K drawn (or to the meshes, when there is no SDF yet), so that
// the panel shows what is on screen; the reason stays in bakeError().
Status Viewer::finishBake() {
  hsdf::BakeJob::Result result = bakeJob_->wait();
  const hsdf::BakeSettings settings = bakeJob_->settings();
  bakeJob_.reset();
  if (!result) {
    const Error error = result.error().withContext(fmt::format("re-baking at resolution {}", settings.resolution));
    bakeError_ = error.message;
    if (bakedEntity_) {
      tuning_.resolution = bakedResolution_;
      tuning_.padding = bakedPadding_;
    } else {
      tuning_.method = Method::Mesh;
    }
    return error;
  }
  log::info("re-baked at resolution {}: {}", settings.resolution, describeSdfStats(sdfStats(**result)));
  if (bakedEntity_ && hiddenSdf_) hiddenSdf_->asset = std::move(*result);
  else if (bakedEntity_) registry_.get<hsdf::HermiteSdfRenderable>(*bakedEntity_).asset = std::move(*result);
  else bakedEntity_ = addSdfEntity(std::move(*result), glm::vec3(0.0f), sdfColor_ ? &*sdfColor_ : nullptr);
  bakedResolution_ = settings.resolution;
  bakedPadding_ = settings.padding;
  return {};
}

Status Viewer::waitForBake() { return bakeJob_ ? finishBake() : Status{}; }

const hsdf::SdfAsset* Viewer::sdfAsset() const {
  if (hiddenSdf_) return hiddenSdf_->asset.get();
  if (!bakedEntity_) return nullptr;
  return registry_.get<hsdf::HermiteSdfRenderable>(*bakedEntity_).asset.get();
}

// The method picks what is drawn: the SDF, or the scene's meshes (also while the first SDF of a
// mesh scene bakes, and always beside it with --side-by-side).
void Viewer::updateVisibility() {
  const bool sdfShown = isSdfMethod(tuning_.method) && bakedEntity_;
  const bool meshesShown = sideBySide_ || !sdfShown;
  if (bakedEntity_ && sdfShown == hiddenSdf_.has_value()) {
    if (sdfShown) {
      registry_.emplace<hsdf::HermiteSdfRenderable>(*bakedEntity_, std::move(*hiddenSdf_));
      hiddenSdf_.reset();
    } else {
      hiddenSdf_ = registry_.get<hsdf::HermiteSdfRenderable>(*bakedEntity_);
      registry_.remove<hsdf::HermiteSdfRenderable>(*bakedEntity_);
    }
  }
  if (meshesShown && !hiddenMeshes_.empty()) {
    for (auto& [entity, mesh] : hiddenMeshes_) registry_.emplace<render::MeshRenderable>(entity, mesh);
    hiddenMeshes_.clear();
  } else if (!meshesShown && hiddenMeshes_.empty()) {
    for (ecs::Entity entity : meshEntities_) {
      hiddenMeshes_.emplace_back(entity, registry_.get<render::MeshRenderable>(entity));
      registry_.remove<render::MeshRenderable>(entity);
    }
  }
}

void Viewer::applyTuningToScene() {
  updateVisibility();
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

Status Viewer::handleWindow(float dt, bool& drawable) {
  window_->pollEvents();
  drawable = !window_->minimized();
  if (!drawable) {
    window_->waitWhileMinimized();
    return {};
  }
  platform::InputState& input = window_->input();
  input.uiWantsMouse = ui_ && uiVisible_ && ui_->wantsMouse();
  input.uiWantsKeyboard = ui_ && uiVisible_ && ui_->wantsKeyboard();
  handleKeys(input);
  if (cameraMode_ == CameraMode::Orbit) orbit_.update(input);
  else fly_.update(input, std::min(dt, 0.1f));  // a stall does not throw the camera across the scene
  const VkExtent2D extent = window_->framebufferExtent();
  if (extent.width != swapchain_->extent().width || extent.height != swapchain_->extent().height)
    ENGINE_TRY(recreateSwapchain());
  return {};
}

// F1: panel on/off; F2: orbit/fly camera; F11: full screen. On the press, not while held.
void Viewer::handleKeys(const platform::InputState& input) {
  auto pressed = [&](int key) { return input.keys[key] && !keysDown_[key]; };
  if (!input.uiWantsKeyboard) {
    if (pressed(GLFW_KEY_F1)) uiVisible_ = !uiVisible_;
    if (pressed(GLFW_KEY_F2)) setCameraMode(cameraMode_ == CameraMode::Orbit ? CameraMode::Fly : CameraMode::Orbit);
    if (pressed(GLFW_KEY_F11)) setFullscreen(!fullscreen());
  }
  std::copy(std::begin(input.keys), std::end(input.keys), std::begin(keysDown_));
}

Status Viewer::setVsync(bool vsync) {
  if (!swapchain_ || vsync == vsync_) return {};
  // The present mode is fixed at swapchain creation: make a new one.
  context_->waitIdle();
  swapchain_.reset();
  ENGINE_TRY_ASSIGN(swapchain_, gpu::Swapchain::create(*context_, window_->surface(), window_->framebufferExtent(), vsync));
  vsync_ = vsync;
  renderer_->resize(swapchain_->extent());
  return {};
}

void Viewer::setFullscreen(bool fullscreen) {
  if (window_) window_->setFullscreen(fullscreen);
}

bool Viewer::fullscreen() const { return window_ && window_->fullscreen(); }

void Viewer::resize(std::uint32_t width, std::uint32_t height) {
  if (window_) {
    window_->setSize(int(width), int(height));
    return;
  }
  context_->waitIdle();
  renderer_->resize({width, height});
}

Status Viewer::step() {
  float dt = 1.0f / 60.0f;  // headless frames are deterministic
  if (window_) {
    const double now = nowSeconds();
    dt = float(now - lastFrameTime_);
    lastFrameTime_ = now;
    bool drawable = true;
    ENGINE_TRY(handleWindow(dt, drawable));
    if (!drawable) return {};
  }
  frameSeconds_ = dt;
  if (bakeJob_ && bakeJob_->done())
    if (Status baked = finishBake(); !baked) log::warn("{}", baked.error().message);
  applyTuningToScene();
  scene::updateWorldTransforms(registry_);
  const bool ui = ui_ && uiVisible_;
  if (ui) ui_->buildFrame(renderer_->extent(), dt);
  render::FrameSettings settings;
  settings.debugView = std::uint32_t(tuning_.debugView);
  settings.swapchain = swapchain_.get();
  settings.overlay = ui ? ui_.get() : nullptr;
  ENGINE_TRY_ASSIGN(const bool presented, renderFrame(settings));
  if (!presented) ENGINE_TRY(recreateSwapchain());
  ++frames_;
  finishStep();
  return {};
}

// A lost device or GPU memory running out (the allocator's budget included) ends the scene: an
// error (the caller exits cleanly, close() still tears down) instead of an exception through the
// program. Other driver failures still throw. The renderer cannot resume a frame that failed
// half-way (its fence is reset but nothing was submitted), so later steps return the same error
// instead of waiting forever.
Expected<bool> Viewer::renderFrame(const render::FrameSettings& settings) {
  if (!frameFailure_.empty()) return makeError("an earlier frame failed: " + frameFailure_);
  try {
    return renderer_->renderFrame(registry_, cameraView(), settings);
  } catch (const gpu::VulkanError& e) {
    if (e.result() == VK_ERROR_DEVICE_LOST) {
      deviceLost_ = true;
      frameFailure_ = fmt::format("frame {}: the Vulkan device was lost ({}); the scene cannot continue",
                                  frames_ + 1, e.what());
    } else if (e.result() == VK_ERROR_OUT_OF_DEVICE_MEMORY) {
      frameFailure_ = fmt::format("frame {}: out of GPU memory ({})", frames_ + 1, e.what());
    } else {
      throw;
    }
    return makeError(frameFailure_);
  }
}

// What the panel or a script asked for that needs the finished frame.
void Viewer::finishStep() {
  if (!pendingScreenshot_) return;
  const std::filesystem::path path = std::move(*pendingScreenshot_);
  pendingScreenshot_.reset();
  const Status written = writeScreenshot(path);
  statusLine_ = written ? "wrote " + path.string() : written.error().message;
  if (!written) log::warn("{}", written.error().message);
}

Status Viewer::writeScreenshot(const std::filesystem::path& path) {
  renderer_->finish();
  const std::vector<std::uint8_t> pixels = renderer_->readbackColor();
  const VkExtent2D extent = renderer_->extent();
  ENGINE_TRY(writePng(path, pixels, extent.width, extent.height, 4));
  std::filesystem::path sidecar = path;
  sidecar.replace_extension(".json");
  ENGINE_TRY(saveTuning(sidecar, tuning_));
  const hsdf::SdfAsset* asset = sdfAsset();
  log::info("screenshot: {} ({}x{}, {}{}{})", path.string(), extent.width, extent.height, methodName(tuning_.method),
            asset ? "; " : "", asset ? describeSdfStats(sdfStats(*asset)) : "");
  return {};
}

SdfStats sdfStats(const hsdf::SdfAsset& asset) {
  SdfStats stats;
  const std::uint64_t k = std::uint64_t(asset.cells.grid.resolution);
  stats.resolution = int(k);
  stats.cells = asset.classification.stats;
  stats.cellScalars = asset.cells.stored_scalars();
  stats.cellBytes = asset.cells.stored_bytes();
  stats.cellBytesHalf = asset.cellsHalf.stored_bytes();
  stats.trilinearScalars = k * k * k;
  stats.hermiteScalars = 4 * k * k * k;
  return stats;
}

std::string describeSdfStats(const SdfStats& s) {
  return fmt::format("K {}: cells {} crossing / {} ambiguous / {} empty; stored scalars: cells {}, trilinear {}, hermite {}",
                     s.resolution, s.cells.crossing, s.cells.ambiguous, s.cells.empty, s.cellScalars, s.trilinearScalars,
                     s.hermiteScalars);
}

Status Viewer::close() {
  if (closed_ || !context_) return {};
  closed_ = true;
  bakeJob_.reset();
  try {
    context_->waitIdle();
  } catch (const gpu::VulkanError& e) {  // a lost device has nothing left to wait for
    if (e.result() != VK_ERROR_DEVICE_LOST) throw;
    deviceLost_ = true;
  }
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
  if (deviceLost_) return makeError("the Vulkan device was lost (VK_ERROR_DEVICE_LOST); closed without it");
  return {};
}

}  // namespace samples
