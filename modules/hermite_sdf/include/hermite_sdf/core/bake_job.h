#pragma once
// The one bake pipeline of the module: source (triangles or an analytic shape) -> fitted grid ->
// budget check -> Hermite field (dense or narrow band) -> cell classification -> SdfAsset, with the
// "no surface" check at the end. hsdf_bake, the scene runner and the UI re-bake all go through
// bakeAsset(); BakeJob runs the same function on a worker thread.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include <glm/glm.hpp>

#include "engine/core/expected.h"
#include "engine/core/progress.h"
#include "engine/scene/scene_data.h"
#include "hermite_sdf/core/field.h"
#include "hermite_sdf/core/materials.h"
#include "hermite_sdf/core/sdf_asset.h"

namespace hsdf {

// What to bake. Either world-space triangles (shared: a UI re-bakes the same scene at another K
// without copying it) or the name of an analytic shape (analyticShapeNames()).
struct BakeSource {
  std::string name;  // names the asset and prefixes errors
  std::shared_ptr<const engine::scene::TriangleSoup> triangles;
  std::string shape;  // used when `triangles` is null
  // The triangles' materials (materials.h): a palette and a slot per triangle when they use two or
  // more, else null or empty (then the asset has no palette and the entity's colour shades it).
  std::shared_ptr<const MeshMaterials> materials;
  // fromScene: each placed mesh's node name and the longest side of its world bounds, so that a bake
  // can name the ones its grid is too coarse to hold (smallPartsWarning); empty for other sources.
  struct Part {
    std::string name;
    double size = 0.0;
  };
  std::vector<Part> parts;

  static BakeSource fromTriangles(std::string name, engine::scene::TriangleSoup triangles);
  static BakeSource fromShape(std::string shapeName);
  // Every mesh instance of a glTF scene in world space, shifted by -origin (flattenTriangles).
  // Errors: what checkFlattenable refuses.
  static engine::Expected<BakeSource> fromScene(std::string name, const engine::scene::SceneData& scene,
                                                const glm::dvec3& origin = glm::dvec3(0.0));
  // A path that exists is read as glTF/GLB (the loader names what is wrong with it); anything else
  // must be an analytic shape name (the error lists the known ones).
  static engine::Expected<BakeSource> fromPathOrShape(const std::string& input);
};

// A source ready to sample at the settings' shell thickness: the SdfSource and a one-line description ("bunny.glb: mesh, 3674
// triangles, closed, ..."). Preparing a mesh builds its BVH.
struct PreparedSource {
  std::string name;
  std::unique_ptr<SdfSource> source;
  std::string description;
  std::vector<SdfMaterial> palette;  // what the source's material slots index; empty: one material
  // Triangles of the input the bake leaves out as not the boundary of a solid (open parts that
  // bound no volume, parts inside the solid: MeshSourceStats); zero-area ones change nothing and
  // are not counted.
  std::size_t droppedTriangles = 0;
  double shellThickness = 0.0;  // what it was prepared for (BakeSettings::shellThickness)
};
struct BakeSettings;
// Errors: what the mesh or the shape refuses, and a shell of an analytic shape (it has no triangles).
engine::Expected<PreparedSource> prepareSource(const BakeSource& source, const BakeSettings& settings);
// The description, logged once per bake by the bakes that print nothing themselves (BakeJob, the
// scene's objects): an info, or a warning when triangles were dropped (what the bake lacks).
void logPreparedSource(const PreparedSource& prepared);

// Limits checked after the grid is fitted and BEFORE anything is allocated; a refusal names the
// limit ("bake budget: max resolution 128"). The kept cells are only known once the cells are
// classified: that limit is checked then, before their records are extracted.
struct BakeBudget {
  int maxResolution = kMaxResolution;
  std::uint64_t maxSamples = std::uint64_t(1) << 28;  // K^3 (256 M: K = 645)
  std::uint64_t maxBytes = std::uint64_t(4) << 30;    // see estimateBakeBytes
  std::uint64_t maxKeptCells = std::uint64_t(1) << 24;  // 16.8 M cells: 3.2 GB of fp32 + fp16 records
};

enum class BakeBand {
  Dense,       // every sample exact: the sphere-tracing baselines need it
  NarrowBand,  // exact near the surface only: enough for the cells (bakeHermiteFieldNarrowBand)
  // The cells alone, never a K^3 array (bakeCellsSparse): time and memory grow with the kept cells.
  // The asset has no dense field, so only the cell renderers draw it; the budget is the kept cells
  // (maxKeptCells, and maxBytes at sparseBakeBytesPerKeptCell a cell), checked while baking,
  // instead of maxSamples and the K^3 estimate.
  Sparse,
};

// The least padding a bake takes (planBake refuses less): with none, the surface lies on the
// grid's boundary.
inline constexpr int kMinBakePadding = 1;

struct BakeSettings {
  int resolution = 64;  // K samples per axis
  int padding = 1;      // P cells around the source bounds (fitGrid), at least kMinBakePadding
  BakeBand band = BakeBand::Dense;
  // The result will be stored in fp16 (.hsdf): refuse, before baking, grids fp16 cannot hold
  // (checkStorable). Drawing in fp16 needs no such check (renderers fall back to fp32).
  bool fp16 = false;
  // Triangles only: above 0, bake them as a shell of this thickness in the triangles' units
  // (MeshSourceOptions::shellThickness), for surfaces without an inside; 0 bakes the solid they
  // bound. A setting, not part of the source: a UI re-bakes one scene as a solid or a shell as it
  // re-bakes it at another K, and levels of detail keep the shell of their level 0.
  double shellThickness = 0.0;
  int refineDepth = 0;   // de Casteljau refinement of ambiguous cells (ClassifyOptions, 0..2)
  unsigned threads = 0;  // 0: all hardware threads
  BakeBudget budget;
};

// Progress in [0,1] over the whole job (bake, then classification) and cancellation. Either
// cancels: the callback returning false or the token; the job then fails with "cancelled".
struct BakeControl {
  engine::ProgressCallback progress;
  const engine::CancelToken* cancel = nullptr;
};

// Bytes the job allocates for a grid besides the kept cells: the field (16 B a sample, and its
// material slot, 1 B a sample, for a source of several materials: `materialSlots`), the narrow
// band's per-sample flags, one class byte per cell. 0 for the sparse bake: it allocates nothing per
// sample or cell of the grid, only per kept cell (checked while it bakes).
std::uint64_t estimateBakeBytes(const GridSpec& grid, BakeBand band, bool materialSlots = false);

// The grid a bake of `source` uses, after the budget and fp16 checks. Allocates nothing.
engine::Expected<GridSpec> planBake(const PreparedSource& source, const BakeSettings& settings);

// A shell (BakeSettings::shellThickness) thinner than one cell of `grid`: both of its faces lie
// between the same samples, so it bakes rough (half a cell: the bunny at K = 128), and with holes
// when far thinner. The warning's words, naming both sizes; nullopt for a solid or a thick shell.
std::optional<std::string> thinShellWarning(const BakeSettings& settings, const GridSpec& grid);

// Placed meshes of a flattened scene (BakeSource::parts) whose bounds, grown by the shell on each
// side, fit inside one cell of `grid`: no sample plane may cross them, so the bake loses them (or
// keeps a blob of a cell) without an error while the rest of the scene has a surface: a crate on a
// floor 1000 units wide at K = 64. The warning's words, naming them and both sizes; nullopt if none.
std::optional<std::string> smallPartsWarning(const BakeSource& source, const BakeSettings& settings, const GridSpec& grid);

// The whole pipeline. Errors name the step: grid fitting, budget (the limit), fp16 storage, bake
// ("cancelled" included), classification, and "the baked field has no surface" when no cell is kept.
engine::Expected<std::shared_ptr<const SdfAsset>> bakeAsset(const PreparedSource& source, const BakeSettings& settings,
                                                            const BakeControl& control = {});
// prepareSource, logPreparedSource, thinShellWarning and smallPartsWarning logged, bakeAsset.
engine::Expected<std::shared_ptr<const SdfAsset>> bakeAsset(const BakeSource& source, const BakeSettings& settings,
                                                            const BakeControl& control = {});

// bakeAsset on a worker thread, for a UI that keeps drawing the old asset meanwhile: poll
// progress(), cancel(), and take() the result once done(). Destroying a running job cancels it
// and waits for the thread.
class BakeJob {
 public:
  using Result = engine::Expected<std::shared_ptr<const SdfAsset>>;

  BakeJob(BakeSource source, BakeSettings settings);
  ~BakeJob();
  BakeJob(const BakeJob&) = delete;
  BakeJob& operator=(const BakeJob&) = delete;

  float progress() const { return progress_.load(std::memory_order_relaxed); }
  void cancel() { cancel_.cancel(); }
  // Whether cancel() was called (the job may still be running until its next check).
  bool cancelled() const { return cancel_.isCancelled(); }
  bool done() const { return done_.load(std::memory_order_acquire); }
  // Whether a caller may finish the job now without waiting for work it still wants: done, or
  // cancelled (wait() then returns at the worker's next check).
  bool finishable() const { return done() || cancelled(); }
  // The result once done() (then once only); nullopt while running or after it was taken.
  std::optional<Result> take();
  // Blocks until done, then take()s.
  Result wait();
  // Blocks until done and leaves the result for take() (a caller that puts it in the scene later,
  // as a frame does, waits without polling done()).
  void waitUntilDone();

  const BakeSettings& settings() const { return settings_; }

 private:
  void run(BakeSource source);

  BakeSettings settings_;
  engine::CancelToken cancel_;
  std::atomic<float> progress_{0.0f};
  std::atomic<bool> done_{false};
  std::mutex mutex_;
  std::condition_variable doneChanged_;  // notified once done_ is set, under mutex_
  std::optional<Result> result_;
  std::thread thread_;
};

}  // namespace hsdf
