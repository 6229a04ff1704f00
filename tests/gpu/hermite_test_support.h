#pragma once
// Helpers of the hermite_sdf GPU tests: SDF assets from analytic shapes and the bunny, SDF
// entities, and the comparison of a GPU frame with the CPU reference ray caster.
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "gpu_test_support.h"
#include "hermite_sdf/core/reference.h"
#include "engine/gpu/lazy_pipeline.h"
#include "hermite_sdf/render/renderable.h"

namespace gputest {

// Bakes an analytic shape ("sphere", "box", "torus", ...) or "bunny" (samples/assets/bunny.glb)
// at K samples per axis with one cell of padding. Fails the test on error.
std::shared_ptr<const hsdf::SdfAsset> bakeAsset(const std::string& shape, int resolution);

// The f samples alone: the field the trilinear tracer draws.
hsdf::TrilinearField trilinearOf(const hsdf::HermiteField& field);

// The field as fp16 textures and fp16 cell records hold it: every value rounded to half.
hsdf::HermiteField roundedToHalf(const hsdf::HermiteField& field);

// The CPU reference image (of `size` pixels) of the interpolant a sphere-tracing `method` draws,
// for an object placed by `model`. Hermite casts through the kept cells only: the same hits as
// all cells (reference.h), faster. Fails the test on error.
hsdf::ReferenceImage referenceFor(hsdf::RenderMethod method, const hsdf::HermiteField& field,
                                  const engine::render::CameraView& camera, glm::ivec2 size,
                                  const glm::mat4& model = glm::mat4(1.0f));

// The CPU reference image of `field` (at the origin) seen by `camera`, cast from its eye as the
// renderer draws from it: camera-relative, the view its rotation alone and the object moved by
// -CameraView::position (exact: a float negated), as the anchors take the eye in double
// (render/ray_anchor.h). From camera.view the reference took the eye from the float translation
// -R eye, 0.04-0.29 cells off 1e6-1e7 cells out. `method` picks the interpolant as referenceFor
// does (the cells' is the Hermite one). Fails the test on error.
hsdf::ReferenceImage referenceFromTheEye(const hsdf::HermiteField& field, const engine::render::CameraView& camera,
                                         glm::ivec2 size,
                                         hsdf::RenderMethod method = hsdf::RenderMethod::HermiteSphereTrace);

// An entity drawing `asset` with a sphere-tracing `method` (no Transform: `transform` is its
// WorldTransform), from fp16 textures when `half`.
engine::ecs::Entity addTracedSdf(engine::ecs::Registry& registry, std::shared_ptr<const hsdf::SdfAsset> asset,
                                 hsdf::RenderMethod method, const glm::mat4& transform = glm::mat4(1.0f),
                                 bool half = false);

engine::ecs::Entity addSdf(engine::ecs::Registry& registry, std::shared_ptr<const hsdf::SdfAsset> asset,
                           hsdf::RenderMethod method, const glm::mat4& transform = glm::mat4(1.0f),
                           std::uint32_t subdivisions = 3);

// A split screen of a width x height frame: two view regions, its left and right halves. Before a
// side is drawn, `show(side)` (0: left, 1: right) puts that side's form of the scene into the
// registry (e.g. another asset for the same entity, as the Viewer's comparison does).
engine::render::FrameSettings splitInHalves(std::uint32_t width, std::uint32_t height,
                                            const std::function<void(std::uint32_t side)>& show);

struct ImageComparison {
  int referenceHits = 0;
  int gpuHits = 0;
  int disagreements = 0;          // coverage differs
  int interiorHoles = 0;          // reference hit, GPU miss, no reference miss among the 8 neighbours
  int interiorExtras = 0;         // GPU hit, reference miss, no reference hit among the 8 neighbours
  double depthErrorP50 = 0.0;     // |view distance difference| / h, percentiles over common hits
  double depthErrorP90 = 0.0;
  double depthErrorP99 = 0.0;
  // Over interior hits only (no reference miss within 2 pixels, and no occlusion edge: two
  // neighbouring reference hits more than a cell apart along their rays): at a silhouette, the
  // object's outline or a nearer part's in front of a farther one, the ray grazes the surface and
  // its depth is ill-conditioned (a tiny change of F moves the hit far).
  double interiorDepthErrorP99 = 0.0;
  double depthErrorMax = 0.0;
  double normalErrorP99Degrees = 0.0;
  // Interior pixels (as for interiorDepthErrorP99) whose depth is off by more than
  // kDepthOutlierCells: a ray that passed through the surface and hit something behind it (a
  // percentile hides a few of those).
  int interiorDepthOutliers = 0;
  int normalFlips = 0;            // GPU normal facing against the reference normal (dot < 0)
  int interiorNormalFlips = 0;    // the same at interior pixels (as for interiorDepthErrorP99)
  double agreement(int pixels) const { return 1.0 - double(disagreements) / double(pixels); }
};

inline constexpr double kDepthOutlierCells = 0.05;

// Pixels unlike all 8 neighbours while those agree with each other (every channel within
// `tolerance` of the first neighbour): the specks a missed root leaves on a smooth surface (the ray
// went through and hit a far face, or nothing). Image borders are not counted. With `wrong` (pixel
// index -> bool), only isolated pixels it calls wrong count: a speck the reference also shows is a
// feature of the interpolant, not a missed root.
int countIsolatedPixels(const Frame& frame, int tolerance = 24, const std::function<bool(std::size_t)>& wrong = {});

// Pixels of a DEBUG_VIEW_WIREFRAME frame drawn in the edges' colour (cells_wire.frag's yellow)
// where the shaded frame of the same view was another colour: the boxes' edges drawn.
int wireEdgePixels(const Frame& wire, const Frame& shaded);

// Pixels of a DEBUG_VIEW_NORMALS frame that disagree with the reference away from its silhouettes
// (the reference's 5x5 neighbourhood all hit or all missed): coverage differs, or the normal is
// more than `degrees` off (orientation-free, as in compareWithReference). At a silhouette the ray
// grazes the surface, where a float search and the double reference may rightly differ.
std::vector<bool> wrongPixels(const Frame& normals, const hsdf::ReferenceImage& reference, double degrees = 10.0);

// Compares GPU depth (and normals decoded from a DEBUG_VIEW_NORMALS frame, if given) with the
// reference image of the object placed by `model`. Depth errors are view-distance differences in
// cells: `spacing` is the grid spacing in object units, and a cell measures h / |M^-1 d| world
// units along the pixel's unit ray d (just h for the identity).
ImageComparison compareWithReference(const Frame& gpu, const std::vector<std::uint8_t>* normalRgba,
                                     const hsdf::ReferenceImage& reference, const engine::render::CameraView& camera,
                                     double spacing, const glm::mat4& model = glm::mat4(1.0f));

// The sphere around the world bounds of `asset` placed by `model`, for framing it.
struct WorldSphere {
  glm::vec3 center;
  float radius;
};
WorldSphere worldSphere(const hsdf::SdfAsset& asset, const glm::mat4& model);
// A camera 1.9 radii from the sphere's centre looking at it; views 0, 1, 2 come from different
// sides, above and below.
engine::render::CameraView orbitAround(const WorldSphere& sphere, int view);

// An orthographic camera with the pose of `camera` (a perspective one, e.g. orbitAround's): its view
// 2 ymag tall, depth between znear and zfar, for a square image. Fails the test on error.
engine::render::CameraView orthographicLike(const engine::render::CameraView& camera, float ymag, float znear, float zfar);

// Far cameras (the far-hit tests of the cells and the tracers, docs/reliability.md "Scales,
// distances and cameras"): a telephoto camera `distance` world units from `sphere`'s centre,
// framing it as orbit views do (half the image height is 0.8 radii at its centre), and the
// orthographic camera placed there (znear and zfar 2 radii around the centre).
std::pair<engine::render::CameraView, engine::render::CameraView> farCameras(const WorldSphere& sphere, double distance);
// The same for `asset`'s surface bounds, `cells` grid cells out.
std::pair<engine::render::CameraView, engine::render::CameraView> farCameras(const hsdf::SdfAsset& asset, double cells);

// An orthographic camera framing `sphere` from `distance` back (farCameras), and the same camera 3
// radii from the centre: its point moved along the axis the view draws, in double. Both draw the
// same pixel rays, so the near one's CPU reference is the far one's.
std::pair<engine::render::CameraView, engine::render::CameraView> farBackCameras(const WorldSphere& sphere, double distance);
std::pair<engine::render::CameraView, engine::render::CameraView> farBackCameras(const hsdf::SdfAsset& asset, double cells);

// The far-hit tests' orthographic camera, in cells back from the torus, and what they allow of its
// normals: at most kFarNormalOutlierShare of the reference's hits, interior pixels more than
// kFarNormalDegrees off the reference, and a normal error p99 below kFarNormalP99Degrees.
// Why these: 1e7 cells out (3e5 sizes of a 32-cell object) the prepass depth holds ~0.6 cell along
// the ray (orthographic: a float ulp of proj[3][2] + (z - proj[3][2]) t). The resolve rebuilds each
// hit from the offset the prepass stored beside the visibility instead (pixelRayStoredPoint): 0-9
// of the 22,354 hits more than 3 degrees off, p99 0.61-0.65 degrees in every cell form, as 1e6 and
// 3e6 cells back (0-1, 0.60), the reference's own distance from the GPU's interpolant near. Rebuilt
// from the depth: 12,297-13,011 (55-58 %), p99 20.5-22.2 (1e6: 78-109, p99 2.8-2.9).
inline constexpr double kFarHitCells = 1.0e7;
inline constexpr double kFarNormalDegrees = 3.0;
inline constexpr double kFarNormalOutlierShare = 0.002;
inline constexpr double kFarNormalP99Degrees = 1.5;

// Two objects of one asset for the far tests with two objects: the first where the asset is, the
// second turned a quarter about the view's horizontal axis and moved across the view by a quarter of
// its size and back by a twentieth, so that the two cross: on screen the second lies partly behind
// the first, partly in front of it and partly beside it. Each has its own anchor
// (HermiteDraw::rayAnchor, SphereTraceDraw::rayAnchor). `frame` holds both.
struct TwoObjects {
  glm::mat4 models[2];
  WorldSphere frame;
};
TwoObjects twoOverlappingObjects(const hsdf::SdfAsset& asset);

// The reference of both objects from one camera: pixel by pixel the nearer hit (reverse-Z: the
// greater depth) of their references. Fails the test unless each object wins over 2,000 pixels
// and both hit over 1,000 (the second partly hidden), so that the scene is what it must be.
hsdf::ReferenceImage nearerHits(hsdf::ReferenceImage first, const hsdf::ReferenceImage& second);

// A far frame's coverage: enough of it, at most `disagreements` pixels unlike the reference (a rim
// along the outline), no interior hole or extra.
void expectFarCoverage(const ImageComparison& c, int disagreements, int minHits = 10000);

// Interior pixels (away from silhouettes) whose normal is more than kFarNormalDegrees off the
// reference's, in a DEBUG_VIEW_NORMALS frame: at most `outlierShare` of the hits; the normal error
// p99 below `p99Degrees`. Prints the count.
void expectFarNormals(const Frame& normals, const hsdf::ReferenceImage& reference, const ImageComparison& c,
                      const std::string& label, double outlierShare = kFarNormalOutlierShare,
                      double p99Degrees = kFarNormalP99Degrees);

// The hermite_sdf GPU tests' fixture: GpuTest with the checks that several of them share.
class HermiteGpuTest : public GpuTest {
 protected:
  // The pipelines of each of the module's features once the warmers were done (none: 0 of 0).
  struct WarmedPipelines {
    engine::gpu::PipelineCounts cells;
    engine::gpu::PipelineCounts tracer;
  };
  // "A switch of method after warming compiles nothing in its frame" (the tuning panel's method,
  // the split screen's compared side; a compile takes hundreds of milliseconds on lavapipe). Twice,
  // warming on, then off: `createFeatures` makes a fresh renderer with the features under test
  // (their Settings::warmPipelines are then set), an entity draws `asset` with `start` for two
  // frames (the second starts the warmers), the warmers are waited for, and the entity switches to
  // each of `switches`, one frame each. Warmed, no switch frame may compile a pipeline of the
  // module's features; not warmed, they must compile some (else the check proves nothing); and every
  // switch frame draws the object (over 500 pixels) with the pixels of the one that never warmed.
  WarmedPipelines expectSwitchesAfterWarmingCompileNothing(const std::function<void()>& createFeatures,
                                                           const std::shared_ptr<const hsdf::SdfAsset>& asset,
                                                           const engine::render::CameraView& camera,
                                                           hsdf::RenderMethod start,
                                                           std::span<const hsdf::RenderMethod> switches);

 private:
  WarmedPipelines warmedCounts() const;
  std::uint32_t compiledByModule() const;
  void setWarming(bool warm);
  void waitForWarmers();
  std::vector<Frame> switchFrames(bool warm, const std::function<void()>& createFeatures,
                                  const std::shared_ptr<const hsdf::SdfAsset>& asset,
                                  const engine::render::CameraView& camera, hsdf::RenderMethod start,
                                  std::span<const hsdf::RenderMethod> switches, WarmedPipelines& warmed);
};

}  // namespace gputest
