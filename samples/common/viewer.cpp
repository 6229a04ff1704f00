#include "viewer.h"

#include <algorithm>
#include <chrono>

#include <GLFW/glfw3.h>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <imgui.h>

#include "engine/core/image_io.h"
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

double nowSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// How long a script waits for the window system to apply a request (minimise, restore, resize).
constexpr double kWindowSystemSeconds = 2.0;

// Handles window events until `done()` or kWindowSystemSeconds have passed; whether it is done.
template <class Done>
bool waitForWindowSystem(platform::Window& window, Done done) {
  const double deadline = nowSeconds() + kWindowSystemSeconds;
  while (!done() && nowSeconds() < deadline) window.waitEvents(0.01);
  return done();
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
  ENGINE_TRY(hsdf::addSceneFeatures(*renderer_, *pool_));
  if (window_ || desc.headlessUi) {
    ENGINE_TRY_ASSIGN(ui_, ui::UiLayer::create(*context_, renderer_->desc().formats.color,
                                               renderer_->desc().framesInFlight, window_.get()));
    ui_->setWindowTitle(kProgramName);
    if (!desc.uiIniFile.empty()) ui_->setIniFile(desc.uiIniFile.string());
    panel_ = std::make_unique<TuningPanel>(*this);
    ui_->addPanel("tuning", [this] { panel_->draw(); });
    ui_->addFeaturePanels(*renderer_);
  }
  differenceOverlay_ = std::make_unique<ImageOverlay>(*context_, renderer_->desc().framesInFlight);
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

// Starts the compared side's bake when it should draw another K (or padding) than it has. The
// main asset at the same K and padding is the same field: it is shared, not baked twice.
void Viewer::updateCompareBake() {
  if (!comparing(tuning_) || drawsCells(tuning_.compareMethod) || !bakeSource_) return;
  const int k = effectiveCompareResolution(tuning_);
  const int padding = tuning_.padding;
  const bool have = compareAsset_ && compareResolution_ == k && comparePadding_ == padding;
  const bool baking = compareJob_ && compareJob_->settings().resolution == k && compareJob_->settings().padding == padding;
  if (baking || (have && !compareJob_)) return;
  compareJob_.reset();  // cancels a bake for a K no longer asked for
  if (have || compareFailed_ == std::pair{k, padding}) return;
  // Shared: the asset baked at K (level 0 when levels of detail draw another), if it has the dense
  // field the compared tracer needs (a sparse cell bake has none).
  const hsdf::HermiteSdfRenderable* r = sdfRenderable();
  const hsdf::HermiteSdfLod* lod = bakedEntity_ ? registry_.tryGet<hsdf::HermiteSdfLod>(*bakedEntity_) : nullptr;
  const auto baked = lod && !lod->levels.empty() ? lod->levels.front() : r ? r->asset : nullptr;
  if (baked && !baked->field.samples.empty() && k == bakedResolution_ && padding == bakedPadding_) {
    compareAsset_ = baked;
    compareResolution_ = k;
    comparePadding_ = padding;
    return;
  }
  hsdf::BakeSettings settings;
  settings.resolution = k;
  settings.padding = padding;
  settings.budget = bakeBudget_;
  compareBakeError_.clear();
  compareJob_ = std::make_unique<hsdf::BakeJob>(*bakeSource_, settings);
}

// A failed compared bake is not retried for the same K (the reason is in compareBakeError()).
void Viewer::finishCompareBake() {
  hsdf::BakeJob::Result result = compareJob_->wait();
  const hsdf::BakeSettings settings = compareJob_->settings();
  compareJob_.reset();
  if (!result) {
    compareBakeError_ = result.error().withContext(fmt::format("baking the compared side at resolution {}", settings.resolution)).message;
    compareFailed_ = {settings.resolution, settings.padding};
    log::warn("{}", compareBakeError_);
    return;
  }
  log::info("compared side baked at resolution {}: {}", settings.resolution, describeSdfStats(sdfStats(**result)));
  compareAsset_ = std::move(*result);
  compareResolution_ = settings.resolution;
  comparePadding_ = settings.padding;
}

int Viewer::compareResolutionDrawn() const {
  if (drawsCells(tuning_.compareMethod) || !compareAsset_) return bakedEntity_ ? bakedResolution_ : 0;
  return compareResolution_;
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
  if (compareJob_) compareJob_->cancel();
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
  if (compareJob_) finishCompareBake();
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
  cells.cullOcclusion = tuning_.cullOcclusion;
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

// The compared side's asset: its own bake, or the main one (a compared method of cells, a .hsdf
// file, or while the first compared bake runs).
std::shared_ptr<const hsdf::SdfAsset> Viewer::comparedAsset(const std::shared_ptr<const hsdf::SdfAsset>& main) const {
  if (drawsCells(tuning_.compareMethod) || !compareAsset_) return main;
  return compareAsset_;
}

// Two regions split at the divider: the main tuning left (top), the compared one right (bottom).
std::vector<render::ViewRegion> Viewer::splitRegions(const std::shared_ptr<const hsdf::SdfAsset>& main) {
  const VkExtent2D e = renderer_->extent();
  const bool vertical = tuning_.split == SplitMode::Vertical;
  const auto divider = std::uint32_t(std::lround(double(tuning_.splitPosition) * (vertical ? e.width : e.height)));
  VkRect2D first{{0, 0}, e}, second{{0, 0}, e};
  if (vertical) {
    first.extent.width = divider;
    second.offset.x = std::int32_t(divider);
    second.extent.width = e.width - divider;
  } else {
    first.extent.height = divider;
    second.offset.y = std::int32_t(divider);
    second.extent.height = e.height - divider;
  }
  const TuningState compared = compareTuning(tuning_);
  const std::shared_ptr<const hsdf::SdfAsset> other = comparedAsset(main);
  return {{first, [this, main] { showState(tuning_, main); }},
          {second, [this, compared, other] { showState(compared, other); }}};
}

// One frame of the normals view with `tuning` and `asset`, read back.
NormalsFrame Viewer::renderNormals(const TuningState& tuning, const std::shared_ptr<const hsdf::SdfAsset>& asset) {
  showState(tuning, asset);
  render::FrameSettings settings;
  settings.debugView = DEBUG_VIEW_NORMALS;
  renderer_->renderFrame(registry_, cameraView(), settings);
  NormalsFrame frame;
  frame.rgba = renderer_->readbackColor();
  frame.visibility = renderer_->readbackVisibility();
  return frame;
}

// The two methods' normals frames (the SDF alone: meshes and the ground would count as covered by
// both), compared on the CPU; the heat map goes to the overlay of the frame drawn next. Needs an
// SDF method on the main side (then the scene's meshes are already hidden, see updateVisibility).
Status Viewer::renderDifference(const std::shared_ptr<const hsdf::SdfAsset>& main) {
  std::vector<std::pair<ecs::Entity, render::MeshRenderable>> meshes;
  registry_.view<render::MeshRenderable>().each(
      [&meshes](ecs::Entity entity, const render::MeshRenderable& mesh) { meshes.emplace_back(entity, mesh); });
  for (const auto& entry : meshes) registry_.remove<render::MeshRenderable>(entry.first);
  const NormalsFrame a = renderNormals(tuning_, main);
  const NormalsFrame b = renderNormals(compareTuning(tuning_), comparedAsset(main));
  for (const auto& [entity, mesh] : meshes) registry_.emplace<render::MeshRenderable>(entity, mesh);
  showState(tuning_, main);
  const VkExtent2D extent = renderer_->extent();
  ENGINE_TRY_ASSIGN(NormalDifference d, compareNormals(a, b, extent.width, extent.height));
  differenceOverlay_->setImage(heatMapImage(d, differenceRange_), extent.width, extent.height);
  difference_ = std::move(d);
  return {};
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

// A minimised window (or a 0x0 framebuffer) gets no swapchain: the old one waits, marked stale,
// and the first drawable step recreates it (an out-of-date swapchain may report the old size).
Status Viewer::recreateSwapchain() {
  swapchainStale_ = true;
  if (window_->minimized()) return {};
  ENGINE_TRY(swapchain_->recreate(window_->framebufferExtent()));
  swapchainStale_ = false;
  ++swapchainRecreations_;
  log::debug("swapchain recreated: {}x{}", swapchain_->extent().width, swapchain_->extent().height);
  renderer_->resize(swapchain_->extent());
  return {};
}

// While minimised the step sleeps for events (at most kMinimizedWaitSeconds) and draws nothing,
// so that the caller's loop (scripts, finished bakes, closing) goes on without spinning.
Status Viewer::handleWindow(float dt, bool& drawable) {
  constexpr double kMinimizedWaitSeconds = 0.05;
  window_->pollEvents();
  drawable = !window_->minimized();
  if (!drawable) {
    if (skippedSteps_++ == 0) {
      const VkExtent2D e = window_->framebufferExtent();
      log::info("window minimised (framebuffer {}x{}): drawing nothing until it is restored", e.width, e.height);
    }
    window_->waitEvents(kMinimizedWaitSeconds);
    return {};
  }
  if (skippedSteps_ > 0) {
    log::info("window restored after {} step(s) without a frame", skippedSteps_);
    skippedSteps_ = 0;
  }
  platform::InputState& input = window_->input();
  input.uiWantsMouse = ui_ && uiVisible_ && ui_->wantsMouse();
  input.uiWantsKeyboard = ui_ && uiVisible_ && ui_->wantsKeyboard();
  handleKeys(input);
  if (cameraMode_ == CameraMode::Orbit) orbit_.update(input);
  else fly_.update(input, std::min(dt, 0.1f));  // a stall does not throw the camera across the scene
  const VkExtent2D extent = window_->framebufferExtent();
  if (swapchainStale_ || extent.width != swapchain_->extent().width || extent.height != swapchain_->extent().height)
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
    if (pressed(GLFW_KEY_F5)) rebuildAndReloadShaders();
  }
  std::copy(std::begin(input.keys), std::end(input.keys), std::begin(keysDown_));
}

Status Viewer::setVsync(bool vsync) {
  if (!swapchain_ || vsync == vsync_) return {};
  // The present mode is fixed at swapchain creation: a new swapchain (later, when minimised).
  swapchain_->setVsync(vsync);
  vsync_ = vsync;
  return recreateSwapchain();
}

Status Viewer::setMinimized(bool minimized) {
  if (!window_) return makeError("minimise/restore: no window (headless)");
  if (minimized) window_->iconify();
  else window_->restore();
  if (!waitForWindowSystem(*window_, [&] { return window_->minimized() == minimized; }))
    return makeError(fmt::format("the window system did not {} the window within {} s (X11 needs a window manager for this)",
                                 minimized ? "minimise" : "restore", kWindowSystemSeconds));
  return {};
}

void Viewer::setFullscreen(bool fullscreen) {
  if (window_) window_->setFullscreen(fullscreen);
}

bool Viewer::fullscreen() const { return window_ && window_->fullscreen(); }

void Viewer::resize(std::uint32_t width, std::uint32_t height) {
  if (window_) {
    window_->setSize(int(width), int(height));
    requestedSize_ = {width, height};
    return;
  }
  context_->waitIdle();
  renderer_->resize({width, height});
}

Status Viewer::waitForWindowSize() {
  if (!window_ || requestedSize_.width == 0) return {};
  auto reached = [this] {
    const VkExtent2D e = window_->framebufferExtent();
    return e.width == requestedSize_.width && e.height == requestedSize_.height;
  };
  if (!waitForWindowSystem(*window_, reached))
    return makeError(fmt::format("the window system did not resize the window to {}x{} within {} s", requestedSize_.width,
                                 requestedSize_.height, kWindowSystemSeconds));
  return {};
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
  if (bakeJob_ && bakeJob_->done()) {
    if (Status baked = finishBake(); !baked) log::warn("{}", baked.error().message);
    updateCompareBake();
  }
  if (compareJob_ && compareJob_->done()) finishCompareBake();
  applyTuningToScene();
  scene::updateWorldTransforms(registry_);
  updateLevelsOfDetail(false);
  const bool ui = ui_ && uiVisible_;
  render::FrameSettings settings;
  settings.debugView = std::uint32_t(tuning_.debugView);
  settings.swapchain = swapchain_.get();
  settings.overlay = ui ? ui_.get() : nullptr;
  // The comparison: the main asset is put back after the frame (regions swap it in and out).
  hsdf::HermiteSdfRenderable* sdf = sdfRenderable();
  const std::shared_ptr<const hsdf::SdfAsset> main = sdf ? sdf->asset : nullptr;
  difference_.reset();
  if (tuning_.difference && main && isSdfMethod(tuning_.method)) {
    ENGINE_TRY(renderDifference(main));
    differenceOverlay_->setNext(settings.overlay);
    settings.overlay = differenceOverlay_.get();
  } else if (tuning_.split != SplitMode::Off && main) {
    settings.regions = splitRegions(main);
  }
  if (ui) ui_->buildFrame(renderer_->extent(), dt);
  ENGINE_TRY_ASSIGN(const bool presented, renderFrame(settings));
  if (!settings.regions.empty()) showState(tuning_, main);
  if (!presented) {
    log::debug("swapchain out of date or suboptimal: recreating it");
    ENGINE_TRY(recreateSwapchain());
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
  if (tuning_.split != SplitMode::Off)
    log::info("screenshot: {}: split {} at {:.2f}: {} K {} | {} K {} ({} normals)", path.string(), splitModeName(tuning_.split),
              tuning_.splitPosition, methodName(tuning_.method), bakedResolution_, methodName(tuning_.compareMethod),
              compareResolutionDrawn(), normalModeName(tuning_.compareNormals));
  if (difference_)
    log::info("screenshot: {}: difference {} vs {}: mean {:.3f} deg, max {:.3f} deg over {} pixels; coverage differs in "
              "{} of {} covered pixels ({:.4f})",
              path.string(), methodName(tuning_.method), methodName(tuning_.compareMethod), difference_->meanDegrees,
              difference_->maxDegrees, difference_->coveredBoth, difference_->coverageDiffers, difference_->coveredEither,
              difference_->coverageDiffersShare());
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
  compareJob_.reset();
  levelJob_.reset();
  try {
    context_->waitIdle();
  } catch (const gpu::VulkanError& e) {  // a lost device has nothing left to wait for
    if (e.result() != VK_ERROR_DEVICE_LOST) throw;
    deviceLost_ = true;
  }
  differenceOverlay_.reset();
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
