#include "engine/render/renderer.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>
#include <glm/gtc/packing.hpp>

#include "engine/core/log.h"
#include "engine/gpu/context.h"
#include "engine/gpu/swapchain.h"
#include "engine/gpu/vk_check.h"
#include "engine/scene/transform.h"

namespace engine::render {
namespace {

constexpr std::uint32_t kMaxTimerScopes = 64;  // passes and feature scopes, per view region (times maxViewRegions)
constexpr std::uint32_t kMaxFramesInFlight = 16;
constexpr std::uint32_t kStatisticsScopes = 2;  // depth prepass, opaque (of the first view region)

// The depth target lives in this layout from the end of the prepass on (shading pass, read-backs).
constexpr VkImageLayout kFinalDepthLayout = VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL;

VkRenderingAttachmentInfo depthAttachment(const gpu::Image& depth, VkAttachmentLoadOp load, VkImageLayout layout) {
  VkRenderingAttachmentInfo info{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  info.imageView = depth.view();
  info.imageLayout = layout;
  info.loadOp = load;
  info.storeOp = layout == kFinalDepthLayout ? VK_ATTACHMENT_STORE_OP_NONE : VK_ATTACHMENT_STORE_OP_STORE;
  info.clearValue.depthStencil = {0.0f, 0};  // reverse-Z: 0 is infinitely far
  return info;
}

// The viewport is always the whole frame (one projection for every region); the scissor is the region.
void setViewportAndScissor(VkCommandBuffer cmd, VkExtent2D extent, VkRect2D scissor) {
  const VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
}

// `rect` clipped to the frame (empty when it lies outside).
VkRect2D clipToFrame(VkRect2D rect, VkExtent2D extent) {
  const std::int64_t x0 = std::clamp<std::int64_t>(rect.offset.x, 0, extent.width);
  const std::int64_t y0 = std::clamp<std::int64_t>(rect.offset.y, 0, extent.height);
  const std::int64_t x1 = std::clamp<std::int64_t>(std::int64_t(rect.offset.x) + rect.extent.width, x0, extent.width);
  const std::int64_t y1 = std::clamp<std::int64_t>(std::int64_t(rect.offset.y) + rect.extent.height, y0, extent.height);
  return {{std::int32_t(x0), std::int32_t(y0)}, {std::uint32_t(x1 - x0), std::uint32_t(y1 - y0)}};
}

std::string regionSuffix(std::uint32_t region) {
  return region == 0 ? std::string() : " [view " + std::to_string(region + 1) + "]";
}

// The extent's sides against zero and the device's largest image and framebuffer; throws
// std::invalid_argument naming `what` (a Vulkan call with such an extent is invalid usage).
void checkExtent(const gpu::Context& context, VkExtent2D extent, const char* what) {
  VkPhysicalDeviceProperties properties;
  vkGetPhysicalDeviceProperties(context.physicalDevice(), &properties);
  const VkPhysicalDeviceLimits& limits = properties.limits;
  const std::uint32_t largest = std::min({limits.maxImageDimension2D, limits.maxFramebufferWidth, limits.maxFramebufferHeight});
  if (extent.width == 0 || extent.height == 0 || extent.width > largest || extent.height > largest)
    throw std::invalid_argument(fmt::format("{}: extent {}x{}: each side must be 1 to {} pixels on '{}' "
                                            "(maxImageDimension2D, maxFramebufferWidth/Height)",
                                            what, extent.width, extent.height, largest,
                                            context.capabilities().deviceName));
}

// The description the renderer is made with, checked before any member uses it.
const RendererDesc& checkedDesc(const gpu::Context& context, const RendererDesc& desc, VkExtent2D extent) {
  if (desc.framesInFlight == 0 || desc.framesInFlight > kMaxFramesInFlight)
    throw std::invalid_argument(fmt::format("RendererDesc::framesInFlight {}: 1 to {}", desc.framesInFlight,
                                            kMaxFramesInFlight));
  checkExtent(context, extent, "Renderer");
  return desc;
}

}  // namespace

void FrameContext::reportDropped(std::string message) const {
  log::error("{}", message);
  if (droppedObjects) droppedObjects->push_back(std::move(message));
}

Renderer::Renderer(const gpu::Context& context, const RendererDesc& desc, VkExtent2D extent)
    : context_(context),
      desc_(checkedDesc(context, desc, extent)),
      extent_(extent),
      scene_(context, desc.framesInFlight * std::max(desc.maxViewRegions, 1u)),
      frameGlobals_(context, desc.framesInFlight, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "frame globals") {
  desc_.maxViewRegions = std::max(desc_.maxViewRegions, 1u);
  try {  // a constructor that throws runs no destructor: the raw handles made so far go back here
    createFrameObjects();
  } catch (...) {
    destroyHandles();
    throw;
  }
}

void Renderer::createFrameObjects() {
  const gpu::Context& context = context_;
  createSceneDescriptors();
  createTargets();
  frames_.resize(desc_.framesInFlight);
  for (std::uint32_t i = 0; i < desc_.framesInFlight; ++i) {
    FrameResources& frame = frames_[i];
    const std::string suffix = " [frame " + std::to_string(i) + "]";
    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.queueFamilyIndex = context.queueFamily();
    VK_CHECK(vkCreateCommandPool(context.device(), &poolInfo, nullptr, &frame.pool));
    context.setName(frame.pool, VK_OBJECT_TYPE_COMMAND_POOL, "frame command pool" + suffix);
    VkCommandBufferAllocateInfo allocInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    allocInfo.commandPool = frame.pool;
    allocInfo.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    allocInfo.commandBufferCount = 1;
    VK_CHECK(vkAllocateCommandBuffers(context.device(), &allocInfo, &frame.cmd));
    context.setName(frame.cmd, VK_OBJECT_TYPE_COMMAND_BUFFER, "frame commands" + suffix);
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VK_CHECK(vkCreateFence(context.device(), &fenceInfo, nullptr, &frame.fence));
    context.setName(frame.fence, VK_OBJECT_TYPE_FENCE, "frame fence" + suffix);
    VkSemaphoreCreateInfo semaphoreInfo{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VK_CHECK(vkCreateSemaphore(context.device(), &semaphoreInfo, nullptr, &frame.imageAvailable));
    context.setName(frame.imageAvailable, VK_OBJECT_TYPE_SEMAPHORE, "image available" + suffix);
    frame.timer = gpu::GpuTimer(context, kMaxTimerScopes * desc_.maxViewRegions, "pass timings" + suffix);
    frame.statistics = gpu::PipelineStatisticsQueries(context, kStatisticsScopes, "pass statistics" + suffix);
  }
}

Renderer::~Renderer() {
  vkDeviceWaitIdle(context_.device());
  retired_.collectAll();
  features_.clear();
  destroyHandles();
}

// Null handles are skipped by the destroy calls: also what a constructor that failed half-way needs.
void Renderer::destroyHandles() noexcept {
  for (FrameResources& frame : frames_) {
    vkDestroySemaphore(context_.device(), frame.imageAvailable, nullptr);
    vkDestroyFence(context_.device(), frame.fence, nullptr);
    vkDestroyCommandPool(context_.device(), frame.pool, nullptr);
  }
  vkDestroyDescriptorPool(context_.device(), descriptorPool_, nullptr);
}

void Renderer::createSceneDescriptors() {
  depthSampler_ = gpu::createClampedSampler(context_, VK_FILTER_NEAREST, "scene depth sampler");

  sceneSetLayout_ = gpu::DescriptorSetLayout(
      context_, {"scene set layout",
                 {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
                  {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
                  {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}},
                 {}});
  desc_.formats.sceneSetLayout = sceneSetLayout_.handle();

  VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 3};
  VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  poolInfo.maxSets = 1;
  poolInfo.poolSizeCount = 1;
  poolInfo.pPoolSizes = &size;
  VK_CHECK(vkCreateDescriptorPool(context_.device(), &poolInfo, nullptr, &descriptorPool_));
  context_.setName(descriptorPool_, VK_OBJECT_TYPE_DESCRIPTOR_POOL, "scene descriptor pool");
  VkDescriptorSetAllocateInfo allocInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  allocInfo.descriptorPool = descriptorPool_;
  allocInfo.descriptorSetCount = 1;
  const VkDescriptorSetLayout setLayout = sceneSetLayout_.handle();
  allocInfo.pSetLayouts = &setLayout;
  VK_CHECK(vkAllocateDescriptorSets(context_.device(), &allocInfo, &sceneSet_));
  context_.setName(sceneSet_, VK_OBJECT_TYPE_DESCRIPTOR_SET, "scene set");
}

// Points the scene set at the current depth target (called with the GPU idle).
void Renderer::updateSceneDescriptors() {
  const VkDescriptorImageInfo images[3] = {{depthSampler_.get(), depth_.view(), kFinalDepthLayout},
                                           {depthSampler_.get(), visibility_.view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
                                           {depthSampler_.get(), hitOffset_.view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}};
  VkWriteDescriptorSet writes[3] = {};
  for (std::uint32_t i = 0; i < 3; ++i) {
    writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    writes[i].dstSet = sceneSet_;
    writes[i].dstBinding = i;
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    writes[i].pImageInfo = &images[i];
  }
  vkUpdateDescriptorSets(context_.device(), 3, writes, 0, nullptr);
}

void Renderer::createTargets() {
  gpu::ImageDesc colorDesc;
  colorDesc.format = desc_.formats.color;
  colorDesc.extent = {extent_.width, extent_.height, 1};
  // Transfer destination: an overlay may copy an image over the frame (e.g. a CPU-made heat map).
  colorDesc.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                    VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
  colorDesc.name = "scene colour";
  color_ = gpu::Image(context_, colorDesc);
  gpu::ImageDesc depthDesc;
  depthDesc.format = desc_.formats.depth;
  depthDesc.extent = colorDesc.extent;
  depthDesc.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                    VK_IMAGE_USAGE_SAMPLED_BIT;
  depthDesc.name = "scene depth";
  depth_ = gpu::Image(context_, depthDesc);
  gpu::ImageDesc visibilityDesc;
  visibilityDesc.format = desc_.formats.visibility;
  visibilityDesc.extent = colorDesc.extent;
  visibilityDesc.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                         VK_IMAGE_USAGE_SAMPLED_BIT;
  visibilityDesc.name = "scene visibility";
  visibility_ = gpu::Image(context_, visibilityDesc);
  gpu::ImageDesc hitOffsetDesc = visibilityDesc;
  hitOffsetDesc.format = desc_.formats.hitOffset;
  hitOffsetDesc.name = "scene hit offsets";
  hitOffset_ = gpu::Image(context_, hitOffsetDesc);
  // Give the targets defined layouts so a read-back before the first frame is valid.
  context_.submitAndWait([&](VkCommandBuffer cmd) {
    gpu::imageBarrier(cmd, color_.handle(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE,
                      VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_NONE);
    gpu::imageBarrier(cmd, depth_.handle(), VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                      kFinalDepthLayout, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE,
                      VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_NONE);
    prepassColorBarrier(cmd, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_2_NONE,
                        VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_NONE);
  });
  updateSceneDescriptors();
}

Status Renderer::addFeature(std::unique_ptr<RenderFeature> feature) {
  const std::uint32_t slots = desc_.framesInFlight * desc_.maxViewRegions;
  ENGINE_TRY(feature->initialize(context_, desc_.formats, slots).withContext(std::string(feature->name())));
  features_.push_back(std::move(feature));
  return {};
}

std::vector<Renderer::ShaderReload> Renderer::reloadShaders() {
  context_.waitIdle();  // no frame in flight uses the pipelines being replaced
  retired_.collectAll();
  std::vector<ShaderReload> results;
  for (auto& feature : features_) {
    Status status = feature->reloadShaders();
    if (!status) log::warn("reloading the shaders of {}: {}", feature->name(), status.error().message);
    results.push_back({std::string(feature->name()), std::move(status)});
  }
  return results;
}

Status Renderer::createAllPipelines() {
  for (auto& feature : features_)
    if (Status status = feature->createAllPipelines(); !status)
      return makeError(std::string(feature->name()) + ": " + status.error().message);
  return {};
}

// Features draw the entities with a WorldTransform; a program that places its entities by
// Transform (and Parent) and never runs scene::updateWorldTransforms drew an empty frame without
// a word. Said once; O(1) a frame (the components' counts), so a registry updated in part is not
// caught.
void Renderer::warnIfWorldTransformsMissing(const ecs::Registry& registry) {
  if (worldTransformsWarned_ || registry.size<scene::Transform>() == 0 || registry.size<scene::WorldTransform>() != 0)
    return;
  worldTransformsWarned_ = true;
  log::warn("renderer: {} entities have a Transform and none a WorldTransform, which is what the features draw: "
            "call engine::scene::updateWorldTransforms(registry) before renderFrame",
            registry.size<scene::Transform>());
}

void Renderer::resize(VkExtent2D extent) {
  if (extent.width == 0 || extent.height == 0) return;
  if (extent.width == extent_.width && extent.height == extent_.height) return;
  checkExtent(context_, extent, "Renderer::resize");
  context_.waitIdle();
  retired_.collectAll();
  extent_ = extent;
  workCounted_ = false;  // the counts were of the old size
  createTargets();
  if (pyramid_) pyramid_->resize(context_, extent_);
}

// Camera-relative (GpuScene::setOrigin): the view matrix of world space shifted by -origin, made in
// double (CameraView::viewFrom), so that its translation is ~0 instead of the rounded product of a far eye.
void Renderer::writeFrameGlobals(std::uint32_t slot, const CameraView& camera) {
  const glm::dvec3 origin = scene_.origin();
  const glm::dmat4 view = camera.viewFrom(origin);
  shader::FrameGlobals globals{};
  globals.view = glm::mat4(view);
  globals.proj = camera.proj;
  globals.viewProj = glm::mat4(glm::dmat4(camera.proj) * view);
  globals.invView = glm::mat4(glm::inverse(view));
  globals.invProj = glm::inverse(camera.proj);
  // The homogeneous eye (CameraView::eye): a point shifted like the world, or a direction as it is.
  const glm::vec4 eye = camera.eye();
  globals.cameraPosition = eye.w == 0.0f ? eye : glm::vec4(glm::vec3(glm::dvec3(camera.position) - origin), 1.0f);
  globals.lightDirection = glm::vec4(glm::normalize(desc_.lightDirection), desc_.lightIntensity);
  globals.lightColor = glm::vec4(1.0f, 0.97f, 0.92f, desc_.ambient);
  globals.viewport = glm::vec4(float(extent_.width), float(extent_.height), 1.0f / float(extent_.width),
                               1.0f / float(extent_.height));
  frameGlobals_.upload(slot, &globals, sizeof(globals));
}

void Renderer::collectTimings(FrameResources& frame) {
  if (!frame.submitted || !frame.timed) return;
  auto timings = frame.timer.results();
  if (!timings.empty()) lastTimings_ = std::move(timings);
  auto statistics = frame.statistics.results();
  if (!statistics.empty()) lastStatistics_ = std::move(statistics);
}

// Zeroes the per-pixel work counters and the totals after them for this frame (after every
// earlier frame's use of them).
VkDeviceAddress Renderer::prepareWorkCounters(VkCommandBuffer cmd) {
  workCounters_.ensure(context_, extent_, retired_, frameNumber_);
  gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  vkCmdFillBuffer(cmd, workCounters_.handle(), 0, VK_WHOLE_SIZE, 0);
  gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  workCounted_ = true;
  return workCounters_.address();
}

// The frame's fence is reset only right before its submit: a frame that fails while it is recorded
// (a feature's upload runs out of GPU memory, a driver call fails) leaves the fence signalled and
// nothing of it submitted, so the next frame on this slot neither waits forever nor sees half a
// frame. The error still reaches the caller; the renderer stays usable.
bool Renderer::renderFrame(const ecs::Registry& registry, const CameraView& camera, const FrameSettings& settings) {
  warnIfWorldTransformsMissing(registry);
  const auto slot = static_cast<std::uint32_t>(frameNumber_ % desc_.framesInFlight);
  FrameResources& frame = frames_[slot];
  if (frame.submitted) {
    VK_CHECK(vkWaitForFences(context_.device(), 1, &frame.fence, VK_TRUE, UINT64_MAX));
    collectTimings(frame);
  }
  retired_.collect(frameNumber_, desc_.framesInFlight);  // frames up to frameNumber_ - framesInFlight are done

  std::uint32_t imageIndex = 0;
  if (settings.swapchain && !settings.swapchain->acquire(frame.imageAvailable, imageIndex)) return false;

  try {
    recordFrame(frame, slot, registry, camera, settings, imageIndex);
  } catch (...) {
    abandonFrame(frame, settings.swapchain, imageIndex);
    throw;
  }
  // What the features retired this frame with an already-completed last use goes now, not a frame later.
  retired_.collect(frameNumber_, desc_.framesInFlight);
  submitFrame(frame, settings.swapchain, imageIndex);
  frame.timed = true;
  ++frameNumber_;
  if (settings.swapchain) return settings.swapchain->present(imageIndex);
  return true;
}

void Renderer::recordFrame(FrameResources& frame, std::uint32_t slot, const ecs::Registry& registry,
                           const CameraView& camera, const FrameSettings& settings, std::uint32_t imageIndex) {
  VK_CHECK(vkResetCommandPool(context_.device(), frame.pool, 0));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(frame.cmd, &begin));

  frame.timer.reset(frame.cmd);
  frame.statistics.reset(frame.cmd);
  frame.timer.begin(frame.cmd, "frame");
  scene_.setOrigin(glm::dvec3(camera.position));
  writeFrameGlobals(slot, camera);
  const VkDeviceAddress workCounters = settings.countWork ? prepareWorkCounters(frame.cmd) : 0;
  FrameContext context{frame.cmd, registry, context_,    scene_,           camera,
                       extent_,   slot,     frameNumber_, settings.debugView, workCounters};
  context.framesInFlight = desc_.framesInFlight;
  context.frameGlobals = frameGlobals_.address(slot);
  if (workCounters) context.workTotals = workCounters + workCounters_.pixelBytes();
  context.droppedObjects = &droppedObjects_;
  context.retired = &retired_;
  if (settings.regions.empty()) {
    recordRegion(frame, context, ViewRegion{{{0, 0}, extent_}, {}}, 0);
  } else {
    if (settings.regions.size() > desc_.maxViewRegions && !reportedTooManyRegions_) {
      log::error("renderFrame: {} view regions, the renderer draws at most {} (RendererDesc::maxViewRegions)",
                 settings.regions.size(), desc_.maxViewRegions);
      reportedTooManyRegions_ = true;
    }
    const std::size_t count = std::min<std::size_t>(settings.regions.size(), desc_.maxViewRegions);
    for (std::size_t i = 0; i < count; ++i) recordRegion(frame, context, settings.regions[i], std::uint32_t(i));
  }
  if (settings.overlay) {
    frame.timer.begin(frame.cmd, "ui");
    settings.overlay->record(frame.cmd, color_, slot);
    frame.timer.end(frame.cmd);
  }
  // The finished frame waits in TRANSFER_SRC for the blit to the window or a read-back.
  gpu::imageBarrier(frame.cmd, color_.handle(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                    VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                    VK_ACCESS_2_TRANSFER_READ_BIT);
  if (settings.swapchain) recordPresentBlit(frame.cmd, *settings.swapchain, imageIndex);
  frame.timer.end(frame.cmd);
  VK_CHECK(vkEndCommandBuffer(frame.cmd));
}

void Renderer::submitFrame(FrameResources& frame, gpu::Swapchain* swapchain, std::uint32_t imageIndex) {
  VkCommandBufferSubmitInfo cmdInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
  cmdInfo.commandBuffer = frame.cmd;
  VkSemaphoreSubmitInfo waitInfo{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
  VkSemaphoreSubmitInfo signalInfo{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
  VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
  submit.commandBufferInfoCount = 1;
  submit.pCommandBufferInfos = &cmdInfo;
  if (swapchain) {
    waitInfo.semaphore = frame.imageAvailable;
    waitInfo.stageMask = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT;
    signalInfo.semaphore = swapchain->renderFinished(imageIndex);
    signalInfo.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    submit.waitSemaphoreInfoCount = 1;
    submit.pWaitSemaphoreInfos = &waitInfo;
    submit.signalSemaphoreInfoCount = 1;
    submit.pSignalSemaphoreInfos = &signalInfo;
  }
  VK_CHECK(vkResetFences(context_.device(), 1, &frame.fence));
  VK_CHECK(vkQueueSubmit2(context_.queue(), 1, &submit, frame.fence));
  frame.submitted = true;
}

// A frame whose recording threw: its commands are dropped (the next frame resets the pool) and its
// fence was never reset. The slot's earlier submission was waited for and its timings collected,
// so the slot counts as free. With a window, the acquired image still has to be presented (and its
// semaphore waited on) or the swapchain runs out of images: it shows the last finished frame again
// (the colour target holds it, in TRANSFER_SRC, since the failed commands never ran).
void Renderer::abandonFrame(FrameResources& frame, gpu::Swapchain* swapchain, std::uint32_t imageIndex) {
  frame.submitted = false;
  if (!swapchain) return;
  VK_CHECK(vkResetCommandPool(context_.device(), frame.pool, 0));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(frame.cmd, &begin));
  recordPresentBlit(frame.cmd, *swapchain, imageIndex);
  VK_CHECK(vkEndCommandBuffer(frame.cmd));
  submitFrame(frame, swapchain, imageIndex);
  frame.timed = false;  // no timer queries in this submission
  (void)swapchain->present(imageIndex);  // out of date: the next acquire says so
}

std::vector<std::string> Renderer::takeDroppedObjects() { return std::exchange(droppedObjects_, {}); }

// One view region: its overrides, the features' prepare with the region's frame slot, its passes.
void Renderer::recordRegion(FrameResources& frame, FrameContext& context, const ViewRegion& region,
                            std::uint32_t index) {
  const VkRect2D rect = clipToFrame(region.rect, extent_);
  // The first region's passes clear the whole frame (pixels outside every region are background).
  if ((rect.extent.width == 0 || rect.extent.height == 0) && index > 0) return;
  if (region.apply) region.apply();
  FrameContext regionContext = context;
  regionContext.frameSlot = context.frameSlot * desc_.maxViewRegions + index;
  regionContext.viewRegion = rect;
  regionContext.viewRegionIndex = index;
  regionContext.timer = &frame.timer;
  scene_.beginFrame();
  frame.timer.setScopeSuffix(regionSuffix(index));  // the features' scopes too
  frame.timer.begin(frame.cmd, "prepare");
  for (auto& feature : features_) feature->prepare(regionContext);
  frame.timer.end(frame.cmd);
  scene_.upload(regionContext.frameSlot);
  recordScenePasses(frame, regionContext, rect, index);
  frame.timer.setScopeSuffix({});
}

void Renderer::recordScenePasses(FrameResources& frame, FrameContext& context, VkRect2D rect, std::uint32_t region) {
  VkCommandBuffer cmd = frame.cmd;
  const bool first = region == 0;
  // Earlier frames (and read-backs) may still use the targets: wait for everything before them.
  // Later regions keep what the earlier ones drew (their old layouts, not UNDEFINED).
  gpu::imageBarrier(cmd, color_.handle(), VK_IMAGE_ASPECT_COLOR_BIT,
                    first ? VK_IMAGE_LAYOUT_UNDEFINED : VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                    VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                    VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT);
  gpu::imageBarrier(cmd, depth_.handle(), VK_IMAGE_ASPECT_DEPTH_BIT, first ? VK_IMAGE_LAYOUT_UNDEFINED : kFinalDepthLayout,
                    VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                    VK_ACCESS_2_MEMORY_WRITE_BIT | VK_ACCESS_2_MEMORY_READ_BIT,
                    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
  prepassColorBarrier(cmd, first ? VK_IMAGE_LAYOUT_UNDEFINED : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                      VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                      VK_ACCESS_2_MEMORY_WRITE_BIT | VK_ACCESS_2_MEMORY_READ_BIT,
                      VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);

  // The frame globals (camera) are the frame's; the objects are the region's.
  const std::uint32_t frameInFlight = context.frameSlot / desc_.maxViewRegions;
  PassContext pass{cmd, context, Pass::DepthPrepass, frameGlobals_.address(frameInFlight),
                   scene_.address(context.frameSlot), sceneSet_, frame.timer};
  frame.timer.begin(cmd, "depth prepass");
  if (first) frame.statistics.begin(cmd, "depth prepass");
  recordDepthPrepass(pass, rect, first);
  if (first) frame.statistics.end(cmd);
  frame.timer.end(cmd);

  // The shading pass tests against the prepass depth and may sample it: make the writes visible
  // and switch to the read-only layout, which allows both at once.
  gpu::imageBarrier(cmd, depth_.handle(), VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                    kFinalDepthLayout,
                    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT |
                        VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
  prepassColorBarrier(cmd, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                      VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
  // Storage writes of prepass shaders (e.g. per-pixel counters) are visible to shading shaders.
  gpu::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
  pass.pass = Pass::Opaque;
  frame.timer.begin(cmd, "opaque");
  if (first) frame.statistics.begin(cmd, "opaque");
  recordOpaquePass(pass, rect, first);
  if (first) frame.statistics.end(cmd);
  frame.timer.end(cmd);

  if (std::none_of(features_.begin(), features_.end(), [](const auto& f) { return f->hasTransparentDraws(); })) return;
  pass.pass = Pass::Transparent;
  frame.timer.begin(cmd, "transparent");
  recordTransparentPass(pass, rect);
  frame.timer.end(cmd);
}

// `first`: the first region's pass clears the whole frame; a later one clears only its rectangle.
// With an early depth stage (RenderFeature::usesEarlyDepth) the prepass is two rendering instances:
// the early draws, then (their depth, visibility and storage writes made visible) the fix-up and
// every feature's ordinary prepass draws.
void Renderer::recordDepthPrepass(PassContext& pass, VkRect2D rect, bool first) {
  const bool early = std::any_of(features_.begin(), features_.end(), [](const auto& f) { return f->usesEarlyDepth(); });
  beginPrepassRendering(pass.cmd, rect, first, VK_ATTACHMENT_LOAD_OP_CLEAR);
  if (early) {
    for (auto& feature : features_)
      if (feature->usesEarlyDepth()) feature->recordEarlyDepth(pass);
    vkCmdEndRendering(pass.cmd);
    barrierBetweenPrepassStages(pass.cmd);
    beginPrepassRendering(pass.cmd, rect, first, VK_ATTACHMENT_LOAD_OP_LOAD);
    for (auto& feature : features_)
      if (feature->usesEarlyDepth()) feature->recordEarlyDepthResolve(pass);
  }
  for (auto& feature : features_) feature->recordPass(pass);
  vkCmdEndRendering(pass.cmd);
  if (std::any_of(features_.begin(), features_.end(), [](const auto& f) { return f->usesOcclusionCulling(); }))
    recordOcclusionPhase2(pass, rect, first);
}

// Occlusion culling's second phase: the pyramid of what phase 1 drew, the features' late culling
// against it, and their phase-2 draws over phase 1's depth and visibility (LOAD). Without a
// pyramid (its shader failed to load) the features get an empty view and must cull nothing.
void Renderer::recordOcclusionPhase2(PassContext& pass, VkRect2D rect, bool first) {
  DepthPyramid* pyramid = ensurePyramid();
  if (pyramid) pyramid->record(pass.cmd, depth_);
  const DepthPyramidView view = pyramid ? pyramid->view() : DepthPyramidView{};
  for (auto& feature : features_)
    if (feature->usesOcclusionCulling()) feature->recordLateCulling(pass, view);
  barrierBetweenPrepassStages(pass.cmd);
  beginPrepassRendering(pass.cmd, rect, first, VK_ATTACHMENT_LOAD_OP_LOAD);
  pass.occlusionLate = true;
  for (auto& feature : features_)
    if (feature->usesOcclusionCulling()) feature->recordPass(pass);
  pass.occlusionLate = false;
  vkCmdEndRendering(pass.cmd);
}

DepthPyramid* Renderer::ensurePyramid() {
  if (pyramid_ || !pyramidFailure_.empty()) return pyramid_.get();
  auto created = DepthPyramid::create(context_);
  if (!created) {
    pyramidFailure_ = "depth pyramid: " + created.error().message;
    log::error("{}; occlusion culling culls nothing", pyramidFailure_);
    return nullptr;
  }
  pyramid_ = std::make_unique<DepthPyramid>(std::move(*created));
  pyramid_->resize(context_, extent_);
  return pyramid_.get();
}

void Renderer::beginPrepassRendering(VkCommandBuffer cmd, VkRect2D rect, bool first, VkAttachmentLoadOp load) {
  VkRenderingAttachmentInfo depth = depthAttachment(depth_, load, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
  VkRenderingAttachmentInfo colors[2] = {};  // RendererFormats::prepassColorFormats: visibility, hit offset
  const gpu::Image* images[2] = {&visibility_, &hitOffset_};
  for (std::uint32_t i = 0; i < 2; ++i) {
    colors[i].sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO;
    colors[i].imageView = images[i]->view();
    colors[i].imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    colors[i].loadOp = load;
    colors[i].storeOp = VK_ATTACHMENT_STORE_OP_STORE;  // cleared to zero: background, offset 0
  }
  VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
  info.renderArea = first ? VkRect2D{{0, 0}, extent_} : rect;
  info.layerCount = 1;
  info.colorAttachmentCount = 2;
  info.pColorAttachments = colors;
  info.pDepthAttachment = &depth;
  vkCmdBeginRendering(cmd, &info);
  setViewportAndScissor(cmd, extent_, rect);
}

// The same barrier on both colour attachments of the prepass (the visibility and the hit offsets).
void Renderer::prepassColorBarrier(VkCommandBuffer cmd, VkImageLayout from, VkImageLayout to, VkPipelineStageFlags2 srcStage,
                                   VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess) {
  for (const gpu::Image* image : {&visibility_, &hitOffset_})
    gpu::imageBarrier(cmd, image->handle(), VK_IMAGE_ASPECT_COLOR_BIT, from, to, srcStage, srcAccess, dstStage, dstAccess);
}

// Between the early depth stage and the rest of the prepass: the attachments are written by one
// rendering instance and loaded by the next, and the fix-up reads what the early fragment shaders
// wrote to storage.
void Renderer::barrierBetweenPrepassStages(VkCommandBuffer cmd) {
  constexpr VkPipelineStageFlags2 tests =
      VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
  gpu::memoryBarrier(cmd, tests | VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                     VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
                         VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     tests | VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                     VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                         VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
                         VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

void Renderer::recordOpaquePass(PassContext& pass, VkRect2D rect, bool first) {
  beginShadingRendering(pass.cmd, rect, first ? VkRect2D{{0, 0}, extent_} : rect, VK_ATTACHMENT_LOAD_OP_CLEAR);
  for (auto& feature : features_) feature->recordPass(pass);
  vkCmdEndRendering(pass.cmd);
}

// Blended surfaces over the finished opaque frame: after every feature's shading (an SDF object's
// resolve would otherwise paint over a blended surface drawn before it), against the prepass
// depth, which none of them is in.
void Renderer::recordTransparentPass(PassContext& pass, VkRect2D rect) {
  // Blending reads what the shading pass wrote.
  gpu::memoryBarrier(pass.cmd, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                     VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
  beginShadingRendering(pass.cmd, rect, rect, VK_ATTACHMENT_LOAD_OP_LOAD);
  for (auto& feature : features_)
    if (feature->hasTransparentDraws()) feature->recordTransparent(pass);
  vkCmdEndRendering(pass.cmd);
}

// The colour target (cleared to the clear colour, or loaded) with the prepass depth, read-only.
void Renderer::beginShadingRendering(VkCommandBuffer cmd, VkRect2D rect, VkRect2D renderArea,
                                     VkAttachmentLoadOp colorLoad) {
  VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  color.imageView = color_.view();
  color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  color.loadOp = colorLoad;
  color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  std::memcpy(color.clearValue.color.float32, &desc_.clearColor, sizeof(float) * 4);
  VkRenderingAttachmentInfo depth = depthAttachment(depth_, VK_ATTACHMENT_LOAD_OP_LOAD, kFinalDepthLayout);
  VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
  info.renderArea = renderArea;
  info.layerCount = 1;
  info.colorAttachmentCount = 1;
  info.pColorAttachments = &color;
  info.pDepthAttachment = &depth;
  vkCmdBeginRendering(cmd, &info);
  setViewportAndScissor(cmd, extent_, rect);
}

void Renderer::recordPresentBlit(VkCommandBuffer cmd, gpu::Swapchain& swapchain, std::uint32_t imageIndex) {
  VkImage target = swapchain.image(imageIndex);
  gpu::imageBarrier(cmd, target, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_NONE,
                    VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  const VkExtent2D dst = swapchain.extent();
  VkImageBlit region{};
  region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.srcOffsets[1] = {std::int32_t(extent_.width), std::int32_t(extent_.height), 1};
  region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.dstOffsets[1] = {std::int32_t(dst.width), std::int32_t(dst.height), 1};
  vkCmdBlitImage(cmd, color_.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target,
                 VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region, VK_FILTER_LINEAR);
  gpu::imageBarrier(cmd, target, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                    VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                    VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE);
}

void Renderer::finish() {
  context_.waitIdle();
  retired_.collectAll();
  if (frameNumber_ == 0) return;
  collectTimings(frames_[(frameNumber_ - 1) % desc_.framesInFlight]);
}

std::vector<std::uint8_t> Renderer::readbackColor() {
  finish();
  return gpu::readbackImage(context_, color_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
}

Expected<std::vector<glm::vec4>> Renderer::readbackColorFloat() {
  const VkFormat format = desc_.formats.color;
  if (format != VK_FORMAT_R32G32B32A32_SFLOAT && format != VK_FORMAT_R16G16B16A16_SFLOAT)
    return makeError("readbackColorFloat: the colour target is not a float format (VkFormat " +
                     std::to_string(int(format)) + "); create the renderer with R32G32B32A32_SFLOAT or "
                     "R16G16B16A16_SFLOAT");
  finish();
  const auto bytes = gpu::readbackImage(context_, color_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  std::vector<glm::vec4> pixels(std::size_t(extent_.width) * extent_.height);
  if (format == VK_FORMAT_R32G32B32A32_SFLOAT) {
    std::memcpy(pixels.data(), bytes.data(), pixels.size() * sizeof(glm::vec4));
    return pixels;
  }
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    std::uint16_t half[4];
    std::memcpy(half, bytes.data() + i * sizeof(half), sizeof(half));
    for (int c = 0; c < 4; ++c) pixels[i][c] = glm::unpackHalf1x16(half[c]);
  }
  return pixels;
}

std::vector<std::uint32_t> Renderer::readbackWorkCounters() {
  finish();
  if (!workCounted_) return {};
  const auto bytes = gpu::readbackBuffer(context_, workCounters_.buffer());
  std::vector<std::uint32_t> counts(workCounters_.pixelBytes() / sizeof(std::uint32_t));
  std::memcpy(counts.data(), bytes.data(), counts.size() * sizeof(std::uint32_t));
  return counts;
}

shader::WorkTotals Renderer::readbackWorkTotals() {
  finish();
  shader::WorkTotals totals{};
  if (!workCounted_) return totals;
  const auto bytes = gpu::readbackBuffer(context_, workCounters_.buffer());
  std::memcpy(&totals, bytes.data() + workCounters_.pixelBytes(), sizeof(totals));
  return totals;
}

std::vector<glm::uvec2> Renderer::readbackVisibility() {
  finish();
  const auto bytes = gpu::readbackImage(context_, visibility_, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  std::vector<glm::uvec2> ids(bytes.size() / sizeof(glm::uvec2));
  std::memcpy(ids.data(), bytes.data(), ids.size() * sizeof(glm::uvec2));
  return ids;
}

std::vector<float> Renderer::readbackDepthPyramid() {
  finish();
  if (!pyramid_) return {};
  const auto bytes = gpu::readbackBuffer(context_, pyramid_->buffer());
  std::vector<float> texels(bytes.size() / sizeof(float));
  std::memcpy(texels.data(), bytes.data(), texels.size() * sizeof(float));
  return texels;
}

std::vector<float> Renderer::readbackDepth() {
  finish();
  const auto bytes = gpu::readbackImage(context_, depth_, kFinalDepthLayout);
  std::vector<float> depth(bytes.size() / sizeof(float));
  std::memcpy(depth.data(), bytes.data(), depth.size() * sizeof(float));
  return depth;
}

}  // namespace engine::render
