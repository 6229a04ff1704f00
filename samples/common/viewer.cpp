#include "viewer.h"

#include <algorithm>

#include <GLFW/glfw3.h>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <imgui.h>

#include "engine/core/log.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/swapchain.h"
#include "engine/gpu/vk_check.h"
#include "engine/platform/window.h"
#include "engine/render/components.h"
#include "engine/render/mesh_feature.h"
#include "engine/scene/transform.h"
#include "engine/ui/ui_layer.h"
#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/render/features.h"
#include "hermite_sdf/render/lod.h"
#include "hermite_sdf/render/sphere_trace_feature.h"
#include "shader_build.h"
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
  contextDesc.applicationName = kProgramName;
  contextDesc.engineName = std::string(kProgramName) + " engine";
  contextDesc.device = desc.device;
  if (desc.validation) contextDesc.validation = true;
  if (!desc.headless) {
    ENGINE_TRY_ASSIGN(window_, ViewerWindow::create(desc.title, desc.width, desc.height));
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
    ENGINE_TRY(window_->createSwapchain(*context_));
    extent = window_->swapchain().extent();
  }
  renderer_ = std::make_unique<render::Renderer>(*context_, render::RendererDesc{}, extent);
  ENGINE_TRY(renderer_->addFeature(std::make_unique<render::MeshFeature>(*pool_)));
  ENGINE_TRY(hsdf::addRenderFeatures(*renderer_));
  if (window_ || desc.headlessUi) {
    ENGINE_TRY_ASSIGN(ui_, ui::UiLayer::create(*context_, renderer_->desc().formats.color,
                                               renderer_->desc().framesInFlight,
                                               window_ ? &window_->window() : nullptr));
    ui_->setWindowTitle(kProgramName);
    if (!desc.uiIniFile.empty()) ui_->setIniFile(desc.uiIniFile.string());
    panel_ = std::make_unique<TuningPanel>(*this);
    ui_->addPanel("tuning", [this] { panel_->draw(); });
    ui_->addFeaturePanels(*renderer_);
  }
  compare_.initialize(*context_, renderer_->desc().framesInFlight,
                      [this](const TuningState& tuning, const std::shared_ptr<const hsdf::SdfAsset>& asset) {
                        showState(tuning, asset);
                      });
  if (window_) window_->startFrameClock();
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
  if (objectScene_ && (tuning_.resolution != bakedResolution_ || tuning_.padding != bakedPadding_)) {
    if (Status rebaked = rebakeSceneObjects(); !rebaked) log::error("{}", rebaked.error().message);
  }
  updateCompareBake();
  if (!bakeSource_ || (!bakedEntity_ && !isSdfMethod(tuning.method) && !comparing(tuning))) return;
  // A scene loaded as meshes bakes its SDF when an SDF method (or a comparison) is first picked.
  if (!bakedEntity_) {
    if (!bakeJob_) startRebake();
    return;
  }
  // Compared with what is being baked, else with what is drawn.
  const int resolution = bakeJob_ ? bakeJob_->settings().resolution : bakedResolution_;
  const int padding = bakeJob_ ? bakeJob_->settings().padding : bakedPadding_;
  // A sparse bake (the cells past K = 256) has no dense field: a dense tracer needs a re-bake.
  const hsdf::SdfAsset* drawn = sdfAsset();
  const bool sparse = bakeJob_ ? bakeJob_->settings().band == hsdf::BakeBand::Sparse
                               : drawn && drawn->field.samples.empty();
  const bool needsDense = isSdfMethod(tuning.method) && !drawsCells(tuning.method);
  if (tuning.resolution != resolution || tuning.padding != padding || (sparse && needsDense)) startRebake();
}

// The compared side shares the asset baked at K (level 0 when levels of detail draw another).
void Viewer::updateCompareBake() {
  const hsdf::HermiteSdfRenderable* r = sdfRenderable();
  const hsdf::HermiteSdfLod* lod = bakedEntity_ ? registry_.tryGet<hsdf::HermiteSdfLod>(*bakedEntity_) : nullptr;
  auto baked = lod && !lod->levels.empty() ? lod->levels.front() : r ? r->asset : nullptr;
  compare_.updateBake(tuning_, bakeSource_ ? &*bakeSource_ : nullptr, {std::move(baked), bakedResolution_, bakedPadding_},
                      bakeBudget_);
}

int Viewer::compareResolutionDrawn() const {
  return compare_.resolutionDrawn(tuning_, bakedEntity_ ? bakedResolution_ : 0);
}

void Viewer::startRebake() {
  hsdf::BakeSettings settings;
  settings.resolution = tuning_.resolution;
  settings.padding = tuning_.padding;
  settings.band = bakeBandFor(tuning_.method, tuning_.resolution);
  settings.budget = bakeBudget_;
  bakeError_.clear();
  bakeJob_.reset();  // cancels a re-bake for settings that are already outdated
  bakeJob_ = std::make_unique<hsdf::BakeJob>(*bakeSource_, settings);
}

void Viewer::cancelBake() {
  if (bakeJob_) bakeJob_->cancel();
  compare_.cancelBake();
  if (levelJob_) levelJob_->cancel();
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
  if (bakedEntity_) {
    hsdf::HermiteSdfRenderable& sdf = hiddenSdf_ ? *hiddenSdf_ : registry_.get<hsdf::HermiteSdfRenderable>(*bakedEntity_);
    // With levels of detail the renderable holds the level drawn; the bake replaced level 0.
    const hsdf::HermiteSdfLod* lod = registry_.tryGet<hsdf::HermiteSdfLod>(*bakedEntity_);
    replaced_ = {lod && !lod->levels.empty() ? lod->levels.front() : sdf.asset, bakedResolution_, bakedPadding_};
    sdf.asset = std::move(*result);
  } else {
    bakedEntity_ = addSdfEntity(std::move(*result), glm::vec3(0.0f), sdfColor_ ? &*sdfColor_ : nullptr);
  }
  bakedResolution_ = settings.resolution;
  bakedPadding_ = settings.padding;
  return {};
}

Status Viewer::waitForBake() {
  const Status main = bakeJob_ ? finishBake() : Status{};
  if (compare_.bakeJob()) compare_.finishBake();
  updateCompareBake();  // e.g. the compared side can share the new main asset
  updateLevelsOfDetail(true);
  return main;
}

hsdf::HermiteSdfRenderable* Viewer::sdfRenderable() {
  if (hiddenSdf_) return &*hiddenSdf_;
  if (!bakedEntity_) return nullptr;
  return &registry_.get<hsdf::HermiteSdfRenderable>(*bakedEntity_);
}

const hsdf::SdfAsset* Viewer::sdfAsset() const {
  if (hiddenSdf_) return hiddenSdf_->asset.get();
  if (!bakedEntity_) return nullptr;
  return registry_.get<hsdf::HermiteSdfRenderable>(*bakedEntity_).asset.get();
}

// The method picks what is drawn: the SDF, or the scene's meshes (also while the first SDF of a
// mesh scene bakes, and always beside it with --side-by-side).
void Viewer::updateVisibility(Method method, bool meshes) {
  const bool sdfShown = isSdfMethod(method) && (bakedEntity_ || !objectEntities_.empty());
  const bool meshesShown = meshes && (sideBySide_ || !sdfShown);
  updateObjectVisibility(sdfShown);
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
  updateVisibility(tuning_.method);
  registry_.view<hsdf::HermiteSdfRenderable>().each(
      [this](ecs::Entity, hsdf::HermiteSdfRenderable& renderable) { applyTuning(tuning_, renderable); });
  hsdf::HermiteCellFeature::Settings& cells = renderer_->feature<hsdf::HermiteCellFeature>()->settings();
  cells.frontToBack = tuning_.frontToBack;
  cells.maxRunLength = tuning_.maxRunLength;
  cells.cullBricks = tuning_.cullBricks;
  cells.cullCells = tuning_.cullCells;
  using CellThinBoxes = hsdf::HermiteCellFeature::ThinBoxes;
  cells.thinBoxes = tuning_.thinBoxes == ThinBoxes::On    ? CellThinBoxes::On
                    : tuning_.thinBoxes == ThinBoxes::Off ? CellThinBoxes::Off
                                                          : CellThinBoxes::Auto;
  using CellEarlyDepth = hsdf::HermiteCellFeature::EarlyDepth;
  cells.earlyDepth = tuning_.earlyDepth == EarlyDepth::On    ? CellEarlyDepth::On
                     : tuning_.earlyDepth == EarlyDepth::Off ? CellEarlyDepth::Off
                                                             : CellEarlyDepth::Auto;
  hsdf::SphereTraceFeature::Settings& tracers = renderer_->feature<hsdf::SphereTraceFeature>()->settings();
  tracers.epsilon = tuning_.traceEpsilon;
  tracers.maxSteps = tuning_.traceMaxSteps;
  tracers.centralDifferenceStep = tuning_.centralDifferenceStep;
}

// Levels of detail (TuningState::lod): the baked entity carries an hsdf::HermiteSdfLod whose level 0
// is the asset baked at K. A renderable holding none of the levels has a new bake (re-bake, refused
// bake put back): its coarser levels are baked then, from the same source, with its band, one
// hsdf::BakeJob per level on a worker thread (finer first), so that the frame never waits for them;
// the module's system picks among the levels ready so far, from the camera of this frame. Off: the
// entity draws level 0 again. `wait` (waitForBake) finishes every level and leaves the choice to
// the next frame.
void Viewer::updateLevelsOfDetail(bool wait) {
  if (objectScene_) return updateObjectLevels(!wait);
  hsdf::HermiteSdfRenderable* renderable = sdfRenderable();
  if (!renderable) return;
  hsdf::HermiteSdfLod* lod = registry_.tryGet<hsdf::HermiteSdfLod>(*bakedEntity_);
  const bool holdsLevel =
      lod && std::find(lod->levels.begin(), lod->levels.end(), renderable->asset) != lod->levels.end();
  if (!tuning_.lod || !bakeSource_) {
    levelJob_.reset();
    // A level goes back to level 0; a new bake in the renderable stays.
    if (holdsLevel) renderable->asset = lod->levels.front();
    if (lod) registry_.remove<hsdf::HermiteSdfLod>(*bakedEntity_);
    return;
  }
  if (!holdsLevel) startLevelBakes(renderable->asset);
  if (Status baked = finishLevelBakes(wait); !baked) {
    bakeError_ = baked.error().message;
    log::warn("{} (levels of detail turned off)", bakeError_);
    tuning_.lod = false;
    return;
  }
  registry_.get<hsdf::HermiteSdfLod>(*bakedEntity_).pixelsPerCell = tuning_.lodPixelsPerCell;
  if (!wait) hsdf::selectSdfLevels(registry_, cameraView(), renderer_->extent().height);
}

// New levels with `finest` (baked at bakedResolution_) as level 0, the coarser ones to come.
void Viewer::startLevelBakes(std::shared_ptr<const hsdf::SdfAsset> finest) {
  levelJob_.reset();  // a level of the old level 0 is outdated
  hsdf::BakeSettings settings;
  settings.resolution = bakedResolution_;
  settings.padding = bakedPadding_;
  settings.band = finest->field.samples.empty() ? hsdf::BakeBand::Sparse : hsdf::BakeBand::Dense;
  settings.budget = bakeBudget_;
  hsdf::HermiteSdfLod lod;
  lod.levels = {std::move(finest)};
  registry_.emplaceOrReplace<hsdf::HermiteSdfLod>(*bakedEntity_, std::move(lod));
  startNextLevelBake(settings);
}

void Viewer::startNextLevelBake(const hsdf::BakeSettings& previous) {
  if (const std::optional<hsdf::BakeSettings> next = hsdf::coarserLodLevel(previous))
    levelJob_ = std::make_unique<hsdf::BakeJob>(*bakeSource_, *next);
  else
    log::info("levels of detail: {} levels from K = {}", registry_.get<hsdf::HermiteSdfLod>(*bakedEntity_).levels.size(),
              bakedResolution_);
}

// Adds the levels whose bakes are done (all of them when `wait`), starting the next one each time.
Status Viewer::finishLevelBakes(bool wait) {
  while (levelJob_ && (wait || levelJob_->done())) {
    hsdf::BakeJob::Result result = levelJob_->wait();
    const hsdf::BakeSettings settings = levelJob_->settings();
    levelJob_.reset();
    if (!result) return result.error().withContext(fmt::format("levels of detail: level K = {}", settings.resolution));
    registry_.get<hsdf::HermiteSdfLod>(*bakedEntity_).levels.push_back(std::move(*result));
    startNextLevelBake(settings);
  }
  return {};
}

// The scene as `tuning` draws it, the SDF entity showing `asset`: a view region's override.
void Viewer::showState(const TuningState& tuning, const std::shared_ptr<const hsdf::SdfAsset>& asset) {
  if (hsdf::HermiteSdfRenderable* r = sdfRenderable(); r && asset) r->asset = asset;
  updateVisibility(tuning.method);
  registry_.view<hsdf::HermiteSdfRenderable>().each(
      [&tuning](ecs::Entity, hsdf::HermiteSdfRenderable& renderable) { applyTuning(tuning, renderable); });
}

std::vector<render::ViewRegion> Viewer::splitRegions(const std::shared_ptr<const hsdf::SdfAsset>& main) {
  return compare_.splitRegions(tuning_, renderer_->extent(), main);
}

void Viewer::rebuildAndReloadShaders() {
  const Expected<std::string> built = rebuildShaders(thisProgramsShaderBuild());
  if (!built) {
    shaderReloadReport_ = built.error().message + "\n(nothing reloaded: the old pipelines keep drawing)";
    log::warn("{}", shaderReloadReport_);
    return;
  }
  reloadShaders();
  shaderReloadReport_ = *built + "\n" + shaderReloadReport_;
}

std::vector<render::Renderer::ShaderReload> Viewer::reloadShaders() {
  std::vector<render::Renderer::ShaderReload> results = renderer_->reloadShaders();
  std::string report;
  for (const auto& r : results)
    report += fmt::format("{}{}: {}", report.empty() ? "" : "\n", r.feature, r.status ? "reloaded" : r.status.error().message);
  shaderReloadReport_ = report;
  log::info("shaders reloaded from {}:\n{}", gpu::shaderDirectory().string(), report);
  return results;
}

bool Viewer::shouldClose() const { return window_ && window_->shouldClose(); }

// Input of a drawable windowed frame: the UI's capture of mouse and keyboard, keys, the camera.
void Viewer::handleInput(float dt) {
  platform::InputState& input = window_->window().input();
  input.uiWantsMouse = ui_ && uiVisible_ && ui_->wantsMouse();
  input.uiWantsKeyboard = ui_ && uiVisible_ && ui_->wantsKeyboard();
  handleKeys(input);
  if (cameraMode_ == CameraMode::Orbit) orbit_.update(input);
  else fly_.update(input, std::min(dt, 0.1f));  // a stall does not throw the camera across the scene
}

// F1: panel on/off; F2: orbit/fly camera; F11: full screen. On the press, not while held.
void Viewer::handleKeys(const platform::InputState& input) {
  auto pressed = [&](int key) { return input.keys[key] && !keysDown_[key]; };
  if (!input.uiWantsKeyboard) {
    if (pressed(GLFW_KEY_F1)) uiVisible_ = !uiVisible_;
    if (pressed(GLFW_KEY_F2)) setCameraMode(cameraMode_ == CameraMode::Orbit ? CameraMode::Fly : CameraMode::Orbit);
    if (pressed(GLFW_KEY_F11)) setFullscreen(!fullscreen());
    if (pressed(GLFW_KEY_F5)) rebuildAndReloadShaders();
  }
  std::copy(std::begin(input.keys), std::end(input.keys), std::begin(keysDown_));
}

Status Viewer::setVsync(bool vsync) { return window_ ? window_->setVsync(vsync, *renderer_) : Status{}; }

bool Viewer::vsync() const { return !window_ || window_->vsync(); }

Status Viewer::setMinimized(bool minimized) {
  if (!window_) return makeError("minimise/restore: no window (headless)");
  return window_->setMinimized(minimized);
}

void Viewer::setFullscreen(bool fullscreen) {
  if (window_) window_->setFullscreen(fullscreen);
}

bool Viewer::fullscreen() const { return window_ && window_->fullscreen(); }

std::uint64_t Viewer::swapchainRecreations() const { return window_ ? window_->swapchainRecreations() : 0; }

void Viewer::resize(std::uint32_t width, std::uint32_t height) {
  if (window_) return window_->requestSize(width, height);
  context_->waitIdle();
  renderer_->resize({width, height});
}

Status Viewer::waitForWindowSize() { return window_ ? window_->waitForSize() : Status{}; }

Status Viewer::step() {
  float dt = 1.0f / 60.0f;  // headless frames are deterministic
  if (window_) {
    dt = window_->secondsSinceLastFrame();
    if (!window_->pollEvents()) return {};
    handleInput(dt);
    ENGINE_TRY(window_->fitSwapchain(*renderer_));
  }
  frameSeconds_ = dt;
  if (bakeJob_ && bakeJob_->done()) {
    if (Status baked = finishBake(); !baked) log::warn("{}", baked.error().message);
    updateCompareBake();
  }
  if (compare_.bakeJob() && compare_.bakeJob()->done()) compare_.finishBake();
  applyTuningToScene();
  scene::updateWorldTransforms(registry_);
  updateLevelsOfDetail(false);
  const bool ui = ui_ && uiVisible_;
  render::FrameSettings settings;
  settings.debugView = std::uint32_t(tuning_.debugView);
  settings.swapchain = window_ ? &window_->swapchain() : nullptr;
  settings.overlay = ui ? ui_.get() : nullptr;
  // The comparison: the main asset is put back after the frame (regions swap it in and out).
  hsdf::HermiteSdfRenderable* sdf = sdfRenderable();
  const std::shared_ptr<const hsdf::SdfAsset> main = sdf ? sdf->asset : nullptr;
  compare_.clearDifference();
  if (tuning_.difference && main && isSdfMethod(tuning_.method)) {
    ENGINE_TRY(compare_.renderDifference(tuning_, main, registry_, *renderer_, cameraView()));
    settings.overlay = compare_.overlay(settings.overlay);
  } else if (tuning_.split != SplitMode::Off && main) {
    settings.regions = splitRegions(main);
  }
  if (ui) ui_->buildFrame(renderer_->extent(), dt);
  ENGINE_TRY_ASSIGN(const bool presented, renderFrame(settings));
  if (!settings.regions.empty()) showState(tuning_, main);
  if (!presented) {
    log::debug("swapchain out of date or suboptimal: recreating it");
    ENGINE_TRY(window_->recreateSwapchain(*renderer_));
  }
  ++frames_;
  finishStep();
  const std::optional<std::string> restored = restoreRefusedBake();
  Status dropped = droppedObjectsError(frames_);
  if (restored && !dropped.ok()) return makeError(dropped.error().message + "; " + *restored);
  return dropped;
}

Expected<Viewer::FrameWork> Viewer::countWork() {
  render::FrameSettings settings;
  settings.debugView = std::uint32_t(tuning_.debugView);
  settings.countWork = true;
  hsdf::HermiteSdfRenderable* sdf = sdfRenderable();
  const std::shared_ptr<const hsdf::SdfAsset> main = sdf ? sdf->asset : nullptr;
  if (tuning_.split != SplitMode::Off && main && !tuning_.difference) settings.regions = splitRegions(main);
  const Expected<bool> rendered = renderFrame(settings);
  if (!settings.regions.empty()) showState(tuning_, main);
  if (!rendered) return rendered.error();
  FrameWork work;
  for (const std::uint32_t count : renderer_->readbackWorkCounters()) work.evaluations += count;
  work.raysOutOfSteps = renderer_->readbackWorkTotals().raysOutOfSteps;
  return work;
}

// A re-baked field the GPU could not take (a feature refused its upload: out of GPU memory) is
// swapped back for the field it replaced, which the features still hold (and drew already in the
// frame that found out, in place of the refused one): the component and the tuning name the K on
// screen again. Checked on the first frame after the swap; the replaced field is released then.
std::optional<std::string> Viewer::restoreRefusedBake() {
  const ReplacedField replaced = std::exchange(replaced_, {});
  hsdf::HermiteSdfRenderable* sdf = sdfRenderable();
  if (!replaced.asset || !sdf || !sdf->asset) return std::nullopt;
  const std::uint64_t id = sdf->asset->id;
  if (!renderer_->feature<hsdf::HermiteCellFeature>()->refused(id) &&
      !renderer_->feature<hsdf::SphereTraceFeature>()->refused(id))
    return std::nullopt;
  bakeError_ = fmt::format("re-baking at resolution {}: the new field does not fit in GPU memory; resolution {} stays "
                           "drawn",
                           bakedResolution_, replaced.resolution);
  log::warn("{}", bakeError_);
  sdf->asset = replaced.asset;
  bakedResolution_ = tuning_.resolution = replaced.resolution;
  bakedPadding_ = tuning_.padding = replaced.padding;
  return bakeError_;
}

// A lost device ends the scene: an error (the caller exits cleanly, close() still tears down)
// instead of an exception through the program, and later steps return the same error. GPU memory
// running out (the allocator's budget included) while a frame is recorded fails that frame only:
// the renderer submits nothing of it and the next step draws again. Other driver failures throw.
Expected<bool> Viewer::renderFrame(const render::FrameSettings& settings) {
  if (!frameFailure_.empty()) return makeError("an earlier frame failed: " + frameFailure_);
  try {
    return renderer_->renderFrame(registry_, cameraView(), settings);
  } catch (const gpu::VulkanError& e) {
    if (e.result() == VK_ERROR_DEVICE_LOST) {
      deviceLost_ = true;
      frameFailure_ = fmt::format("frame {}: the Vulkan device was lost ({}); the scene cannot continue",
                                  frames_ + 1, e.what());
      return makeError(frameFailure_);
    }
    if (e.result() == VK_ERROR_OUT_OF_DEVICE_MEMORY)
      return makeError(fmt::format("frame {}: out of GPU memory ({}); the frame was skipped", frames_ + 1, e.what()));
    throw;
  }
}

// Objects the features could not draw in the frame just rendered (the rest of it was drawn).
Status Viewer::droppedObjectsError(std::uint64_t frame) {
  const std::vector<std::string> dropped = renderer_->takeDroppedObjects();
  if (dropped.empty()) return {};
  return makeError(fmt::format("frame {}: {}", frame, fmt::join(dropped, "; ")));
}

// What the panel or a script asked for that needs the finished frame.
void Viewer::finishStep() {
  screenshots_.writeRequested([this](const std::filesystem::path& path) { return writeScreenshot(path); });
}

Status Viewer::writeScreenshot(const std::filesystem::path& path) {
  const std::optional<NormalDifference>& difference = compare_.difference();
  return Screenshots::write(*renderer_, path,
                            {.tuning = tuning_,
                             .asset = sdfAsset(),
                             .resolution = bakedResolution_,
                             .compareResolution = compareResolutionDrawn(),
                             .difference = difference ? &*difference : nullptr});
}

Status Viewer::close() {
  if (closed_ || !context_) return {};
  closed_ = true;
  bakeJob_.reset();
  levelJob_.reset();
  try {
    context_->waitIdle();
  } catch (const gpu::VulkanError& e) {  // a lost device has nothing left to wait for
    if (e.result() != VK_ERROR_DEVICE_LOST) throw;
    deviceLost_ = true;
  }
  compare_.release();
  ui_.reset();
  renderer_.reset();
  if (window_) window_->destroySwapchain(*context_);
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
