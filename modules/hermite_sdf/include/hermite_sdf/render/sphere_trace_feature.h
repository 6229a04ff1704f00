#pragma once
// The paper's two baselines as one engine RenderFeature: every entity with a HermiteSdfRenderable
// whose method is TrilinearSphereTrace or HermiteSphereTrace (and a WorldTransform) is drawn by
// sphere tracing a dense 3D texture of its asset's field. Changing the component's method (or
// normals, or halfPrecision) takes effect on the next frame; one frame can mix methods.
//
// Fields. Trilinear: f as R32_SFLOAT (R16_SFLOAT with halfPrecision), read with hardware trilinear
// filtering (sample i at texture coordinate (i + 0.5) / K, i.e. the sample positions of GridSpec).
// Hermite: (f, fx, fy, fz) as RGBA32F (RGBA16F); each step fetches the 8 corners of its cell with
// texelFetch (reused while the steps stay in the cell) and evaluates the tricubic Ferguson–Hermite
// interpolant. Textures are uploaded once per (asset id, method, precision) and released when no
// entity has drawn them for framesInFlight frames.
//
// Tracing. The proxy is the grid's bounding box; the ray starts at the box entry, or at the near
// plane when that is farther, and steps by the interpolated distance f until |f| < epsilon * h,
// or until f changes sign between two steps (an overshoot): either is a hit, placed on the exact
// interpolant (trilinear: the cell's 8 texels interpolated in float, not the filtered texture;
// regula falsi inside a sign change). EPSILON IS IN UNITS OF THE GRID SPACING h (default 1e-4,
// the paper's eps), so the tolerance scales with the field and not with the scene. Hardware
// filters quantize the trilinear weights (8 fractional bits on an H100): there the filtered f may
// never fall below epsilon near the surface, and a tracer that only tested epsilon oscillated
// until its step limit (noise on that GPU). A ray leaving the box, or running out of steps
// (maxSteps, default 1024), misses; the latter is counted in frames that count work. Rays that graze one part of the surface before hitting
// another take hundreds of steps (up to ~830 on the K = 16 torus of the tests); 512 left a hole
// pixel per view there. A ray that starts inside the surface finds where it leaves. A ray that
// passes within epsilon * h of the surface counts as a hit there (silhouettes grow by that much).
// The trilinear interpolant is not an exact distance (it underestimates near the surface, which
// only costs steps); the filtered texture also quantizes the interpolation weights
// (subTexelPrecisionBits, 8 bits on most devices), so its surface can sit up to ~2^-9 h from the
// exact trilinear interpolant's.
//
// Passes. Depth prepass: the box's front faces, gl_FragDepth with conservative depth (the hit is
// never nearer than the face; early depth testing keeps working) and the visibility id
// (1 + object index, evaluations). Its shaders have no discard (a miss writes the far plane) and
// no buffer write, which would cost early depth rejection on GPUs; frames that count work
// (FrameContext::workCounters) use variants with the counters (*_counted.frag): evaluations per
// pixel and rays out of steps (WorkTotals::raysOutOfSteps). Objects whose box the near plane may cut (the eye inside or
// close to the box) are drawn by their back faces with a variant without the depth guarantee.
// Shading pass: the same faces again; a fragment is shaded only where the visibility buffer names
// its object (one shading per pixel), at the hit rebuilt from the prepass depth, with the normal
// the component asks for: Exact (analytic gradient of the interpolant: trilinear or tricubic) or
// CentralDifferences (6 field evaluations centralDifferenceStep grid units apart). Debug views:
// normals, depth, evals (heat map of field evaluations, 64 = red).
//
// Transforms: any invertible affine world matrix. Rays are traced in object space (grid units),
// where f is a distance, so non-uniform scale and shear change neither the step nor epsilon (both
// in object units); depth is written for the world-space hit. Mirrored objects keep their front
// faces through OBJECT_FLAG_MIRRORED (shaders/hermite/box.glsl). Objects whose matrix cannot be
// inverted are skipped (Stats::skippedObjects).
//
// Descriptors. Bindless where Context::capabilities().descriptorIndexing (one array of 3D
// textures, indexed per draw, one bind and one instanced draw per pass and method), otherwise one
// descriptor set per texture bound before each object's draw (lavapipe).
//
// GPU timings: "trilinear prepass", "hermite prepass", "trilinear shading", "hermite shading".
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include "engine/ecs/entity.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/image.h"
#include "engine/gpu/memory.h"
#include "engine/gpu/lazy_pipeline.h"
#include "engine/gpu/pipeline.h"
#include "engine/render/drawn_per_region.h"
#include "engine/render/per_frame_buffer.h"
#include "engine/render/region_stats.h"
#include "engine/render/render_feature.h"
#include "hermite_sdf/render/renderable.h"

namespace shader {
struct SphereTraceDraw;  // hermite/hermite_host_device.h
}  // namespace shader

namespace hsdf {

class FieldTextureBindings;

class SphereTraceFeature final : public engine::render::RenderFeature {
 public:
  static constexpr std::uint32_t kFeatureId = 3;  // ObjectData::feature (SPHERE_TRACE_FEATURE_ID)

  struct Options {
    bool allowBindless = true;  // false: per-texture descriptor sets even where bindless works
  };
  // A NaN, infinite or non-positive epsilon or central-difference step takes its default (a
  // warning names it once).
  struct Settings {
    float epsilon = 1e-4f;              // stop when |f| < epsilon * h (grid spacings)
    std::uint32_t maxSteps = 1024;      // field evaluations per ray (see the header comment)
    float centralDifferenceStep = 0.5f; // grid spacings
    // Trilinear tracer only: 0 filters with the device's sampler; b in 1..16 emulates a filter unit
    // that rounds its weights to b fractional bits (NVIDIA: 8), in the shader, so that a device
    // which filters in full float (lavapipe) shows what such GPUs draw. For tests and experiments.
    std::uint32_t emulatedFilterBits = 0;
    // From the second frame with objects of this module (drawn here or by the cells:
    // hasSdfObjects), the pipelines a switch to either tracer binds (the tuning panel's method, the split screen's
    // compared side) are compiled on a worker thread at low priority, so that the frame after the
    // switch binds them instead of compiling them; after a shader reload, from the next frame.
    // Off: that frame compiles them (hundreds of milliseconds each on lavapipe).
    bool warmPipelines = true;
  };
  // The trilinear tracer's switch from filtered to exact values (grid units), for a filter whose
  // weights have `bits` fractional bits: such a filter is off by at most 2^-(bits+1) of the largest
  // difference of two neighbouring texels (about 1 cell for a distance field, 2 for samples that
  // jump across zero); 4x that margin: 2^-(bits-2), 1/64 cell for NVIDIA's and lavapipe's 8 bits,
  // 1/4 for the 4 bits Vulkan allows. Bits past 8 count as 8 (a finer filter needs no less).
  static float exactBelowCells(std::uint32_t bits);

  struct Stats {
    std::uint32_t trilinearObjects = 0;
    std::uint32_t hermiteObjects = 0;
    std::uint32_t nearObjects = 0;    // drawn by their back faces
    std::uint32_t culledObjects = 0;  // outside the view frustum
    std::uint32_t skippedObjects = 0; // singular transform, or a field that cannot become a
                                      // texture (logged once per asset)
    std::uint32_t textures = 0;
    // Multi-material assets' palettes and slots: one buffer per asset, whichever methods and
    // precisions draw it.
    std::uint32_t materialBuffers = 0;
    std::uint64_t textureBytes = 0;  // the textures' images and the material buffers
    bool bindless = false;
  };

  SphereTraceFeature();
  explicit SphereTraceFeature(Options options);
  ~SphereTraceFeature() override;
  std::string_view name() const override { return "sphere tracing"; }
  engine::Status initialize(const engine::gpu::Context& context, const engine::render::RendererFormats& formats,
                            std::uint32_t framesInFlight) override;
  void prepare(engine::render::FrameContext& frame) override;
  void recordPass(engine::render::PassContext& pass) override;
  void drawUi() override;
  // Describes the eleven pipelines again from the SPIR-V on disk and compiles those frames bound;
  // a failure keeps the old ones.
  engine::Status reloadShaders() override;
  engine::Status createAllPipelines() override;
  // The feature's pipelines: described at creation, compiled when a frame first draws with one.
  engine::gpu::PipelineCounts pipelineCounts() { return engine::gpu::countPipelines(pipelines_.all()); }
  // Waits until the pipelines being warmed (Settings::warmPipelines) are compiled; none: returns.
  void waitForWarmPipelines() { warming_.wait(); }

  Settings& settings() { return settings_; }
  const Stats& stats() const { return stats_; }
  // Every view region's stats of the last frame, in drawing order (stats() is the last region's).
  std::vector<Stats> regionStats() const { return regionStats_.all(stats_); }
  // Whether the field texture of `assetId` could not be uploaded (out of GPU memory or texture
  // slots): the asset is not drawn, and tried again only once memory has been given back, the
  // budget raised or a texture released. Lets the caller draw the field the asset replaced instead.
  bool refused(std::uint64_t assetId) const;

 private:
  std::uint32_t deviceFilterBits_ = 8;  // VkPhysicalDeviceLimits::subTexelPrecisionBits
  struct FieldTexture {
    engine::gpu::Image image;
    // A multi-material asset's palette and sample slots (FieldMaterialsHeader), read by address
    // in the shading pass (ObjectData::payload); none for one material. The asset's textures of
    // both methods and precisions share one (materials_): the last one released frees it.
    std::shared_ptr<const engine::gpu::Buffer> materials;
    std::uint32_t slot = 0;
    std::uint64_t lastUsedFrame = 0;
    std::uint64_t bytes = 0;  // the image's
  };
  // A texture no longer drawn, retired with the frame (FrameContext::retire): when the frames that
  // may draw it have completed it is destroyed and gives its slot back to the bindings (which must
  // outlive it: the renderer destroys what is retired before its features).
  struct RetiredTexture {
    FieldTexture texture;
    FieldTextureBindings* bindings = nullptr;
    std::uint64_t* releasedTextures = nullptr;  // counts it once its slot is free again
    RetiredTexture(FieldTexture t, FieldTextureBindings* b, std::uint64_t* released)
        : texture(std::move(t)), bindings(b), releasedTextures(released) {}
    RetiredTexture(const RetiredTexture&) = delete;
    RetiredTexture& operator=(const RetiredTexture&) = delete;
    ~RetiredTexture();
  };
  using TextureKey = std::tuple<std::uint64_t, std::uint32_t, bool>;  // asset id, method, half
  struct Range {
    std::uint32_t first = 0;
    std::uint32_t count = 0;
  };

  // [method]: front faces with conservative depth, back faces (near plane), each without and
  // with the work counters ([counted]: frames that count work), and shading.
  // Described when the feature is created, compiled when a frame first draws with one
  // (engine/gpu/lazy_pipeline.h).
  struct Pipelines {
    engine::gpu::LazyPipeline depthFront[2][2];  // [method][counted]
    engine::gpu::LazyPipeline depthNear[2][2];
    engine::gpu::LazyPipeline shade[2];
    engine::gpu::LazyPipeline wire;  // DEBUG_VIEW_WIREFRAME: the proxies' edges
    // Every pipeline above, in one fixed order (a reload pairs the old set with the fresh one).
    std::vector<engine::gpu::LazyPipeline*> all();
  };
  engine::Expected<Pipelines> describePipelines() const;
  std::vector<engine::gpu::LazyPipeline*> likelyNextPipelines(bool counted);
  void createSamplers();
  const FieldTexture* acquireTexture(const SdfAsset& asset, std::uint32_t method, bool half,
                                     const engine::render::FrameContext& frame);
  // `outOfResources`: the error is GPU memory or the texture table, not the asset (no dense field,
  // too large a resolution), so refused() names it.
  // `neededBytes`: what the upload allocates, for a refusal's retry.
  engine::Expected<FieldTexture> uploadTexture(const SdfAsset& asset, std::uint32_t method, bool half,
                                               bool& outOfResources, VkDeviceSize& neededBytes);
  void forgetRefusalsThatMayFit();
  void releaseUnusedTextures(const engine::render::FrameContext& frame);
  // An entity's asset and the texture it draws with (null: nothing to draw).
  struct EntityTexture {
    std::shared_ptr<const SdfAsset> asset;
    const FieldTexture* texture = nullptr;
  };
  using DrawLists = std::vector<shader::SphereTraceDraw>[2][2];  // [method][near], as front_ and near_
  EntityTexture entityTexture(engine::ecs::Entity entity, const HermiteSdfRenderable& r, std::uint32_t method,
                              const engine::render::FrameContext& frame);
  shader::SphereTraceDraw makeDraw(const EntityTexture& found, const HermiteSdfRenderable& r, std::uint32_t object);
  void collectDraws(engine::render::FrameContext& frame);
  void uploadDraws(const engine::render::FrameContext& frame, const DrawLists& lists);
  void recordDraws(VkCommandBuffer cmd, VkPipelineLayout layout, Range range) const;
  void recordMethod(engine::render::PassContext& pass, std::uint32_t method);
  void recordWireframe(engine::render::PassContext& pass);

  Options options_;
  Settings settings_;
  Stats stats_;
  engine::render::RegionStats<Stats> regionStats_;
  const engine::gpu::Context* context_ = nullptr;
  std::unique_ptr<FieldTextureBindings> bindings_;
  engine::gpu::SamplerHandle samplers_[2];  // by method: linear, nearest
  engine::render::RendererFormats formats_;
  Pipelines pipelines_;
  // Compiles likelyNextPipelines() on a worker; declared after pipelines_ so that it is stopped
  // and joined before they are destroyed. Stopped before a reload replaces them.
  engine::gpu::PipelineWarming warming_;
  std::map<TextureKey, FieldTexture> textures_;
  // By asset id: the materials buffer its textures share (expired once they are all released).
  std::map<std::uint64_t, std::weak_ptr<const engine::gpu::Buffer>> materials_;
  std::set<TextureKey> failedTextures_;  // reported once, not retried (refusals: until they may fit)
  // Of those, the refusals for GPU memory or the texture table (refused()), with the number of
  // textures released when they were made (a released texture frees a slot of the table).
  struct Refusal {
    engine::gpu::MemoryRefusal memory;
    std::uint64_t releasedTextures = 0;
  };
  std::map<TextureKey, Refusal> refusals_;
  std::uint64_t releasedTextures_ = 0;
  // The asset each entity drew in each view region's last frame: drawn instead of a refused asset
  // that replaced it.
  engine::render::DrawnPerRegion<std::shared_ptr<const SdfAsset>> drawnAssets_;
  std::string settingsSaid_;  // the warnings about bad Settings given so far (each said once)
  engine::render::PerFrameBuffer drawBuffer_;
  std::vector<std::uint32_t> drawSlots_;  // texture slot per draw of this frame
  Range front_[2], near_[2];              // per method, ranges of this frame's draws
};

}  // namespace hsdf
