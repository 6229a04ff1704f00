#include "viewer.h"

#include <algorithm>

#include <GLFW/glfw3.h>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <imgui.h>

#include "engine/core/log.h"
#include "engine/gpu/allocate_or_refuse.h"
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
  // A GPU memory budget too small for the render targets is an error, like a bad option.
  const auto initialized = gpu::allocateOrRefuse([&] { return viewer->initialize(desc); });
  if (!initialized) return makeError(fmt::format("creating the renderer: out of GPU memory ({})", initialized.error().message));
  ENGINE_TRY(*initialized);
  return viewer;
}

// A destructor that throws terminates the program: what close() reports is logged instead.
Viewer::~Viewer() {
  try {
    if (const Status closed = close(); !closed) log::error("closing the viewer: {}", closed.error().message);
  } catch (const std::exception& e) {
    log::error("closing the viewer: {}", e.what());
  }
}

Status Viewer::initialize(const ViewerDesc& desc) {
  gpu::ContextDesc contextDesc;
  contextDesc.applicationName = kProgramName;
  contextDesc.engineName = std::string(kProgramName) + " engine";
  contextDesc.device = desc.device;
  contextDesc.shaderStatistics = desc.shaderStatistics;
  contextDesc.pipelineCacheFile = desc.pipelineCacheFile;
  if (desc.validation) contextDesc.validation = true;
  if (!desc.headless) {
    ENGINE_TRY_ASSIGN(window_, ViewerWindow::create(desc.title, desc.width, desc.height));
    contextDesc.instanceExtensions = platform::Window::requiredInstanceExtensions();
    contextDesc.swapchain = true;
  }
  bakes_.setBudget(desc.bakeBudget);
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
  ENGINE_TRY(hsdf::addSceneFeatures(*renderer_, *pool_));
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
  compare_.createOverlay(*context_, renderer_->desc().framesInFlight);
  if (window_) window_->startFrameClock();
  return {};
}

void Viewer::setTuning(const TuningState& tuning) {
  tuning_ = tuning;
  if (sceneObjects_.loaded() && !sceneObjects_.baked()) {
    // The first SDF method after a mesh method's load. A failed bake keeps the meshes drawn and
    // the method with them (as a failed re-bake keeps its K); the panel shows why.
    if (Status baked = sceneObjects_.bakeIfWanted(meshEntities_); !baked) {
      log::error("{}", baked.error().message);
      bakes_.setError(baked.error().message);
      tuning_.method = Method::Mesh;
    } else if (sceneObjects_.baked()) {
      bakes_.setError({});
    }
  } else if (sceneObjects_.loaded() && bakeKey(tuning_) != bakes_.baked()) {
    // The reason stays in bakeError() (the panel shows it) as for one baked object.
    if (Status rebaked = sceneObjects_.rebake(); !rebaked) {
      log::error("{}", rebaked.error().message);
      bakes_.setError(rebaked.error().message);
    } else {
      bakes_.setError({});
    }
  }
  updateCompareBake();
  bakes_.followTuning();
  warnIfCellsOnly();
}

Status Viewer::checkTuning(const TuningState& t) const {
  if (t.method == Method::Mesh && !hasMeshes())
    return makeError("method mesh: this scene has no triangles (a .hsdf file, an analytic shape); draw it with cells, "
                     "trilinear or hermite");
  if (!canRebake() && bakeKey(t) != bakeKey(tuning_))
    return makeError(fmt::format("resolution {} / padding {} / shell {:g}: a .hsdf file is drawn as it was baked (K = "
                                 "{}); there is no source to bake again",
                                 t.resolution, t.padding, t.shellThickness, tuning_.resolution));
  if (!canRebake() && t.lod)
    return makeError("lod: levels of detail bake the source again at K/2, K/4, ...; a .hsdf file has no source");
  // SdfObjects reads them when the scene loads and keeps its nodes' choice (a script changing them
  // was taken and drew nothing new).
  if (t.nodeDraw != tuning_.nodeDraw || t.triangleNodes != tuning_.triangleNodes)
    return makeError(sceneObjects_.loaded()
                         ? "node_draw / triangle_nodes: chosen per node when the scene loads (--node-draw, "
                           "--triangle-nodes); load the scene again to change them"
                         : "node_draw / triangle_nodes: choose per node of a scene loaded with --objects");
  if (sceneObjects_.loaded() && comparing(t))
    return makeError("split / difference: the comparison draws one baked SDF; a scene of separate objects has one "
                     "per mesh");
  return {};
}

// A tracer asked for where no bake can give it the dense field (a cells-only .hsdf: no source to
// re-bake) draws the cells (drawableMethod); said once per such request, in the log and the panel.
void Viewer::warnIfCellsOnly() {
  const hsdf::SdfAsset* asset = bakes_.asset();
  const bool cellsOnly = asset && asset->field.samples.empty() && !bakes_.source();
  const bool wanted =
      needsDenseField(tuning_.method) || (comparing(tuning_) && needsDenseField(tuning_.compareMethod));
  if (cellsOnly && wanted && !warnedCellsOnly_) {
    const std::string message = fmt::format("'{}' holds only cells: the sphere tracers need the dense field (bake "
                                            "without --cells); its cells are drawn instead", asset->name);
    log::warn("{}", message);
    bakes_.setError(message);
  }
  warnedCellsOnly_ = cellsOnly && wanted;
}

// The compared side shares the asset baked at K (level 0 when levels of detail draw another).
void Viewer::updateCompareBake() {
  compare_.updateBake(tuning_, bakes_.source(), {bakes_.bakedAsset(), bakes_.baked()},
                      bakes_.budget());
}

int Viewer::resolutionDrawn() const {
  const hsdf::SdfAsset* drawn = sdfAsset();  // with levels of detail, the level the view picked
  return drawn && bakes_.entity() ? int(drawn->cells.grid.resolution) : bakes_.resolution();
}

int Viewer::compareResolutionDrawn() const {
  return compare_.resolutionDrawn(tuning_, bakes_.entity() ? bakes_.resolution() : 0);
}

void Viewer::cancelBake() {
  bakes_.cancel();
  compare_.cancelBake();
}

Status Viewer::waitForBake() {
  const Status main = bakes_.job() ? bakes_.finish() : Status{};
  if (compare_.bakeJob()) compare_.finishBake();
  updateCompareBake();  // e.g. the compared side can share the new main asset
  updateLevelsOfDetail(true);
  return main;
}

const hsdf::SdfAsset* Viewer::sdfAsset() const { return bakes_.asset(); }

// The method picks what is drawn: the SDF, or the scene's meshes (also while the first SDF of a
// mesh scene bakes, and always beside it with --side-by-side).
void Viewer::updateVisibility(Method method, bool meshes) {
  const bool sdfShown = isSdfMethod(method) && (bakes_.entity() || !sceneObjects_.entities().empty());
  const bool meshesShown = meshes && (sideBySide_ || !sdfShown);
  sceneObjects_.setShown(sdfShown);
  bakes_.setShown(sdfShown);
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
  hsdf::SphereTraceFeature::Settings& tracers = renderer_->feature<hsdf::SphereTraceFeature>()->settings();
  applyTuning(tuning_, cells, tracers);
  if (!window_) applyCapturedFrames(cells, tracers);  // headless frames are captured
}

// Levels of detail (TuningState::lod): the scene objects' or the SDF entity's. `wait` (waitForBake)
// finishes every level and leaves the choice to the next frame.
void Viewer::updateLevelsOfDetail(bool wait) {
  const bool levels = sceneObjects_.loaded() ? sceneObjects_.updateLevels() : bakes_.updateLevels(wait);
  if (levels && !wait) hsdf::selectSdfLevels(registry_, cameraView(), renderer_->extent().height);
}

// The scene as `tuning` draws it, the SDF entity showing `asset`: a view region's override.
void Viewer::showState(const TuningState& tuning, const std::shared_ptr<const hsdf::SdfAsset>& asset) {
  if (hsdf::HermiteSdfRenderable* r = bakes_.renderable(); r && asset) r->asset = asset;
  updateVisibility(tuning.method);
  registry_.view<hsdf::HermiteSdfRenderable>().each(
      [&tuning](ecs::Entity, hsdf::HermiteSdfRenderable& renderable) { applyTuning(tuning, renderable); });
}

std::vector<render::ViewRegion> Viewer::splitRegions(const std::shared_ptr<const hsdf::SdfAsset>& main) {
  return compare_.splitRegions(tuning_, renderer_->extent(), main, bakes_.bakedAsset());
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
  // Said as it went: a reload in which a feature kept its old pipelines is a warning naming them (it
  // was "shaders reloaded" whatever failed).
  const auto kept = std::count_if(results.begin(), results.end(), [](const auto& r) { return !r.status.ok(); });
  if (kept == 0)
    log::info("shaders reloaded from {}:\n{}", gpu::shaderDirectory().string(), report);
  else
    log::warn("shaders from {}: {} of {} features kept their old pipelines:\n{}", gpu::shaderDirectory().string(),
              kept, results.size(), report);
  return results;
}

bool Viewer::shouldClose() const { return window_ && window_->shouldClose(); }

// Input of a drawable windowed frame: the UI's capture of mouse and keyboard, keys, the camera.
void Viewer::handleInput(float dt) {
  platform::InputState& input = window_->window().input();
  input.uiWantsMouse = ui_ && uiVisible_ && ui_->wantsMouse();
  input.uiWantsKeyboard = ui_ && uiVisible_ && ui_->wantsKeyboard();
  handleKeys(input);
  moveCamera(input, dt);
}

// F1: panel on/off; F2: orbit/fly camera; F11: full screen. On the press, not while held; a tap
// shorter than a frame is a press too (the window's press edges come from its key events).
void Viewer::handleKeys(const platform::InputState& input) {
  auto pressed = [&](int key) { return input.keysPressed[key]; };
  if (!input.uiWantsKeyboard) {
    if (pressed(GLFW_KEY_F1)) uiVisible_ = !uiVisible_;
    if (pressed(GLFW_KEY_F2)) setCameraMode(cameraMode_ == CameraMode::Orbit ? CameraMode::Fly : CameraMode::Orbit);
    if (pressed(GLFW_KEY_F11)) setFullscreen(!fullscreen());
    if (pressed(GLFW_KEY_F5)) rebuildAndReloadShaders();
  }
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
  // A cancelled bake is finished (waited for: the worker stops at its next check) on the next
  // step, before the tuning can start another: a re-bake started first would replace the
  // cancelled job without reporting it, and the tuning would not name what is drawn.
  if (bakes_.job() && bakes_.job()->finishable()) {
    if (Status baked = bakes_.finish(); !baked) log::warn("{}", baked.error().message);
    updateCompareBake();
  }
  if (compare_.bakeJob() && compare_.bakeJob()->finishable()) compare_.finishBake();
  applyTuningToScene();
  if (animation_) animation_->step(registry_, dt);
  scene::updateWorldTransforms(registry_);
  updateLevelsOfDetail(false);
  const bool ui = ui_ && uiVisible_;
  render::FrameSettings settings;
  settings.debugView = std::uint32_t(tuning_.debugView);
  settings.swapchain = window_ ? &window_->swapchain() : nullptr;
  settings.overlay = ui ? ui_.get() : nullptr;
  // The comparison: the main asset is put back after the frame (regions swap it in and out).
  hsdf::HermiteSdfRenderable* sdf = bakes_.renderable();
  const std::shared_ptr<const hsdf::SdfAsset> main = sdf ? sdf->asset : nullptr;
  compare_.clearDifference();
  if (tuning_.difference && main && isSdfMethod(tuning_.method)) {
    ENGINE_TRY(compare_.renderDifference(tuning_, main, bakes_.bakedAsset(), registry_, *renderer_, cameraView()));
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
  const std::optional<std::string> restored = bakes_.restoreRefused(*renderer_);
  Status dropped = droppedObjectsError(frames_);
  if (restored && !dropped.ok()) return makeError(dropped.error().message + "; " + *restored);
  return dropped;
}

Expected<Viewer::FrameWork> Viewer::countWork() {
  render::FrameSettings settings;
  settings.debugView = std::uint32_t(tuning_.debugView);
  settings.countWork = true;
  hsdf::HermiteSdfRenderable* sdf = bakes_.renderable();
  const std::shared_ptr<const hsdf::SdfAsset> main = sdf ? sdf->asset : nullptr;
  if (tuning_.split != SplitMode::Off && main && !tuning_.difference) settings.regions = splitRegions(main);
  const Expected<bool> rendered = renderFrame(settings);
  if (!settings.regions.empty()) showState(tuning_, main);
  if (!rendered) return rendered.error();
  FrameWork work;
  for (const std::uint32_t count : renderer_->readbackWorkCounters()) work.evaluations += count;
  const shader::WorkTotals totals = renderer_->readbackWorkTotals();
  work.raysOutOfSteps = totals.raysOutOfSteps;
  work.tileEntriesWalked = totals.tileEntriesWalked;
  work.tileEntriesTested = totals.tileEntriesTested;
  work.tileMaskWordsRead = totals.tileMaskWordsRead;
  const auto* cells = renderer_->feature<hsdf::HermiteCellFeature>();
  if (cells->stats().tiles) {
    const shader::CellTileTotals tiles = cells->tileTotals();
    work.tilesDrawn = tiles.instanceCount;
    work.tileEntries = tiles.entriesNeeded;
    work.tilesOverflowed = tiles.boxDrawCount != 0;
  }
  return work;
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
                             .resolution = resolutionDrawn(),
                             .compareResolution = compareResolutionDrawn(),
                             .difference = difference ? &*difference : nullptr});
}

Status Viewer::close() {
  if (closed_ || !context_) return {};
  closed_ = true;
  bakes_.stop();
  // The teardown goes on whatever the wait says: stopping half-way would leave the rest to the
  // members' destructors, in declaration order, not dependency order.
  std::string waitFailed;
  try {
    context_->waitIdle();
  } catch (const gpu::VulkanError& e) {  // a lost device has nothing left to wait for
    if (e.result() == VK_ERROR_DEVICE_LOST)
      deviceLost_ = true;
    else
      waitFailed = e.what();
  }
  compare_.release();
  ui_.reset();
  renderer_.reset();
  if (window_) window_->destroySwapchain(*context_);
  registry_.clear();
  pool_.reset();
  // Objects never destroyed are reported while the device is destroyed: counted too.
  const std::uint64_t othersBefore =
      gpu::Context::processValidationMessageCount() - context_->validationMessageCount();
  context_.reset();
  window_.reset();
  const std::uint64_t messages = gpu::Context::processValidationMessageCount() - othersBefore;
  if (messages > 0) return makeError(std::to_string(messages) + " Vulkan validation message(s); see the log above");
  if (deviceLost_) return makeError("the Vulkan device was lost (VK_ERROR_DEVICE_LOST); closed without it");
  if (!waitFailed.empty()) return makeError("waiting for the GPU before closing: " + waitFailed);
  return {};
}

}  // namespace samples
