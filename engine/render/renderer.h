#pragma once
// The frame loop: frames in flight, the offscreen colour and depth targets, and the passes
//   depth prepass -> opaque -> transparent (blended surfaces, when a feature has any) -> overlay
//   (UI) -> present (blit to the swapchain) or read back.
// Headless and windowed rendering run the same code; a window only adds the final blit.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/gpu/buffer.h"
#include "engine/gpu/deferred_release.h"
#include "engine/gpu/descriptor_set_layout.h"
#include "engine/gpu/gpu_timer.h"
#include "engine/gpu/image.h"
#include "engine/gpu/pipeline_statistics.h"
#include "engine/gpu/pixel_buffer.h"
#include "engine/render/depth_pyramid.h"
#include "engine/render/gpu_scene.h"
#include "engine/render/per_frame_buffer.h"
#include "engine/render/render_feature.h"

namespace engine::gpu {
class Swapchain;
}

namespace engine::render {

// Something drawn over the finished frame in a render pass of its own (the ImGui layer). The
// colour target arrives in COLOR_ATTACHMENT_OPTIMAL and must be left in it.
class OverlayPass {
 public:
  virtual ~OverlayPass() = default;
  virtual void record(VkCommandBuffer cmd, const gpu::Image& color, std::uint32_t frameSlot) = 0;
};

struct RendererDesc {
  RendererFormats formats;
  std::uint32_t framesInFlight = 2;
  glm::vec4 clearColor{0.05f, 0.06f, 0.08f, 1.0f};  // linear
  glm::vec3 lightDirection{0.4f, 0.8f, 0.45f};        // towards the light
  float lightIntensity = 1.0f;
  float ambient = 0.25f;
  // View regions one frame may have (FrameSettings::regions). Features see framesInFlight *
  // maxViewRegions frame slots: each region of each frame in flight has its own per-frame data.
  std::uint32_t maxViewRegions = 4;
};

// A rectangle of the frame drawn with its own version of the scene, same camera: the split-screen
// comparison draws the same entity with a different method (or asset, or normals) in each region.
// Before the features prepare a region, `apply` runs: it changes the components of the registry
// given to renderFrame (e.g. which render method a module's component asks for); each region is then
// drawn by the full pass list with its scissor (the viewport stays full-size, so the projection
// and every pixel's ray are those of the whole frame). A region costs its pixels plus each
// feature's per-frame CPU work (prepare) once more. Pixels outside every region show the clear
// colour and background; later regions draw over earlier ones where they overlap.
struct ViewRegion {
  VkRect2D rect{};                 // pixels, clipped to the frame; empty regions are skipped
  std::function<void()> apply;     // may be empty: the registry as it is
};

struct FrameSettings {
  std::uint32_t debugView = 0;          // DEBUG_VIEW_*
  // Per-pixel work counters: the renderer clears one uint per pixel before the prepass and hands
  // its address to the features (FrameContext::workCounters), which add their root-search work
  // there (field evaluations of the cells and sphere tracers), and frame-wide totals
  // (FrameContext::workTotals: e.g. rays out of steps). Read with readbackWorkCounters() and
  // readbackWorkTotals(). Off by default: features count in pipeline variants of their own (a
  // shader with buffer writes loses early depth rejection on GPUs), so timed frames leave it off.
  bool countWork = false;
  // Empty: one region, the whole frame. At most RendererDesc::maxViewRegions (further ones are
  // not drawn; an error is logged).
  std::vector<ViewRegion> regions;
  gpu::Swapchain* swapchain = nullptr;  // present to it when set
  OverlayPass* overlay = nullptr;
};

class Renderer {
 public:
  // Throws std::invalid_argument naming the value for RendererDesc::framesInFlight outside 1..16 and
  // an extent with a side of 0 or past the device's largest image or framebuffer; gpu::VulkanError
  // when a Vulkan call fails (out of memory for the targets).
  Renderer(const gpu::Context& context, const RendererDesc& desc, VkExtent2D extent);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Initializes the feature with the renderer's formats; the renderer owns it from then on.
  Status addFeature(std::unique_ptr<RenderFeature> feature);
  template <class F>
  F* feature() const {
    for (const auto& f : features_)
      if (auto* typed = dynamic_cast<F*>(f.get())) return typed;
    return nullptr;
  }
  const std::vector<std::unique_ptr<RenderFeature>>& features() const { return features_; }

  // Recreates every feature's pipelines from the SPIR-V on disk (gpu::shaderDirectory()), after
  // waiting for the GPU. A feature that fails keeps its old pipelines and reports why; the frame
  // keeps drawing. One result per feature, in the order they were added.
  struct ShaderReload {
    std::string feature;
    Status status;
  };
  std::vector<ShaderReload> reloadShaders();
  // Compiles every pipeline each feature may draw with (RenderFeature::createAllPipelines), which
  // frames would otherwise compile when they first need one: behind a load screen, or where every
  // pipeline must exist. The first error names its feature.
  Status createAllPipelines();

  // Recreates the targets (waits for the GPU). An extent with a side of 0 (a minimised window)
  // keeps the current targets; one past the device's limits throws std::invalid_argument.
  void resize(VkExtent2D extent);
  VkExtent2D extent() const { return extent_; }

  // Records and submits one frame. Returns false when a swapchain was given and it is out of
  // date (resize it and the renderer, then try again). An exception while the frame is recorded
  // (e.g. gpu::VulkanError out of device memory from a feature's upload) reaches the caller with
  // nothing of the frame submitted; the next call renders normally (with a window, the failed
  // frame shows the last finished one again). The features draw entities by their
  // scene::WorldTransform: run scene::updateWorldTransforms(registry) after changing Transforms
  // (a registry of Transforms without any WorldTransform is said once, as a warning).
  bool renderFrame(const ecs::Registry& registry, const CameraView& camera, const FrameSettings& settings = {});

  // Waits for the GPU, then copies the last frame back: RGBA8 (sRGB-encoded) and depth values.
  std::vector<std::uint8_t> readbackColor();
  // The colour target as floats, for a renderer made with a float colour format
  // (RendererDesc::formats.color = R32G32B32A32_SFLOAT or R16G16B16A16_SFLOAT): e.g. the normals
  // of DEBUG_VIEW_NORMALS (0.5 n + 0.5) without 8-bit quantization. Error for other formats.
  Expected<std::vector<glm::vec4>> readbackColorFloat();
  // The work counters of the last frame rendered with FrameSettings::countWork, one per pixel
  // (row-major from the top); empty when no frame has counted yet.
  std::vector<std::uint32_t> readbackWorkCounters();
  // The frame-wide totals of that frame (shader::WorkTotals); all zero when no frame has counted.
  shader::WorkTotals readbackWorkTotals();
  std::vector<float> readbackDepth();
  // The depth pyramid of the last frame's last view region that used occlusion culling (levels
  // concatenated, DepthPyramid::levelOffset), with its view; empty when no frame built one.
  std::vector<float> readbackDepthPyramid();
  DepthPyramidView depthPyramidView() const { return pyramid_ ? pyramid_->view() : DepthPyramidView{}; }
  // Per pixel: x = 1 + GPU scene object index (0 = background), y = feature-specific part id.
  std::vector<glm::uvec2> readbackVisibility();
  // Named GPU timings of the most recent frame whose results are available.
  const std::vector<gpu::GpuTiming>& lastTimings() const { return lastTimings_; }
  // Pipeline statistics of the most recent frame whose results are available, per pass:
  // "depth prepass" and "opaque". Empty on devices without pipeline-statistics queries.
  const std::vector<gpu::PipelineStatistics>& lastPipelineStatistics() const { return lastStatistics_; }
  // Objects the features dropped since the last call, each with why (FrameContext::reportDropped):
  // e.g. a new asset whose GPU buffers did not fit the allocator's budget. The frames that
  // dropped them drew the rest of the scene.
  std::vector<std::string> takeDroppedObjects();
  // Why occlusion culling culls nothing (its depth pyramid could not be made: a shader missing), or
  // empty. The frames are right, only not culled: a measurement of occlusion culling must check it.
  const std::string& occlusionFailure() const { return pyramidFailure_; }
  // Waits for all frames and collects the timings of the last one.
  void finish();

  std::uint64_t frameNumber() const { return frameNumber_; }
  // The GPU objects retired by the renderer and its features (FrameContext::retire) that are not
  // destroyed yet: their frames may still be in flight.
  std::size_t pendingReleases() const { return retired_.pending(); }
  const RendererDesc& desc() const { return desc_; }

 private:
  struct FrameResources {
    VkCommandPool pool = VK_NULL_HANDLE;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    VkSemaphore imageAvailable = VK_NULL_HANDLE;
    gpu::GpuTimer timer;
    gpu::PipelineStatisticsQueries statistics;
    bool submitted = false;  // its fence will signal (or has)
    bool timed = false;      // the submission wrote the timer and statistics queries
  };

  void createFrameObjects();
  void destroyHandles() noexcept;
  void createTargets();
  void createSceneDescriptors();
  void updateSceneDescriptors();
  void writeFrameGlobals(std::uint32_t slot, const CameraView& camera);
  void recordFrame(FrameResources& frame, std::uint32_t slot, const ecs::Registry& registry, const CameraView& camera,
                   const FrameSettings& settings, std::uint32_t imageIndex);
  void submitFrame(FrameResources& frame, gpu::Swapchain* swapchain, std::uint32_t imageIndex);
  void abandonFrame(FrameResources& frame, gpu::Swapchain* swapchain, std::uint32_t imageIndex);
  void recordRegion(FrameResources& frame, FrameContext& context, const ViewRegion& region, std::uint32_t index);
  void recordScenePasses(FrameResources& frame, FrameContext& context, VkRect2D rect, std::uint32_t region);
  void recordDepthPrepass(PassContext& pass, VkRect2D rect, bool first);
  void beginPrepassRendering(VkCommandBuffer cmd, VkRect2D rect, bool first, VkAttachmentLoadOp load);
  static void barrierBetweenPrepassStages(VkCommandBuffer cmd);
  void recordOcclusionPhase2(PassContext& pass, VkRect2D rect, bool first);
  DepthPyramid* ensurePyramid();
  void recordOpaquePass(PassContext& pass, VkRect2D rect, bool first);
  void recordTransparentPass(PassContext& pass, VkRect2D rect);
  void beginShadingRendering(VkCommandBuffer cmd, VkRect2D rect, VkRect2D renderArea, VkAttachmentLoadOp colorLoad);
  void recordPresentBlit(VkCommandBuffer cmd, gpu::Swapchain& swapchain, std::uint32_t imageIndex);
  void collectTimings(FrameResources& frame);
  void prepassColorBarrier(VkCommandBuffer cmd, VkImageLayout from, VkImageLayout to, VkPipelineStageFlags2 srcStage,
                           VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess);
  void warnIfWorldTransformsMissing(const ecs::Registry& registry);
  VkDeviceAddress prepareWorkCounters(VkCommandBuffer cmd);

  const gpu::Context& context_;
  RendererDesc desc_;
  VkExtent2D extent_;
  gpu::Image color_;
  gpu::Image depth_;
  gpu::Image visibility_;
  gpu::Image hitOffset_;  // RendererFormats::hitOffset, beside the visibility
  gpu::SamplerHandle depthSampler_;
  gpu::DescriptorSetLayout sceneSetLayout_;
  VkDescriptorPool descriptorPool_ = VK_NULL_HANDLE;
  VkDescriptorSet sceneSet_ = VK_NULL_HANDLE;
  std::vector<FrameResources> frames_;
  GpuScene scene_;
  PerFrameBuffer frameGlobals_;
  std::vector<std::unique_ptr<RenderFeature>> features_;
  // What the renderer and its features retired (FrameContext::retire). Emptied before the features
  // go: a retired object may give a slot back to the feature that made it.
  gpu::DeferredRelease retired_;
  // Made on the first frame with occlusion culling (its shader loaded then); sized with the targets.
  std::unique_ptr<DepthPyramid> pyramid_;
  std::string pyramidFailure_;  // why it could not be made (its shader did not load): features get an empty pyramid
  std::vector<gpu::GpuTiming> lastTimings_;
  std::vector<gpu::PipelineStatistics> lastStatistics_;
  // One uint per pixel, then shader::WorkTotals; created on the first counting frame.
  gpu::PixelBuffer workCounters_{"work counters", VK_BUFFER_USAGE_TRANSFER_SRC_BIT, sizeof(shader::WorkTotals)};
  bool workCounted_ = false;
  bool worldTransformsWarned_ = false;  // warnIfWorldTransformsMissing said it
  std::vector<std::string> droppedObjects_;  // FrameContext::reportDropped, until takeDroppedObjects()
  bool reportedTooManyRegions_ = false;
  std::uint64_t frameNumber_ = 0;
};

}  // namespace engine::render
