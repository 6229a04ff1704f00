#include "hermite_sdf/render/sphere_trace_feature.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <imgui.h>

#include "engine/core/log.h"
#include "engine/core/math.h"
#include "engine/ecs/registry.h"
#include "engine/gpu/allocate_or_refuse.h"
#include "engine/gpu/context.h"
#include "engine/gpu/deferred_release.h"
#include "engine/gpu/vk_check.h"
#include "engine/render/gpu_scene.h"
#include "engine/scene/transform.h"
#include "hermite/hermite_host_device.h"
#include "render/wireframe.h"
#include "render/near_plane.h"
#include "render/ray_anchor.h"
#include "render/sphere_trace_textures.h"

namespace hsdf {

static_assert(SphereTraceFeature::kFeatureId == SPHERE_TRACE_FEATURE_ID);

namespace {

constexpr const char* kMethodNames[kTraceMethodCount] = {"trilinear", "hermite"};
constexpr std::uint32_t kBoxVertices = 36;

bool traceMethod(RenderMethod method, std::uint32_t& out) {
  if (method == RenderMethod::TrilinearSphereTrace) out = std::uint32_t(TraceMethod::Trilinear);
  else if (method == RenderMethod::HermiteSphereTrace) out = std::uint32_t(TraceMethod::Hermite);
  else return false;
  return true;
}

// A length setting a program may set by hand (epsilon, the central-difference step): a NaN, an
// infinity or a value not above zero drew garbage (a NaN epsilon twice the coverage) and takes
// the default instead, said once per value.
float checkedLength(float value, float fallback, const char* name, std::string& said) {
  if (std::isfinite(value) && value > 0.0f) return value;
  const std::string message = fmt::format("sphere tracing: Settings::{} {} is not a positive length; {} is used",
                                          name, value, fallback);
  if (said.find(message) == std::string::npos) {
    engine::log::warn("{}", message);
    said += message + "\n";
  }
  return fallback;
}

}  // namespace

SphereTraceFeature::SphereTraceFeature() = default;

SphereTraceFeature::SphereTraceFeature(Options options) : options_(options) {}

SphereTraceFeature::~SphereTraceFeature() {
  if (!context_) return;
  // The bindings' descriptor set layout is in every pipeline's description: a worker compiling one
  // would create its layout from a destroyed handle (the members' destruction joins it after this).
  warming_.stop();
  textures_.clear();
  bindings_.reset();
  for (engine::gpu::SamplerHandle& sampler : samplers_) sampler.reset();
}

float SphereTraceFeature::exactBelowCells(std::uint32_t bits) {
  const int b = int(std::clamp(bits, 1u, 8u));
  return std::ldexp(1.0f, 2 - b);
}

namespace {

// What every pipeline of the tracers reads (`draws`: this frame's SphereTraceDraw buffer), the same
// in each pass of a frame.
shader::SphereTracePushConstants pushConstants(const engine::render::PassContext& pass, VkDeviceAddress draws) {
  shader::SphereTracePushConstants push{};
  push.draw.frameGlobals = pass.frameGlobals;
  push.draw.objects = pass.objects;
  push.draw.debugView = pass.frame.debugView;
  push.draws = draws;
  push.counters = pass.frame.workCounters;
  push.workTotals = pass.frame.workTotals;
  return push;
}

}  // namespace

engine::Status SphereTraceFeature::initialize(const engine::gpu::Context& context,
                                              const engine::render::RendererFormats& formats,
                                              std::uint32_t framesInFlight) {
  context_ = &context;
  ENGINE_TRY(checkFieldFormats(context));
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(context.physicalDevice(), &properties);
  deviceFilterBits_ = properties.limits.subTexelPrecisionBits;
  const bool bindless = options_.allowBindless && context.capabilities().descriptorIndexing;
  ENGINE_TRY_ASSIGN(bindings_, FieldTextureBindings::create(context, bindless));
  stats_.bindless = bindless;
  createSamplers();
  drawBuffer_ = engine::render::PerFrameBuffer(context, framesInFlight, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                               "sphere trace draws");
  formats_ = formats;
  ENGINE_TRY_ASSIGN(pipelines_, describePipelines());
  return {};
}

// engine::gpu::reloadPipelineSet: those only warmed are warmed again from the next frame
// (Settings::warmPipelines).
engine::Status SphereTraceFeature::reloadShaders() {
  return engine::gpu::reloadPipelineSet(*context_, warming_, pipelines_, [this] { return describePipelines(); });
}

engine::Status SphereTraceFeature::createAllPipelines() {
  return engine::gpu::createAll(*context_, pipelines_.all());
}

void SphereTraceFeature::createSamplers() {
  for (std::uint32_t method = 0; method < kTraceMethodCount; ++method) {
    // Trilinear fields are filtered by the hardware; Hermite fields are only texelFetch'ed.
    const VkFilter filter = method == std::uint32_t(TraceMethod::Trilinear) ? VK_FILTER_LINEAR : VK_FILTER_NEAREST;
    samplers_[method] = engine::gpu::createClampedSampler(*context_, filter,
                                                           std::string("sphere trace ") + kMethodNames[method] + " sampler");
  }
}

std::vector<engine::gpu::LazyPipeline*> SphereTraceFeature::Pipelines::all() {
  std::vector<engine::gpu::LazyPipeline*> set;
  for (auto* pairs : {&depthFront, &depthNear})
    for (auto& pair : *pairs)
      for (auto& pipeline : pair) set.push_back(&pipeline);
  for (auto& pipeline : shade) set.push_back(&pipeline);
  set.push_back(&wire);
  return set;
}

// What a switch to either tracer binds in a frame like this one (its work counters on or off):
// each method's front faces and shading. Not the near variants (the eye close to an object) or
// the wireframe: rarer than a switch, and each compile costs ~0.1-0.4 s of CPU on lavapipe beside
// the frames. The record precision needs no pipeline of its own (only the texture's format
// differs). Trilinear first: the split screen's compared method unless the user picks another.
// Those made already are skipped by the worker at the cost of a lock.
std::vector<engine::gpu::LazyPipeline*> SphereTraceFeature::likelyNextPipelines(bool counted) {
  std::vector<engine::gpu::LazyPipeline*> set;
  for (std::uint32_t method = 0; method < kTraceMethodCount; ++method) {
    set.push_back(&pipelines_.depthFront[method][counted ? 1 : 0]);
    set.push_back(&pipelines_.shade[method]);
  }
  return set;
}

// Every pipeline, described with its shader modules loaded (a missing or bad SPIR-V file fails
// here), compiled when a frame first draws with it.
engine::Expected<SphereTraceFeature::Pipelines> SphereTraceFeature::describePipelines() const {
  const engine::render::RendererFormats& formats = formats_;
  Pipelines pipelines;
  const std::string bindless = bindings_->bindless() ? "_bindless" : "";
  ENGINE_TRY_ASSIGN(auto vert, engine::gpu::loadSharedShaderModule(*context_, "sphere_trace.vert"));
  for (std::uint32_t method = 0; method < kTraceMethodCount; ++method) {
    const std::string prefix = std::string("sphere_trace_") + kMethodNames[method];
    ENGINE_TRY_ASSIGN(auto shadeFrag, engine::gpu::loadSharedShaderModule(*context_, prefix + "_shade" + bindless + ".frag"));

    engine::gpu::GraphicsPipelineDesc desc;
    desc.vertex = vert->handle();
    desc.pushConstantBytes = sizeof(shader::SphereTracePushConstants);
    desc.setLayouts = {formats.sceneSetLayout, bindings_->layout()};
    desc.depthFormat = formats.depth;
    desc.colorFormats = formats.prepassColorFormats();
    desc.depthCompare = VK_COMPARE_OP_GREATER;

    for (const bool counted : {false, true}) {
      const std::string variant = counted ? "_counted" : "";
      ENGINE_TRY_ASSIGN(auto depthFrag,
                        engine::gpu::loadSharedShaderModule(*context_, prefix + "_depth" + bindless + variant + ".frag"));
      ENGINE_TRY_ASSIGN(auto nearFrag,
                        engine::gpu::loadSharedShaderModule(*context_, prefix + "_depth_near" + bindless + variant + ".frag"));
      desc.name = std::string("sphere trace ") + kMethodNames[method] + " depth" + variant;
      desc.fragment = depthFrag->handle();
      desc.cullMode = VK_CULL_MODE_BACK_BIT;
      pipelines.depthFront[method][counted] = engine::gpu::LazyPipeline(desc, {vert, depthFrag});

      desc.name = std::string("sphere trace ") + kMethodNames[method] + " depth near" + variant;
      desc.fragment = nearFrag->handle();
      desc.cullMode = VK_CULL_MODE_FRONT_BIT;
      pipelines.depthNear[method][counted] = engine::gpu::LazyPipeline(desc, {vert, nearFrag});
    }

    // Shading: the prepass decided visibility; the box only selects candidate pixels. Its cull
    // mode follows the object's prepass variant (dynamic state, core in Vulkan 1.3).
    desc.name = std::string("sphere trace ") + kMethodNames[method] + " shading";
    desc.fragment = shadeFrag->handle();
    desc.colorFormats = {formats.color};
    desc.depthTest = false;
    desc.depthWrite = false;
    desc.extraDynamicStates = {VK_DYNAMIC_STATE_CULL_MODE};
    pipelines.shade[method] = engine::gpu::LazyPipeline(desc, {vert, shadeFrag});
  }

  // The boxes' edges over the shaded frame, tested against the prepass depth (as the cells' are).
  ENGINE_TRY_ASSIGN(auto wireVert, engine::gpu::loadSharedShaderModule(*context_, "sphere_trace_wire.vert"));
  ENGINE_TRY_ASSIGN(auto wireFrag, engine::gpu::loadSharedShaderModule(*context_, "cells_wire.frag"));
  engine::gpu::GraphicsPipelineDesc wire = wireframePipelineDesc(formats);
  wire.name = "sphere trace wireframe";
  wire.vertex = wireVert->handle();
  wire.fragment = wireFrag->handle();
  wire.pushConstantBytes = sizeof(shader::SphereTracePushConstants);
  pipelines.wire = engine::gpu::LazyPipeline(wire, {wireVert, wireFrag});
  return pipelines;
}

namespace {

// A multi-material asset's palette and sample slots as the shading pass reads them
// (FieldMaterialsHeader, then the palette, then the slots four to a word); empty for one material.
std::vector<std::uint8_t> fieldMaterialsBlock(const SdfAsset& asset) {
  if (asset.palette.empty() || asset.field.materials.empty()) return {};
  shader::FieldMaterialsHeader header{};
  std::vector<shader::HermiteMaterialGpu> palette;
  for (const SdfMaterial& m : asset.palette) palette.push_back({m.baseColor, glm::vec4(m.roughness, m.metallic, 0.0f, 0.0f)});
  const std::size_t paletteBytes = palette.size() * sizeof(shader::HermiteMaterialGpu);
  header.paletteSize = std::uint32_t(palette.size());
  header.slotsOffset = std::uint32_t(sizeof header + paletteBytes);
  const std::size_t slotBytes = (asset.field.materials.size() + 3) / 4 * 4;
  std::vector<std::uint8_t> block(sizeof header + paletteBytes + slotBytes, 0);
  std::memcpy(block.data(), &header, sizeof header);
  std::memcpy(block.data() + sizeof header, palette.data(), paletteBytes);
  std::memcpy(block.data() + sizeof header + paletteBytes, asset.field.materials.data(), asset.field.materials.size());
  return block;
}

}  // namespace

engine::Expected<SphereTraceFeature::FieldTexture> SphereTraceFeature::uploadTexture(const SdfAsset& asset,
                                                                                     std::uint32_t method, bool half,
                                                                                     bool& outOfResources,
                                                                                     VkDeviceSize& neededBytes) {
  outOfResources = false;
  neededBytes = 0;
  const GridSpec& grid = asset.field.grid;
  if (asset.field.samples.empty())
    return engine::makeError("it has no dense field (cells only: a sparse bake or a file baked with --cells)");
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(context_->physicalDevice(), &properties);
  if (grid.resolution < 2 || std::uint32_t(grid.resolution) > properties.limits.maxImageDimension3D)
    return engine::makeError("resolution " + std::to_string(grid.resolution) + " exceeds the device's 3D texture size " +
                             std::to_string(properties.limits.maxImageDimension3D));
  if (std::uint32_t(grid.resolution) > SPHERE_TRACE_MAX_RESOLUTION)
    return engine::makeError("resolution " + std::to_string(grid.resolution) + " exceeds the sphere tracers' " +
                             std::to_string(SPHERE_TRACE_MAX_RESOLUTION) + " (their march keys a cell as one int)");
  ENGINE_TRY_ASSIGN(FieldTexels texels, packFieldTexels(asset.field, TraceMethod(method), half));
  neededBytes = texels.bytes.size();  // at least (its staging copy comes on top)

  FieldTexture texture;
  engine::gpu::ImageDesc desc;
  desc.type = VK_IMAGE_TYPE_3D;
  desc.format = texels.format;
  desc.extent = {std::uint32_t(grid.resolution), std::uint32_t(grid.resolution), std::uint32_t(grid.resolution)};
  desc.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  desc.name = asset.name + " " + kMethodNames[method] + (half ? " fp16" : " fp32") + " field";
  // The asset's materials as another of its textures uploaded them, else uploaded here.
  const auto shared = materials_.find(asset.id);
  std::shared_ptr<const engine::gpu::Buffer> materials = shared == materials_.end() ? nullptr : shared->second.lock();
  const std::vector<std::uint8_t> block = materials ? std::vector<std::uint8_t>() : fieldMaterialsBlock(asset);
  neededBytes += block.size();
  // Refused for the budget or the device's memory: this object only is dropped.
  const engine::Status uploaded = engine::gpu::allocateOrRefuse([&] {
    texture.image = engine::gpu::Image(*context_, desc);
    engine::gpu::uploadImage(*context_, texture.image, texels.bytes.data(), texels.bytes.size());
    if (!block.empty())
      materials = std::make_shared<const engine::gpu::Buffer>(engine::gpu::createBufferWithData(
          *context_, block.data(), block.size(), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
          asset.name + " materials"));
  });
  if (!uploaded) {
    outOfResources = true;
    return engine::makeError("out of GPU memory (" + uploaded.error().message + ")");
  }
  texture.bytes = texels.bytes.size();
  auto slot = bindings_->add(texture.image.view(), samplers_[method].get());
  if (!slot) {
    outOfResources = true;
    return slot.error();
  }
  texture.slot = *slot;
  texture.materials = materials;
  if (materials) materials_[asset.id] = materials;
  return texture;
}

// Only a refusal for resources: an asset the tracers cannot draw at all (cells only) is not drawn,
// and its entity does not go on drawing the field it replaced (it did: a stale image).
bool SphereTraceFeature::refused(std::uint64_t assetId) const {
  return std::any_of(refusals_.begin(), refusals_.end(), [assetId](const auto& r) { return std::get<0>(r.first) == assetId; });
}

// A refusal for GPU memory or the texture table is forgotten (the texture is tried again, and
// reported again if refused) once memory may fit it or a texture has given its slot back since.
void SphereTraceFeature::forgetRefusalsThatMayFit() {
  const engine::gpu::Allocator& allocator = context_->allocator();
  std::erase_if(refusals_, [&](const auto& r) {
    const bool retry = r.second.memory.mayRetry(allocator) || r.second.releasedTextures < releasedTextures_;
    if (retry) failedTextures_.erase(r.first);
    return retry;
  });
}

const SphereTraceFeature::FieldTexture* SphereTraceFeature::acquireTexture(const SdfAsset& asset, std::uint32_t method,
                                                                           bool half,
                                                                           const engine::render::FrameContext& frame) {
  const TextureKey key{asset.id, method, half};
  auto found = textures_.find(key);
  if (found == textures_.end()) {
    if (failedTextures_.contains(key)) return nullptr;
    bool outOfResources = false;
    VkDeviceSize needed = 0;
    auto uploaded = uploadTexture(asset, method, half, outOfResources, needed);
    if (!uploaded) {
      frame.reportDropped(fmt::format("sphere tracing: '{}' is not drawn: {}", asset.name, uploaded.error().message));
      failedTextures_.insert(key);
      if (outOfResources)
        refusals_.insert_or_assign(key, Refusal{engine::gpu::MemoryRefusal(context_->allocator(), needed), releasedTextures_});
      return nullptr;
    }
    found = textures_.emplace(key, std::move(uploaded.value())).first;
  }
  found->second.lastUsedFrame = frame.frameNumber;
  return &found->second;
}

SphereTraceFeature::RetiredTexture::~RetiredTexture() {
  try {
    bindings->remove(texture.slot);
    ++*releasedTextures;
  } catch (const engine::gpu::VulkanError& e) {  // a destructor must not throw: the slot stays taken
    engine::log::error("sphere tracing: a released texture's slot was not given back: {}", e.what());
  }
}

// A texture no frame has drawn for framesInFlight frames is unneeded (a shorter wait would upload
// again the texture of a view region drawn every other region, or of a split screen); it is retired
// with the last frame that drew it, so it is destroyed, and its slot freed, as soon as that frame
// has completed.
void SphereTraceFeature::releaseUnusedTextures(const engine::render::FrameContext& frame) {
  for (auto it = textures_.begin(); it != textures_.end();) {
    const std::uint64_t lastUse = it->second.lastUsedFrame;
    if (engine::gpu::DeferredRelease::completed(lastUse, frame.frameNumber, frame.framesInFlight)) {
      auto retired = std::make_unique<RetiredTexture>(std::move(it->second), bindings_.get(), &releasedTextures_);
      frame.retire(std::move(retired), lastUse);
      it = textures_.erase(it);
    } else {
      ++it;
    }
  }
}

// The texture an entity draws with `method`, and its asset: the renderable's, or, while that one is
// refused (its texture did not fit in GPU memory) after it replaced the entity's field, the field it
// replaced, still uploaded, from the frame that found out on. Null texture: nothing to draw.
SphereTraceFeature::EntityTexture SphereTraceFeature::entityTexture(engine::ecs::Entity entity,
                                                                    const HermiteSdfRenderable& r, std::uint32_t method,
                                                                    const engine::render::FrameContext& frame) {
  const auto acquire = [&](const std::shared_ptr<const SdfAsset>& asset) {
    return EntityTexture{asset, acquireTexture(*asset, method, r.halfPrecision && halfPrecisionFits(asset->field.grid), frame)};
  };
  EntityTexture found = acquire(r.asset);
  if (!found.texture && refused(r.asset->id))
    if (const auto* previous = drawnAssets_.previous(entity)) found = acquire(*previous);
  return found;
}

// One object's draw: its grid, its texture and the tracing settings (checked once each).
shader::SphereTraceDraw SphereTraceFeature::makeDraw(const EntityTexture& found, const HermiteSdfRenderable& r,
                                                     std::uint32_t object) {
  const GridSpec& grid = found.asset->field.grid;
  shader::SphereTraceDraw draw{};
  draw.gridOriginSpacing = glm::vec4(glm::vec3(grid.bounds().min), float(grid.spacing));
  draw.object = object;
  draw.resolution = std::uint32_t(grid.resolution);
  draw.flags = r.normals == NormalMode::CentralDifferences ? HERMITE_FLAG_NORMALS_CENTRAL : 0u;
  draw.texture = found.texture->slot;
  draw.maxSteps = std::max(settings_.maxSteps, 1u);
  draw.epsilon = checkedLength(settings_.epsilon, Settings{}.epsilon, "epsilon", settingsSaid_);
  draw.centralStep = checkedLength(settings_.centralDifferenceStep, Settings{}.centralDifferenceStep,
                                   "centralDifferenceStep", settingsSaid_);
  draw.filterBits = std::min(settings_.emulatedFilterBits, 16u);
  draw.exactBelow = exactBelowCells(draw.filterBits != 0 ? draw.filterBits : deviceFilterBits_);
  return draw;
}

void SphereTraceFeature::collectDraws(engine::render::FrameContext& frame) {
  DrawLists lists;
  const engine::math::Frustum frustum = engine::math::extractFrustum(frame.camera.proj * frame.camera.view);
  const ViewAxis axis = viewAxis(frame.camera);
  std::unordered_map<engine::ecs::Entity, std::shared_ptr<const SdfAsset>> drawnThisFrame;
  drawnAssets_.beginRegion(frame);
  frame.registry.view<HermiteSdfRenderable, engine::scene::WorldTransform>().each(
      [&](engine::ecs::Entity entity, const HermiteSdfRenderable& r, const engine::scene::WorldTransform& world) {
        std::uint32_t method = 0;
        if (!r.asset) return;
        if (!traceMethod(r.method, method)) return;  // drawn by the cells
        if (!engine::render::drawableTransform(world.matrix)) {  // the rays could not be taken into the grid
          ++stats_.skippedObjects;
          return;
        }
        const Aabb bounds = r.asset->field.grid.bounds();
        if (!engine::math::intersects(frustum, world.matrix, glm::vec3(bounds.min), glm::vec3(bounds.max))) {
          ++stats_.culledObjects;
          if (const auto* previous = drawnAssets_.previous(entity))
            drawnThisFrame[entity] = *previous;  // what it would draw when back in view
          return;
        }
        const EntityTexture found = entityTexture(entity, r, method, frame);
        if (!found.texture) {
          ++stats_.skippedObjects;
          return;
        }
        drawnThisFrame[entity] = found.asset;
        const Aabb drawn = found.asset->field.grid.bounds();
        shader::ObjectData object =
            engine::render::GpuScene::makeObject(world.matrix, r.color, r.roughness, 0.0f, kFeatureId);
        object.payload = found.texture->materials ? found.texture->materials->address() : 0;  // FieldMaterialsHeader
        const bool near = nearPlaneMayCut(frame.camera, object.model, glm::vec3(drawn.min), glm::vec3(drawn.max));
        shader::SphereTraceDraw draw = makeDraw(found, r, frame.scene.addObject(object));
        const GridSpec& grid = found.asset->field.grid;
        draw.rayAnchor = glm::vec4(rayAnchorGrid(axis, world.matrix, grid, eyeInGrid(frame.camera, world.matrix, grid)));
        lists[method][near ? 1 : 0].push_back(draw);
        (method == std::uint32_t(TraceMethod::Trilinear) ? stats_.trilinearObjects : stats_.hermiteObjects)++;
        stats_.nearObjects += near ? 1u : 0u;
      });
  drawnAssets_.setDrawn(std::move(drawnThisFrame));
  uploadDraws(frame, lists);
}

// One buffer: [trilinear front][trilinear near][hermite front][hermite near].
void SphereTraceFeature::uploadDraws(const engine::render::FrameContext& frame, const DrawLists& lists) {
  std::vector<shader::SphereTraceDraw> all;
  for (std::uint32_t method = 0; method < kTraceMethodCount; ++method) {
    front_[method] = {std::uint32_t(all.size()), std::uint32_t(lists[method][0].size())};
    all.insert(all.end(), lists[method][0].begin(), lists[method][0].end());
    near_[method] = {std::uint32_t(all.size()), std::uint32_t(lists[method][1].size())};
    all.insert(all.end(), lists[method][1].begin(), lists[method][1].end());
  }
  drawSlots_.clear();
  for (const shader::SphereTraceDraw& draw : all) drawSlots_.push_back(draw.texture);
  if (!all.empty()) drawBuffer_.upload(frame.frameSlot, all);
}

void SphereTraceFeature::prepare(engine::render::FrameContext& frame) {
  regionStats_.startRegion(frame.frameNumber, stats_);
  const bool bindless = stats_.bindless;
  stats_ = Stats{};
  stats_.bindless = bindless;
  forgetRefusalsThatMayFit();
  collectDraws(frame);
  releaseUnusedTextures(frame);
  stats_.textures = std::uint32_t(textures_.size());
  std::set<const engine::gpu::Buffer*> materials;  // as the textures hold them: each counted once
  for (const auto& [key, texture] : textures_) {
    stats_.textureBytes += texture.bytes;
    if (texture.materials && materials.insert(texture.materials.get()).second)
      stats_.textureBytes += texture.materials->size();
  }
  stats_.materialBuffers = std::uint32_t(materials.size());
  std::erase_if(materials_, [](const auto& m) { return m.second.expired(); });
  warming_.frame(*context_, settings_.warmPipelines && hasSdfObjects(frame.registry),
                 [&] { return likelyNextPipelines(frame.workCounters != 0); });
}

// Bindless: one instanced draw for the whole range (gl_InstanceIndex = the draw's index).
// Per-texture sets: each object binds its set and draws its own instance.
void SphereTraceFeature::recordDraws(VkCommandBuffer cmd, VkPipelineLayout layout, Range range) const {
  if (range.count == 0) return;
  if (bindings_->bindless()) {
    bindings_->bind(cmd, layout, 0);
    vkCmdDraw(cmd, kBoxVertices, range.count, 0, range.first);
    return;
  }
  for (std::uint32_t i = range.first; i < range.first + range.count; ++i) {
    bindings_->bind(cmd, layout, drawSlots_[i]);
    vkCmdDraw(cmd, kBoxVertices, 1, 0, i);
  }
}

void SphereTraceFeature::recordMethod(engine::render::PassContext& pass, std::uint32_t method) {
  if (front_[method].count + near_[method].count == 0) return;
  VkCommandBuffer cmd = pass.cmd;
  const bool prepass = pass.pass == engine::render::Pass::DepthPrepass;
  pass.timer.begin(cmd, std::string(kMethodNames[method]) + (prepass ? " prepass" : " shading"));
  const shader::SphereTracePushConstants push = pushConstants(pass, drawBuffer_.address(pass.frame.frameSlot));
  const bool counted = pass.frame.workCounters != 0;
  const VkShaderStageFlags stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
  if (prepass) {
    for (const bool near : {false, true}) {
      const Range& range = near ? near_[method] : front_[method];
      if (range.count == 0) continue;  // no pipeline compiled for a list with nothing to draw
      engine::gpu::LazyPipeline& lazy = near ? pipelines_.depthNear[method][counted] : pipelines_.depthFront[method][counted];
      const engine::gpu::Pipeline* pipeline = lazy.getOrLog(*context_);
      if (!pipeline) continue;
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline->handle());
      vkCmdPushConstants(cmd, pipeline->layout(), stages, 0, sizeof(push), &push);
      recordDraws(cmd, pipeline->layout(), range);
    }
  } else if (const engine::gpu::Pipeline* made = pipelines_.shade[method].getOrLog(*context_)) {
    const engine::gpu::Pipeline& pipeline = *made;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.handle());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.layout(), 0, 1, &pass.sceneSet, 0, nullptr);
    vkCmdPushConstants(cmd, pipeline.layout(), stages, 0, sizeof(push), &push);
    vkCmdSetCullMode(cmd, VK_CULL_MODE_BACK_BIT);
    recordDraws(cmd, pipeline.layout(), front_[method]);
    vkCmdSetCullMode(cmd, VK_CULL_MODE_FRONT_BIT);
    recordDraws(cmd, pipeline.layout(), near_[method]);
  }
  pass.timer.end(cmd);
}

void SphereTraceFeature::recordPass(engine::render::PassContext& pass) {
  for (std::uint32_t method = 0; method < kTraceMethodCount; ++method) recordMethod(pass, method);
  if (pass.pass == engine::render::Pass::Opaque && pass.frame.debugView == DEBUG_VIEW_WIREFRAME) recordWireframe(pass);
}

// Every draw of both methods, front and near lists alike: one instanced draw per list (the
// instance is the draw's index; no texture is read).
void SphereTraceFeature::recordWireframe(engine::render::PassContext& pass) {
  const shader::SphereTracePushConstants push = pushConstants(pass, drawBuffer_.address(pass.frame.frameSlot));
  const engine::gpu::Pipeline* pipeline = pipelines_.wire.getOrLog(*context_);
  if (!pipeline) return;
  VkCommandBuffer cmd = pass.cmd;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline->handle());
  vkCmdPushConstants(cmd, pipeline->layout(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                     sizeof(push), &push);
  constexpr std::uint32_t kEdgeVertices = 24;
  for (std::uint32_t method = 0; method < kTraceMethodCount; ++method)
    for (const Range& range : {front_[method], near_[method]})
      if (range.count != 0) vkCmdDraw(cmd, kEdgeVertices, range.count, 0, range.first);
}

void SphereTraceFeature::drawUi() {
  if (!ImGui::CollapsingHeader("Sphere tracing")) return;
  // Read-only: the application owns the settings (the scene runner's tuning panel writes them).
  ImGui::TextWrapped("epsilon %.1e h, max steps %u, central difference step %.2f h", double(settings_.epsilon),
                     settings_.maxSteps, double(settings_.centralDifferenceStep));
  const std::vector<Stats> regions = regionStats();
  for (std::size_t i = 0; i < regions.size(); ++i) {
    const Stats& s = regions[i];
    const std::string view = engine::render::regionPrefix(i, regions.size());
    ImGui::TextWrapped("%sobjects: %u trilinear, %u hermite, %u near, %u culled, %u skipped", view.c_str(),
                       s.trilinearObjects, s.hermiteObjects, s.nearObjects, s.culledObjects, s.skippedObjects);
  }
  ImGui::TextWrapped("textures: %u, %.2f MiB, %s", stats_.textures, double(stats_.textureBytes) / (1024.0 * 1024.0),
                     stats_.bindless ? "bindless" : "per-texture descriptor sets");
}

}  // namespace hsdf
