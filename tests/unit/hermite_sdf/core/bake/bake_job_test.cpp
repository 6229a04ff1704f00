// The module bake job (hermite_sdf/core/bake_job.h): the one pipeline hsdf_bake, the scene runner and
// the UI re-bake share. Each case says what it would catch.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/core/log.h"
#include "hermite_sdf/core/bake_job.h"
#include "hermite_sdf/core/cells.h"

namespace hsdf {
namespace {

BakeSource bunnySource() {
  auto source = BakeSource::fromPathOrShape(std::string(HSDF_ASSET_DIR) + "/bunny.glb");
  EXPECT_TRUE(source.ok()) << source.error().message;
  return source.ok() ? *source : BakeSource::fromShape("sphere");
}

BakeSettings atResolution(int resolution) {
  BakeSettings settings;
  settings.resolution = resolution;
  return settings;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Tricky: the token is only polled between rows of work and the callback every 20 ms, so a bake
// that ignored them would still "succeed"; the bunny at K = 96 takes seconds, far longer than the
// first poll, so a result other than "cancelled" means cancellation did not stop the work.
TEST(BakeJob, ProgressCallbackReturningFalseCancelsTheBake) {
  BakeSettings settings;
  settings.resolution = 96;
  settings.threads = 1;
  int calls = 0;
  BakeControl control;
  control.progress = [&calls](float) { return ++calls > 1 ? true : false; };
  const auto result = bakeAsset(bunnySource(), settings, control);
  ASSERT_FALSE(result.ok());
  EXPECT_TRUE(contains(result.error().message, "cancelled")) << result.error().message;
  EXPECT_EQ(calls, 1) << "progress kept being reported after the bake was cancelled";
}

// Tricky: the token must be honoured before any sample is computed (a UI cancels a job that has
// not started yet); the progress callback must not see a single fraction.
TEST(BakeJob, CancelledTokenStopsBeforeAnyWork) {
  engine::CancelToken token;
  token.cancel();
  bool reported = false;
  BakeControl control;
  control.cancel = &token;
  control.progress = [&reported](float) { return reported = true; };
  BakeSettings settings;
  settings.resolution = 32;
  const auto result = bakeAsset(BakeSource::fromShape("torus"), settings, control);
  ASSERT_FALSE(result.ok());
  EXPECT_TRUE(contains(result.error().message, "cancelled")) << result.error().message;
  EXPECT_FALSE(reported);
}

// Tricky: cancel() races the worker; the bunny at K = 128 cannot finish between the constructor
// and the next statement, so "cancelled" proves the flag reaches the running bake, and wait()
// returning at all proves the thread stops.
TEST(BakeJob, WorkerThreadJobCancels) {
  BakeJob job(bunnySource(), atResolution(128));
  EXPECT_FALSE(job.finishable()) << "a running job that nobody cancelled is not finished";
  job.cancel();
  EXPECT_TRUE(job.finishable()) << "a cancelled job may be finished before the worker notices";
  const BakeJob::Result result = job.wait();
  ASSERT_FALSE(result.ok());
  EXPECT_TRUE(contains(result.error().message, "cancelled")) << result.error().message;
  EXPECT_TRUE(job.done());
}

// Why: a caller that puts the result in its scene later (the soak, waiting for a bake a frame
// started, then letting the next frame take it) needs a wait that leaves the result in place, not
// a poll of done(). Tricky: the bunny at K = 48 is still running right after the constructor, so
// returning early leaves done() false; the result must then be there for take(), once.
TEST(BakeJob, WaitUntilDoneBlocksAndLeavesTheResultToTake) {
  BakeJob job(bunnySource(), atResolution(48));
  ASSERT_FALSE(job.done()) << "the bake must outlast the constructor for the test to mean anything";
  job.waitUntilDone();
  EXPECT_TRUE(job.done());
  job.waitUntilDone();  // done already: returns at once
  std::optional<BakeJob::Result> result = job.take();
  ASSERT_TRUE(result.has_value()) << "the wait took the result";
  ASSERT_TRUE(result->ok()) << result->error().message;
  EXPECT_GT((**result)->cells.records.size(), 0u);
}

// Tricky: each limit is checked on numbers alone. K = 4096 is 6.9e10 samples (1.1 TB): had the job
// allocated first, it would fail with an allocation error (or be killed), not name the limit.
TEST(BakeJob, BudgetRefusesBeforeAllocatingAndNamesTheLimit) {
  const BakeSource torus = BakeSource::fromShape("torus");
  bool reported = false;
  BakeControl control;
  control.progress = [&reported](float) { return reported = true; };

  BakeSettings huge;
  huge.resolution = kMaxResolution;
  auto result = bakeAsset(torus, huge, control);
  ASSERT_FALSE(result.ok());
  EXPECT_TRUE(contains(result.error().message, "over the bake budget's max samples 268435456")) << result.error().message;

  BakeSettings overK;
  overK.resolution = 65;
  overK.budget.maxResolution = 64;
  result = bakeAsset(torus, overK, control);
  ASSERT_FALSE(result.ok());
  EXPECT_TRUE(contains(result.error().message, "resolution 65 is over the bake budget's max resolution 64"))
      << result.error().message;

  // One byte under what K = 32 needs: the estimate must cover the field and the cell classes.
  BakeSettings overBytes;
  overBytes.resolution = 32;
  auto prepared = prepareSource(torus, BakeSettings{});
  ASSERT_TRUE(prepared.ok());
  auto grid = planBake(*prepared, overBytes);
  ASSERT_TRUE(grid.ok());
  const std::uint64_t needed = estimateBakeBytes(*grid, BakeBand::Dense);
  EXPECT_EQ(needed, 32ull * 32 * 32 * sizeof(HermiteSample) + 31ull * 31 * 31);
  overBytes.budget.maxBytes = needed - 1;
  result = bakeAsset(torus, overBytes, control);
  ASSERT_FALSE(result.ok());
  EXPECT_TRUE(contains(result.error().message, "over the bake budget's max bytes " + std::to_string(needed - 1)))
      << result.error().message;
  overBytes.budget.maxBytes = needed;
  EXPECT_TRUE(bakeAsset(torus, overBytes).ok()) << "the exact budget must be enough";
  EXPECT_FALSE(reported) << "a refused bake reported progress, so it started working";
}

// Tricky: the kept cells are known only after classification, so this limit cannot be checked on
// the grid alone; it must still refuse before the records are extracted, name the count and the
// limit, and let exactly the limit through (off by one would refuse a field that fits).
TEST(BakeJob, KeptCellBudgetRefusesNamingTheCountAndTheLimit) {
  const BakeSource torus = BakeSource::fromShape("torus");
  BakeSettings settings;
  settings.resolution = 16;
  auto full = bakeAsset(torus, settings);
  ASSERT_TRUE(full.ok()) << full.error().message;
  const std::uint64_t kept = (*full)->classification.stats.kept();
  ASSERT_GT(kept, 100u);

  settings.budget.maxKeptCells = kept - 1;
  auto refused = bakeAsset(torus, settings);
  ASSERT_FALSE(refused.ok());
  EXPECT_TRUE(contains(refused.error().message, std::to_string(kept) + " kept cells, over the budget's max kept cells " +
                                                    std::to_string(kept - 1)))
      << refused.error().message;
  settings.budget.maxKeptCells = kept;
  auto fits = bakeAsset(torus, settings);
  ASSERT_TRUE(fits.ok()) << fits.error().message;
  EXPECT_EQ((*fits)->cells.records.size(), kept);
}

// Tricky: the worker thread must run the very same pipeline (settings, band, refinement), not a
// variant of it: the fields must be bitwise equal and the kept cells identical.
TEST(BakeJob, WorkerThreadResultEqualsSynchronousResult) {
  BakeSettings settings;
  settings.resolution = 24;
  settings.padding = 2;
  settings.band = BakeBand::NarrowBand;
  settings.refineDepth = 1;
  const BakeSource blob = BakeSource::fromShape("blob");
  const auto sync = bakeAsset(blob, settings);
  ASSERT_TRUE(sync.ok()) << sync.error().message;
  BakeJob job(blob, settings);
  const BakeJob::Result threaded = job.wait();
  ASSERT_TRUE(threaded.ok()) << threaded.error().message;
  EXPECT_TRUE(job.finishable());
  EXPECT_FLOAT_EQ(job.progress(), 1.0f);
  const SdfAsset& a = **sync;
  const SdfAsset& b = **threaded;
  EXPECT_NE(a.id, b.id);
  EXPECT_EQ(a.field.grid.resolution, 24);
  ASSERT_EQ(a.field.samples.size(), b.field.samples.size());
  EXPECT_EQ(0, std::memcmp(a.field.samples.data(), b.field.samples.data(), a.field.samples.size() * sizeof(HermiteSample)));
  ASSERT_EQ(a.cells.records.size(), b.cells.records.size());
  ASSERT_GT(a.cells.records.size(), 0u);
  EXPECT_EQ(0, std::memcmp(a.cells.records.data(), b.cells.records.data(), a.cells.records.size() * sizeof(CellRecord)));
  EXPECT_EQ(a.classification.refineDepth, 1);
  EXPECT_FALSE(job.take().has_value()) << "the result can be taken once";
}

// Tricky: progress is reported over the whole job (bake, then classification): it must never go
// backwards when the phases hand over, and must end at exactly 1.
TEST(BakeJob, ProgressIsMonotoneAndEndsAtOne) {
  std::vector<float> fractions;
  BakeControl control;
  control.progress = [&fractions](float f) {
    fractions.push_back(f);
    return true;
  };
  BakeSettings settings;
  settings.resolution = 48;
  ASSERT_TRUE(bakeAsset(bunnySource(), settings, control).ok());
  ASSERT_FALSE(fractions.empty());
  for (std::size_t i = 1; i < fractions.size(); ++i) EXPECT_LE(fractions[i - 1], fractions[i]);
  EXPECT_EQ(fractions.back(), 1.0f);
}

// Tricky: a closed slab 0.01 thick bounds a volume, but at K = 8 no sample falls inside it: the
// field is positive everywhere. The bake itself succeeds and only the classification shows there is
// nothing to draw. (An open square is refused before, by the mesh source: MeshSign tests.)
TEST(BakeJob, FieldWithoutSurfaceIsAnError) {
  engine::scene::TriangleSoup slab;
  for (const float y : {0.0f, 0.01f})
    for (const glm::vec2 xz : {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(1, 1), glm::vec2(0, 1)})
      slab.positions.push_back({xz.x, y, xz.y});
  // Outward windings: bottom (y = 0) faces down, top faces up, four sides.
  slab.indices = {0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6, 0, 4, 5, 0, 5, 1, 1, 5, 6, 1, 6, 2,
                  2, 6, 7, 2, 7, 3, 3, 7, 4, 3, 4, 0};
  BakeSettings settings;
  settings.resolution = 8;
  const auto result = bakeAsset(BakeSource::fromTriangles("slab", slab), settings);
  ASSERT_FALSE(result.ok());
  EXPECT_TRUE(contains(result.error().message, "the baked field has no surface: none of its 343 cells changes sign"))
      << result.error().message;
}

// Tricky: fp16 storage of a grid finer than 2^-13 is refused before the bake (it would lose the
// values near the surface), while the same grid in fp32 bakes.
TEST(BakeJob, Fp16StorageRefusesTooFineGrids) {
  engine::scene::TriangleSoup tiny;
  const float s = 1e-4f;
  tiny.positions = {{0, 0, 0}, {s, 0, 0}, {0, s, 0}, {0, 0, s}};
  tiny.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  BakeSettings settings;
  settings.resolution = 16;
  settings.fp16 = true;
  const BakeSource source = BakeSource::fromTriangles("tiny", tiny);
  const auto refused = bakeAsset(source, settings);
  ASSERT_FALSE(refused.ok());
  EXPECT_TRUE(contains(refused.error().message, "fp16: fp16 needs a grid spacing of at least 2^-13"))
      << refused.error().message;
  settings.fp16 = false;
  const auto baked = bakeAsset(source, settings);
  EXPECT_TRUE(baked.ok()) << baked.error().message;
}

// Tricky: a lone sheet bounds no volume, so the solid bake refuses it; as a shell it bakes in
// every band, the sparse descent (which skips bricks by the band queries' bounds, here asked for
// triangles within band + t/2) keeping exactly the dense bake's cells, each of them at the shell's
// two faces (|z| = t/2 over the square) or its rim, on both sides of the sheet.
TEST(BakeJob, AShellBakesWhatTheSolidBakeRefusesOnBothSidesOfTheSheet) {
  engine::scene::TriangleSoup sheet;
  sheet.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  sheet.indices = {0, 1, 2, 0, 2, 3};
  BakeSource source = BakeSource::fromTriangles("sheet", sheet);
  BakeSettings settings;
  settings.resolution = 24;
  const auto solid = bakeAsset(source, settings);
  ASSERT_FALSE(solid.ok());
  EXPECT_TRUE(contains(solid.error().message, "bounds no volume")) << solid.error().message;

  const double thickness = 0.15;
  settings.shellThickness = thickness;
  std::vector<std::vector<CellRecord>> kept;
  for (const BakeBand band : {BakeBand::Dense, BakeBand::Sparse}) {
    settings.band = band;
    const auto baked = bakeAsset(source, settings);
    ASSERT_TRUE(baked.ok()) << baked.error().message;
    const CellStream& cells = (*baked)->cells;
    const double h = cells.grid.spacing;
    ASSERT_GT(thickness, 2.0 * h) << "the test wants both faces resolved";
    int above = 0, below = 0;
    for (const CellRecord& r : cells.records) {
      const glm::dvec3 centre = glm::dvec3(cells.grid.origin) + (glm::dvec3(r.x, r.y, r.z) + 0.5) * h;
      const glm::dvec2 past = glm::max(glm::abs(glm::dvec2(centre.x, centre.y) - 0.5) - 0.5, 0.0);
      const double toShell = std::sqrt(glm::dot(past, past) + centre.z * centre.z) - 0.5 * thickness;
      EXPECT_LE(std::abs(toShell), std::sqrt(3.0) * h) << r.x << " " << r.y << " " << r.z;
      above += centre.z > 0.0;
      below += centre.z < 0.0;
    }
    EXPECT_GT(above, 100);
    EXPECT_GT(below, 100);
    kept.push_back(cells.records);
  }
  ASSERT_EQ(kept[0].size(), kept[1].size());
  EXPECT_EQ(std::memcmp(kept[0].data(), kept[1].data(), kept[0].size() * sizeof(CellRecord)), 0);
}

// Tricky: an analytic shape has no triangles to put a shell around; taking the option silently
// would bake the solid the user did not ask for.
TEST(BakeJob, AShellOfAnAnalyticShapeIsRefused) {
  BakeSource source = BakeSource::fromShape("torus");
  BakeSettings shell;
  shell.shellThickness = 0.1;
  const auto refused = bakeAsset(source, shell);
  ASSERT_FALSE(refused.ok());
  EXPECT_TRUE(contains(refused.error().message, "torus: a shell is baked around triangles")) << refused.error().message;
}

// Tricky: the thickness is in the prepared source (its distances and bounds) and in the settings
// (what a UI compares to decide a re-bake, what levels of detail copy): a source prepared for one
// thickness baked with settings naming another would draw one surface labelled as the other.
TEST(BakeJob, ASourcePreparedForAnotherShellThicknessIsRefusedNamingBoth) {
  engine::scene::TriangleSoup sheet;
  sheet.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  sheet.indices = {0, 1, 2, 0, 2, 3};
  BakeSettings thin;
  thin.resolution = 16;
  thin.shellThickness = 0.1;
  auto prepared = prepareSource(BakeSource::fromTriangles("sheet", sheet), thin);
  ASSERT_TRUE(prepared.ok()) << prepared.error().message;
  EXPECT_TRUE(bakeAsset(*prepared, thin).ok());
  BakeSettings thick = thin;
  thick.shellThickness = 0.3;
  const auto refused = bakeAsset(*prepared, thick);
  ASSERT_FALSE(refused.ok());
  EXPECT_TRUE(contains(refused.error().message, "shell thickness 0.3: 'sheet' was prepared for 0.1"))
      << refused.error().message;
}

// Tricky: fitGrid itself takes padding 0 (a grid may hug any box), and a cube baked so drew its
// faces with holes and specks in every method, its surface on the grid's boundary. Every band of
// the one pipeline refuses it before baking, naming the padding; one cell bakes.
TEST(BakeJob, PaddingBelowOneCellIsRefusedNamingIt) {
  BakeSettings settings;
  settings.resolution = 8;
  for (const BakeBand band : {BakeBand::Dense, BakeBand::NarrowBand, BakeBand::Sparse}) {
    settings.band = band;
    for (const int padding : {0, -1}) {
      settings.padding = padding;
      const auto refused = bakeAsset(BakeSource::fromShape("box"), settings);
      ASSERT_FALSE(refused.ok());
      EXPECT_TRUE(contains(refused.error().message, "padding " + std::to_string(padding) + ": a bake needs at least 1 cell"))
          << refused.error().message;
    }
    settings.padding = kMinBakePadding;
    const auto baked = bakeAsset(BakeSource::fromShape("box"), settings);
    EXPECT_TRUE(baked.ok()) << baked.error().message;
  }
}

TEST(BakeJob, UnknownInputListsTheShapes) {
  const auto source = BakeSource::fromPathOrShape("no_such_shape");
  ASSERT_FALSE(source.ok());
  EXPECT_TRUE(contains(source.error().message, "'no_such_shape' is neither a file nor an analytic shape"));
  EXPECT_TRUE(contains(source.error().message, "torus"));
}

// Every message logged while it lives, with its level.
class LogCapture {
 public:
  LogCapture() {
    engine::log::setSink([this](engine::log::Level level, std::string_view message) { messages.emplace_back(level, message); });
  }
  ~LogCapture() { engine::log::setSink({}); }
  LogCapture(const LogCapture&) = delete;
  LogCapture& operator=(const LogCapture&) = delete;
  std::vector<std::pair<engine::log::Level, std::string>> messages;
};

// Tricky: only hsdf_bake printed what a bake left out ("2 dropped: open parts that bound no
// volume"); the scene runner and the Viewer bake through the job and said nothing, so a floor or a
// decal that vanished from the SDF left no trace in their logs. The job logs the same description
// once per bake: a warning when triangles were dropped (the bake lacks them), else an info.
TEST(BakeJob, TheBakeLogsWhatItDroppedOnce) {
  engine::scene::TriangleSoup scene;
  // A closed tetrahedron on a floor quad twenty times its size, one mesh.
  scene.positions = {{0, 0.1f, 0}, {1, 0.1f, 0}, {0, 1.1f, 0}, {0, 0.1f, 1}, {-10, 0, -10}, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}};
  scene.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3, 4, 5, 6, 4, 6, 7};
  BakeSettings settings;
  settings.resolution = 12;
  {
    LogCapture log;
    BakeJob job(BakeSource::fromTriangles("tetra on a floor", scene), settings);
    ASSERT_TRUE(job.wait().ok());
    ASSERT_EQ(log.messages.size(), 1u);
    EXPECT_EQ(log.messages[0].first, engine::log::Level::Warning);
    EXPECT_TRUE(contains(log.messages[0].second,
                         "bake: tetra on a floor: mesh, 4 triangles (2 dropped: open parts that bound no volume"))
        << log.messages[0].second;
  }
  scene.indices.resize(12);
  LogCapture log;
  ASSERT_TRUE(bakeAsset(BakeSource::fromTriangles("tetra", scene), settings).ok());
  ASSERT_EQ(log.messages.size(), 1u);
  EXPECT_EQ(log.messages[0].first, engine::log::Level::Info);
  EXPECT_EQ(log.messages[0].second, "bake: tetra: mesh, 4 triangles, closed, sign from pseudonormals");
}

// A closed unit cube (12 triangles) placed by a node of `scale` at `at`.
engine::scene::NodeData cubeNode(std::string name, const glm::vec3& at, const glm::vec3& scale) {
  engine::scene::NodeData node;
  node.name = std::move(name);
  node.local = node.world = glm::scale(glm::translate(glm::mat4(1.0f), at), scale);
  node.mesh = 0;
  return node;
}

engine::scene::SceneData floorAndCrateScene() {
  engine::scene::MeshPrimitiveData cube;
  for (int c = 0; c < 8; ++c)
    cube.positions.push_back({float(c & 1) - 0.5f, float((c >> 1) & 1) - 0.5f, float((c >> 2) & 1) - 0.5f});
  cube.indices = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  cube.normals.assign(8, glm::vec3(0.0f));
  engine::scene::SceneData scene;
  scene.meshes.push_back({"cube", {cube}});
  scene.nodes.push_back(cubeNode("floor", {0, -50, 0}, {1000, 100, 1000}));
  scene.nodes.push_back(cubeNode("crate", {10, 0.5f, 10}, {1, 1, 1}));
  return scene;
}

// Tricky: a crate 1 unit wide on a floor 1000 units wide (an exported level) baked as one SDF: at
// K = 64 a cell is 16 units, no sample plane crosses the crate and the bake drops it, with no error
// (the floor has a surface) and nothing in the log. The warning names the node and both sizes, for
// the bake jobs (the scene runner, the Viewer) and hsdf_bake alike, and goes once the grid is
// fine enough to hold it.
TEST(BakeJob, APlacedMeshInsideOneCellIsNamed) {
  const auto source = BakeSource::fromScene("level", floorAndCrateScene());
  ASSERT_TRUE(source.ok()) << source.error().message;
  ASSERT_EQ(source->parts.size(), 2u);
  EXPECT_EQ(source->parts[1].name, "'crate'");
  EXPECT_NEAR(source->parts[1].size, 1.0, 1e-6);
  BakeSettings settings = atResolution(64);
  const auto prepared = prepareSource(*source, settings);
  ASSERT_TRUE(prepared.ok()) << prepared.error().message;
  const auto coarse = planBake(*prepared, settings);
  ASSERT_TRUE(coarse.ok()) << coarse.error().message;
  const auto warning = smallPartsWarning(*source, settings, *coarse);
  ASSERT_TRUE(warning.has_value()) << "grid spacing " << coarse->spacing;
  EXPECT_TRUE(contains(*warning, "1 of the 2 placed meshes fits inside one grid cell")) << *warning;
  EXPECT_TRUE(contains(*warning, "'crate' (1)")) << *warning;
  EXPECT_FALSE(contains(*warning, "floor")) << *warning;
  {
    LogCapture log;
    ASSERT_TRUE(bakeAsset(*source, settings).ok());
    bool logged = false;
    for (const auto& [level, text] : log.messages) logged |= level == engine::log::Level::Warning && contains(text, "'crate' (1)");
    EXPECT_TRUE(logged) << "the bake did not log the lost crate";
  }
  // A shell half a unit thick makes the crate 2 wide; still inside a 16-unit cell. At K = 2048 a
  // cell is about half a unit (a sparse bake's plan): the crate is held, and named no more.
  settings.shellThickness = 0.5;
  EXPECT_TRUE(smallPartsWarning(*source, settings, *coarse).has_value());
  settings.shellThickness = 0.0;
  settings.resolution = 2048;
  settings.band = BakeBand::Sparse;  // planned only: a dense field at K = 2048 is over the budget
  const auto fine = planBake(*prepared, settings);
  ASSERT_TRUE(fine.ok()) << fine.error().message;
  ASSERT_LT(fine->spacing, 1.0);
  EXPECT_FALSE(smallPartsWarning(*source, settings, *fine).has_value()) << *smallPartsWarning(*source, settings, *fine);
}

}  // namespace
}  // namespace hsdf
