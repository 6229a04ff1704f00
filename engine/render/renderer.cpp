#include "engine/render/renderer.h"

#include <cstring>

#include "engine/core/log.h"
#include "engine/gpu/context.h"
#include "engine/gpu/swapchain.h"
#include "engine/gpu/vk_check.h"

namespace engine::render {
namespace {

constexpr std::uint32_t kMaxTimerScopes = 32;

VkRenderingAttachmentInfo depthAttachment(const gpu::Image& depth, VkAttachmentLoadOp load) {
  VkRenderingAttachmentInfo info{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  info.imageView = depth.view();
  info.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  info.loadOp = load;
  info.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  info.clearValue.depthStencil = {0.0f, 0};  // reverse-Z: 0 is infinitely far
  return info;
}

void setViewportAndScissor(VkCommandBuffer cmd, VkExtent2D extent) {
  const VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
  const VkRect2D scissor{{0, 0}, extent};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
}

}  // namespace

Renderer::Renderer(const gpu::Context& context, const RendererDesc& desc, VkExtent2D extent)
    : context_(context),
      desc_(desc),
      extent_(extent),
      scene_(context, desc.framesInFlight),
      frameGlobals_(context, desc.framesInFlight, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "frame globals") {
  createTargets();
  frames_.resize(desc.framesInFlight);
  for (std::uint32_t i = 0; i < desc.framesInFlight; ++i) {
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
    frame.timer = gpu::GpuTimer(context, kMaxTimerScopes, "pass timings" + suffix);
  }
}

Renderer::~Renderer() {
  vkDeviceWaitIdle(context_.device());
  features_.clear();
  for (FrameResources& frame : frames_) {
    vkDestroySemaphore(context_.device(), frame.imageAvailable, nullptr);
    vkDestroyFence(context_.device(), frame.fence, nullptr);
    vkDestroyCommandPool(context_.device(), frame.pool, nullptr);
  }
}

void Renderer::createTargets() {
  gpu::ImageDesc colorDesc;
  colorDesc.format = desc_.formats.color;
  colorDesc.extent = {extent_.width, extent_.height, 1};
  colorDesc.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                    VK_IMAGE_USAGE_SAMPLED_BIT;
  colorDesc.name = "scene colour";
  color_ = gpu::Image(context_, colorDesc);
  gpu::ImageDesc depthDesc;
  depthDesc.format = desc_.formats.depth;
  depthDesc.extent = colorDesc.extent;
  depthDesc.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                    VK_IMAGE_USAGE_SAMPLED_BIT;
  depthDesc.name = "scene depth";
  depth_ = gpu::Image(context_, depthDesc);
  // Give the targets defined layouts so a read-back before the first frame is valid.
  context_.submitAndWait([&](VkCommandBuffer cmd) {
    gpu::imageBarrier(cmd, color_.handle(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE,
                      VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_NONE);
    gpu::imageBarrier(cmd, depth_.handle(), VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE,
                      VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_NONE);
  });
}

Status Renderer::addFeature(std::unique_ptr<RenderFeature> feature) {
  ENGINE_TRY(feature->initialize(context_, desc_.formats, desc_.framesInFlight).withContext(std::string(feature->name())));
  features_.push_back(std::move(feature));
  return {};
}

void Renderer::resize(VkExtent2D extent) {
  if (extent.width == 0 || extent.height == 0) return;
  if (extent.width == extent_.width && extent.height == extent_.height) return;
  context_.waitIdle();
  extent_ = extent;
  createTargets();
}

void Renderer::writeFrameGlobals(std::uint32_t slot, const CameraView& camera) {
  shader::FrameGlobals globals{};
  globals.view = camera.view;
  globals.proj = camera.proj;
  globals.viewProj = camera.proj * camera.view;
  globals.invView = glm::inverse(camera.view);
  globals.invProj = glm::inverse(camera.proj);
  globals.cameraPosition = glm::vec4(camera.position, camera.znear);
  globals.lightDirection = glm::vec4(glm::normalize(desc_.lightDirection), desc_.lightIntensity);
  globals.lightColor = glm::vec4(1.0f, 0.97f, 0.92f, desc_.ambient);
  globals.viewport = glm::vec4(float(extent_.width), float(extent_.height), 1.0f / float(extent_.width),
                               1.0f / float(extent_.height));
  frameGlobals_.upload(slot, &globals, sizeof(globals));
}

void Renderer::collectTimings(FrameResources& frame) {
  if (!frame.submitted) return;
  auto timings = frame.timer.results();
  if (!timings.empty()) lastTimings_ = std::move(timings);
}

bool Renderer::renderFrame(const ecs::Registry& registry, const CameraView& camera, const FrameSettings& settings) {
  const auto slot = static_cast<std::uint32_t>(frameNumber_ % desc_.framesInFlight);
  FrameResources& frame = frames_[slot];
  if (frame.submitted) {
    VK_CHECK(vkWaitForFences(context_.device(), 1, &frame.fence, VK_TRUE, UINT64_MAX));
    collectTimings(frame);
  }

  std::uint32_t imageIndex = 0;
  if (settings.swapchain && !settings.swapchain->acquire(frame.imageAvailable, imageIndex)) return false;

  VK_CHECK(vkResetFences(context_.device(), 1, &frame.fence));
  VK_CHECK(vkResetCommandPool(context_.device(), frame.pool, 0));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(frame.cmd, &begin));

  scene_.beginFrame();
  writeFrameGlobals(slot, camera);
  FrameContext context{registry, context_, scene_, camera, extent_, slot, frameNumber_, settings.debugView};
  for (auto& feature : features_) feature->prepare(context);
  scene_.upload(slot);

  frame.timer.reset(frame.cmd);
  frame.timer.begin(frame.cmd, "frame");
  recordScenePasses(frame, context);
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

  VkCommandBufferSubmitInfo cmdInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
  cmdInfo.commandBuffer = frame.cmd;
  VkSemaphoreSubmitInfo waitInfo{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
  VkSemaphoreSubmitInfo signalInfo{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
  VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
  submit.commandBufferInfoCount = 1;
  submit.pCommandBufferInfos = &cmdInfo;
  if (settings.swapchain) {
    waitInfo.semaphore = frame.imageAvailable;
    waitInfo.stageMask = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT;
    signalInfo.semaphore = settings.swapchain->renderFinished(imageIndex);
    signalInfo.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    submit.waitSemaphoreInfoCount = 1;
    submit.pWaitSemaphoreInfos = &waitInfo;
    submit.signalSemaphoreInfoCount = 1;
    submit.pSignalSemaphoreInfos = &signalInfo;
  }
  VK_CHECK(vkQueueSubmit2(context_.queue(), 1, &submit, frame.fence));
  frame.submitted = true;
  ++frameNumber_;
  if (settings.swapchain) return settings.swapchain->present(imageIndex);
  return true;
}

void Renderer::recordScenePasses(FrameResources& frame, FrameContext& context) {
  VkCommandBuffer cmd = frame.cmd;
  // Earlier frames (and read-backs) may still use the targets: wait for everything before them.
  gpu::imageBarrier(cmd, color_.handle(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                    VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                    VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT);
  gpu::imageBarrier(cmd, depth_.handle(), VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                    VK_ACCESS_2_MEMORY_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);

  PassContext pass{cmd, context, Pass::DepthPrepass, frameGlobals_.address(context.frameSlot),
                   scene_.address(context.frameSlot), frame.timer};
  frame.timer.begin(cmd, "depth prepass");
  recordDepthPrepass(pass);
  frame.timer.end(cmd);

  // The shading pass tests against the prepass depth: make its writes visible.
  gpu::imageBarrier(cmd, depth_.handle(), VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
  pass.pass = Pass::Opaque;
  frame.timer.begin(cmd, "opaque");
  recordOpaquePass(pass);
  frame.timer.end(cmd);
}

void Renderer::recordDepthPrepass(PassContext& pass) {
  VkRenderingAttachmentInfo depth = depthAttachment(depth_, VK_ATTACHMENT_LOAD_OP_CLEAR);
  VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
  info.renderArea = {{0, 0}, extent_};
  info.layerCount = 1;
  info.pDepthAttachment = &depth;
  vkCmdBeginRendering(pass.cmd, &info);
  setViewportAndScissor(pass.cmd, extent_);
  for (auto& feature : features_) feature->recordPass(pass);
  vkCmdEndRendering(pass.cmd);
}

void Renderer::recordOpaquePass(PassContext& pass) {
  VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  color.imageView = color_.view();
  color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  color.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  std::memcpy(color.clearValue.color.float32, &desc_.clearColor, sizeof(float) * 4);
  VkRenderingAttachmentInfo depth = depthAttachment(depth_, VK_ATTACHMENT_LOAD_OP_LOAD);
  VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
  info.renderArea = {{0, 0}, extent_};
  info.layerCount = 1;
  info.colorAttachmentCount = 1;
  info.pColorAttachments = &color;
  info.pDepthAttachment = &depth;
  vkCmdBeginRendering(pass.cmd, &info);
  setViewportAndScissor(pass.cmd, extent_);
  for (auto& feature : features_) feature->recordPass(pass);
  vkCmdEndRendering(pass.cmd);
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
  if (frameNumber_ == 0) return;
  collectTimings(frames_[(frameNumber_ - 1) % desc_.framesInFlight]);
}

std::vector<std::uint8_t> Renderer::readbackColor() {
  finish();
  return gpu::readbackImage(context_, color_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
}

std::vector<float> Renderer::readbackDepth() {
  finish();
  const auto bytes = gpu::readbackImage(context_, depth_, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
  std::vector<float> depth(bytes.size() / sizeof(float));
  std::memcpy(depth.data(), bytes.data(), depth.size() * sizeof(float));
  return depth;
}

}  // namespace engine::render
