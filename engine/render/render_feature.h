#pragma once
// RenderFeature: how a module plugs into the frame. The renderer owns the frame and calls every
// feature in a fixed order:
//   prepare()          CPU: read components from the registry, add objects to the GPU scene,
//                      upload per-frame data (the frame slot's previous submission is complete);
//   recordEarlyDepth() only when usesEarlyDepth() said so after prepare(): a rendering instance of
//                      its own that opens the depth prepass (same attachments, cleared), then
//   recordEarlyDepthResolve() first in the rest of the prepass (storage writes of the early draws
//                      are visible to it): the early stage's depth fixed up before anything else draws;
//   recordPass(Depth)  inside the depth prepass (depth + visibility id + hit offset, compare GREATER,
//                      reverse-Z);
//                      with occlusion culling (usesOcclusionCulling() after prepare()), this is
//                      phase 1 (what was visible last frame), then the prepass ends, the depth
//                      pyramid is built from it (depth_pyramid.h) and
//   recordLateCulling() outside any rendering instance: compute culling against the pyramid, then
//   recordPass(Depth)  again, phase 2 (PassContext::occlusionLate), only for such features, in a
//                      rendering instance that loads what phase 1 drew;
//   recordPass(Opaque) inside the shading pass (colour + read-only depth: depth is final, test
//                      EQUAL or read it from the scene descriptor set);
//   recordTransparent() only when hasTransparentDraws() said so after prepare(): a pass of its own
//                      after every feature's shading (the SDF objects' resolve included), colour
//                      loaded + the prepass depth read-only: surfaces blended over the finished
//                      opaque frame (glTF alphaMode BLEND), which are in no prepass attachment;
//   drawUi()           inside the ImGui frame: the feature's tuning panel.
// A feature reads components, never globals. Features create (or describe, to compile on first
// use) their pipelines in initialize() with the formats the renderer gives them, and again in
// reloadShaders() from fresh SPIR-V.
// View regions (FrameSettings::regions): a frame with several regions calls prepare() and the
// passes once per region, in that order (prepare, depth, opaque, transparent; next region), each region with
// its own frame slot, so per-frame data written in prepare() stays valid until its passes ran.
// The framesInFlight given to initialize() counts these slots (frames in flight x regions).
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/core/expected.h"
#include "engine/gpu/deferred_release.h"
#include "engine/gpu/gpu_timer.h"
#include "engine/render/camera_view.h"
#include "engine/render/depth_pyramid.h"

namespace engine::ecs {
class Registry;
}
namespace engine::gpu {
class Context;
}

namespace engine::render {

class GpuScene;

enum class Pass { DepthPrepass, Opaque, Transparent };

struct RendererFormats {
  VkFormat color = VK_FORMAT_R8G8B8A8_SRGB;
  VkFormat depth = VK_FORMAT_D32_SFLOAT;
  // The depth prepass also writes a visibility buffer: per pixel, x = 1 + the GPU scene index of
  // the object that won the depth test (0: background) and y = which part of it (feature-specific:
  // the triangle of a mesh, the cell of a ray-cast surface). Attachment 0 of every prepass
  // pipeline, written as a uvec2.
  VkFormat visibility = VK_FORMAT_R32G32_UINT;
  // Beside it, attachment 1: a float the winning fragment stores with its id, where along the view
  // its surface lies, measured from a plane of the feature's own near the object (0 where the
  // feature needs none: meshes). Far from the eye the depth buffer holds a hit only to a float ulp
  // of the whole distance (reverse-Z znear / d: ~6e-8 of it); a feature that shades once per pixel
  // rebuilds its hit from this instead. Every prepass pipeline writes both (prepassColorFormats).
  VkFormat hitOffset = VK_FORMAT_R32_SFLOAT;
  // Layout of the scene descriptor set (set 0 of pipelines that use it), filled in by the renderer:
  // binding 0: the prepass depth (sampler2D), binding 1: the visibility buffer (usampler2D),
  // binding 2: the hit offsets (sampler2D), all nearest-sampled in the shading pass. A feature that
  // shades once per pixel reads them to know which of its fragments produced the visible surface.
  VkDescriptorSetLayout sceneSetLayout = VK_NULL_HANDLE;

  // The colour attachments of the depth prepass, in order, for every pipeline drawn in it.
  std::vector<VkFormat> prepassColorFormats() const { return {visibility, hitOffset}; }
};

struct FrameContext {
  VkCommandBuffer cmd;         // recording; work recorded in prepare() runs before the passes
  const ecs::Registry& registry;
  const gpu::Context& gpu;
  GpuScene& scene;
  const CameraView& camera;
  VkExtent2D extent;
  std::uint32_t frameSlot;     // which frame slot's resources to use (frame in flight x view region)
  std::uint64_t frameNumber;
  std::uint32_t debugView;     // DEBUG_VIEW_* (shared/host_device.h)
  // Address of one uint per pixel (index y * width + x), zeroed before the prepass, to which
  // features atomically add their per-pixel root-search work (FrameSettings::countWork); 0 when
  // the frame does not count.
  VkDeviceAddress workCounters = 0;
  // Address of this frame's shader::WorkTotals (zeroed with the counters), 0 when not counting.
  VkDeviceAddress workTotals = 0;
  // Address of this frame's FrameGlobals (the camera), for compute work recorded in prepare()
  // that reads what the passes read.
  VkDeviceAddress frameGlobals = 0;
  // The view region drawn now (the whole frame without regions); passes are scissored to it.
  VkRect2D viewRegion{{0, 0}, {0, 0}};
  // Its index in FrameSettings::regions (0 without regions): state a feature keeps per view region
  // (e.g. DrawnPerRegion) is found by it.
  std::uint32_t viewRegionIndex = 0;
  // Frames in flight (not frame slots): a resource last used by frame L is free once frame
  // L + framesInFlight is being prepared (that frame's slot waited for L's fence).
  std::uint32_t framesInFlight = 1;
  // The renderer's one list of GPU objects waiting for their frames to complete
  // (gpu/deferred_release.h has the frame number rule). A feature never destroys an object that a
  // submitted frame may use, nor waits for the device to do so: it retires it here.
  gpu::DeferredRelease* retired = nullptr;
  // Retires `object` (a Buffer, an Image, a unique_ptr to a group of them...) that this frame's
  // commands recorded so far, or any earlier frame's, may use.
  template <class T>
  void retire(T&& object) const {
    retired->retire(std::forward<T>(object), frameNumber);
  }
  // Retires `object` that no frame after `lastUse` uses (e.g. slotLastUse() for a frame slot's own
  // buffers, or the last frame that drew an asset).
  template <class T>
  void retire(T&& object, std::uint64_t lastUse) const {
    retired->retire(std::forward<T>(object), lastUse);
  }
  // The last frame that may have used this frame slot's own resources: the slot's previous frame
  // (frame slots repeat every framesInFlight frames), complete now.
  std::uint64_t slotLastUse() const { return frameNumber >= framesInFlight ? frameNumber - framesInFlight : 0; }
  // Where a feature says it could not draw an object (e.g. its new asset's GPU buffers did not fit
  // the memory budget): it drops the object, draws the rest and reports it here once; the
  // renderer hands the reports to its caller (Renderer::takeDroppedObjects).
  std::vector<std::string>* droppedObjects = nullptr;
  void reportDropped(std::string message) const;
  // The frame's named GPU timings: the renderer times every feature's prepare() together as
  // "prepare" (per view region, like the passes); a feature names the parts of its compute work
  // inside it (gpu::GpuTimerScope). Null where the frame is not timed.
  gpu::GpuTimer* timer = nullptr;
};

struct PassContext {
  VkCommandBuffer cmd;
  const FrameContext& frame;
  Pass pass;
  VkDeviceAddress frameGlobals;  // FrameGlobals of this frame
  VkDeviceAddress objects;       // ObjectData[] of this frame
  // Opaque and transparent passes: the scene descriptor set (prepass depth, see RendererFormats).
  // The depth attachment is read-only there, so it can be sampled while it is tested against.
  VkDescriptorSet sceneSet;
  gpu::GpuTimer& timer;          // for sub-pass timings: timer.begin(cmd, "name") / end(cmd)
  // Depth prepass with occlusion culling: false in phase 1 (every feature), true in phase 2
  // (only the features that use occlusion culling draw what their late culling kept).
  bool occlusionLate = false;
};

class RenderFeature {
 public:
  virtual ~RenderFeature() = default;
  virtual std::string_view name() const = 0;
  virtual Status initialize(const gpu::Context& context, const RendererFormats& formats,
                            std::uint32_t framesInFlight) = 0;
  virtual void prepare(FrameContext& frame) = 0;
  virtual void recordPass(PassContext& pass) = 0;
  // The early depth stage, for proxies that are cheaper to test at the depth of their own faces
  // than at the depth of what they draw (a feature that ray-casts inside bounding boxes: hidden
  // boxes then fail an early depth test instead of running the ray cast). The early draws may leave
  // depths that are not the surface's in the depth buffer; recordEarlyDepthResolve() must replace
  // them with the true ones before any other feature's prepass draw tests against them. pass.pass is
  // DepthPrepass.
  virtual bool usesEarlyDepth() const { return false; }
  virtual void recordEarlyDepth(PassContext& /*pass*/) {}
  virtual void recordEarlyDepthResolve(PassContext& /*pass*/) {}
  // Two-phase occlusion culling (the scheme of zeux/niagara): when any feature says so after
  // prepare(), the prepass draws phase 1, the renderer builds the depth pyramid of what it drew,
  // calls recordLateCulling() (compute only; pass.pass is DepthPrepass, no rendering instance is
  // open; the pyramid is readable by compute shaders) and then recordPass() with
  // pass.occlusionLate set. The feature's own barriers make its late culling's output visible to
  // the phase-2 draws. Correctness must not depend on phase 1: anything phase 1 left out that may
  // be visible has to be drawn in phase 2.
  virtual bool usesOcclusionCulling() const { return false; }
  virtual void recordLateCulling(PassContext& /*pass*/, const DepthPyramidView& /*pyramid*/) {}
  // Blended surfaces (glTF alphaMode BLEND: a glass pane): when any feature says so after prepare(),
  // the renderer opens the transparent pass after the shading pass, and calls recordTransparent()
  // (pass.pass is Transparent) of each feature that said so, in the order they were added. The
  // colour target holds the finished opaque frame; the depth attachment is the prepass's,
  // read-only: a blended surface tests against it and writes none, and it must not be in the
  // prepass (it would hide what lies behind it, and the visibility buffer, which the resolves,
  // the debug views and picking read, would name it). Blending is the feature's pipeline state;
  // a feature draws its blended surfaces back to front itself (there is no order across features).
  virtual bool hasTransparentDraws() const { return false; }
  virtual void recordTransparent(PassContext& /*pass*/) {}
  virtual void drawUi() {}
  // Recreates the pipelines from the SPIR-V on disk now (e.g. after the shaders were rebuilt).
  // On failure the old pipelines stay and the error says why (the file, the loader's or Vulkan's
  // message). Called between frames; waits for the GPU before replacing pipelines.
  virtual Status reloadShaders() { return makeError("shader reload is not supported by " + std::string(name())); }
  // Compiles now every pipeline the feature may draw with. A feature may otherwise compile one
  // only when a frame first needs it (gpu/lazy_pipeline.h): call this where a later hitch would
  // hurt (behind a load screen) or where every pipeline must exist (a shader statistics run).
  virtual Status createAllPipelines() { return {}; }
};

}  // namespace engine::render
