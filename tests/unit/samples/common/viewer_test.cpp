// The Viewer (samples/common/viewer.h), headless on the test device (HSDF_TEST_DEVICE, lavapipe
// unless set) with the validation layers on: what the perf capture and the soak test rely on.
// Small images (64x48) keep it fast.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <imgui.h>
#include <imgui_internal.h>  // ImGuiWindow: where the panel's controls reached
#include <nlohmann/json.hpp>

#include "hermite_sdf/core/hsdf_file.h"
#include "test_viewer.h"
#include "tuning_panel.h"

namespace samples {
namespace {

std::unique_ptr<Viewer> makeViewer(const hsdf::BakeBudget& budget = {}) { return makeTestViewer(64, 48, budget); }

// Share of pixels that differ from the top-left one (background: the object is framed in the
// middle and the ground plane is off).
double coverage(Viewer& viewer) {
  viewer.renderer().finish();
  const std::vector<std::uint8_t> rgba = viewer.renderer().readbackColor();
  std::size_t covered = 0;
  for (std::size_t i = 0; i < rgba.size(); i += 4)
    for (std::size_t c = 0; c < 3; ++c)
      if (rgba[i + c] != rgba[c]) {
        ++covered;
        break;
      }
  return double(covered) / double(rgba.size() / 4);
}

const hsdf::HermiteSdfRenderable& theSdf(Viewer& viewer) {
  const hsdf::HermiteSdfRenderable* found = nullptr;
  viewer.registry().view<hsdf::HermiteSdfRenderable>().each(
      [&found](engine::ecs::Entity, const hsdf::HermiteSdfRenderable& r) { found = &r; });
  EXPECT_NE(found, nullptr);
  return *found;
}

// A torus baked at K = `resolution`, drawn with Hermite cells, without the ground plane.
std::unique_ptr<Viewer> viewTorus(int resolution) {
  auto viewer = makeViewer();
  if (!viewer) return nullptr;
  SceneDesc scene;
  scene.shape = "torus";
  scene.groundPlane = false;
  TuningState tuning;
  tuning.method = hsdf::RenderMethod::Cells;
  tuning.resolution = resolution;
  const engine::Status loaded = viewer->loadScene(scene, tuning);
  EXPECT_TRUE(loaded.ok()) << loaded.error().message;
  return loaded.ok() ? std::move(viewer) : nullptr;
}

// Why: the panel's and the capture's GPU timings name each method's pass inside the depth prepass;
// a scope must hold its own work, whatever was drawn before it in the same render pass (here the
// ground plane). Lavapipe stamps a timestamp that shares its scene with draws about when its last
// screen bin reached it (GpuTimer::slotsPerScope_): behind the ground, the tracers' and the
// tiles' prepass read ~0.1 % of the depth prepass they make up. On every device the method's
// search is by far the larger part of the pass.
TEST(Viewer, EachMethodsPrepassTimingHoldsItsWorkBehindTheGround) {
  auto viewer = makeTestViewer(192, 144);
  ASSERT_NE(viewer, nullptr);
  if (!viewer->context().capabilities().timestamps) GTEST_SKIP() << "no timestamp queries on this device";
  SceneDesc scene;
  scene.shape = "torus";
  scene.groundPlane = true;
  TuningState tuning;
  tuning.resolution = 32;
  ASSERT_TRUE(viewer->loadScene(scene, tuning).ok());
  const auto milliseconds = [&](const std::string& name) {
    const engine::gpu::GpuTiming* timing = engine::gpu::findTiming(viewer->renderer().lastTimings(), name);
    if (!timing) ADD_FAILURE() << "no timing named '" << name << "'";
    return timing ? timing->milliseconds : 0.0;
  };
  for (const auto& [method, scope] : {std::pair{hsdf::RenderMethod::HermiteSphereTrace, "hermite prepass"},
                                      std::pair{hsdf::RenderMethod::TrilinearSphereTrace, "trilinear prepass"},
                                      std::pair{hsdf::RenderMethod::Cells, "cells prepass"},
                                      std::pair{hsdf::RenderMethod::CellRuns, "cells prepass"},
                                      std::pair{hsdf::RenderMethod::CellBricks, "cells prepass"}}) {
    tuning.method = method;
    viewer->setTuning(tuning);
    ASSERT_TRUE(viewer->waitForBake().ok());
    ASSERT_TRUE(viewer->step().ok());
    ASSERT_TRUE(viewer->step().ok());
    viewer->renderer().finish();
    const double pass = milliseconds("depth prepass"), own = milliseconds(scope);
    EXPECT_GT(own, 0.3 * pass) << scope << " of method " << int(method) << ": " << own << " of " << pass << " ms";
    EXPECT_LE(own, pass * 1.001 + 1e-6) << scope << " is timed inside the depth prepass";
  }
}

// Tricky: a new K must go through the bake job and land in the same entity (new asset, new grid,
// different kept cells) while the scene keeps drawing; tuning changes between frames must reach
// the component; and none of it may provoke a validation message (close() counts them).
TEST(Viewer, RebakesAndRetunesBetweenFrames) {
  auto viewer = viewTorus(16);
  ASSERT_NE(viewer, nullptr);
  TuningState tuning = viewer->tuning();
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_GT(coverage(*viewer), 0.05);
  const std::uint64_t firstId = theSdf(*viewer).asset->id;
  const std::size_t firstCells = theSdf(*viewer).asset->cells.records.size();

  tuning.resolution = 24;
  viewer->setTuning(tuning);
  ASSERT_NE(viewer->bakeJob(), nullptr);
  ASSERT_TRUE(viewer->step().ok()) << "frames keep coming while the re-bake runs";
  ASSERT_TRUE(viewer->waitForBake().ok());
  EXPECT_EQ(viewer->bakeJob(), nullptr);
  const hsdf::SdfAsset& rebaked = *theSdf(*viewer).asset;
  EXPECT_NE(rebaked.id, firstId);
  EXPECT_EQ(rebaked.field.grid.resolution, 24);
  EXPECT_NE(rebaked.cells.records.size(), firstCells);

  tuning.method = hsdf::RenderMethod::TrilinearSphereTrace;
  tuning.subdivisions = 5;
  tuning.normals = hsdf::NormalMode::CentralDifferences;
  viewer->setTuning(tuning);
  EXPECT_EQ(viewer->bakeJob(), nullptr) << "same K and padding: no re-bake";
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_EQ(theSdf(*viewer).method, hsdf::RenderMethod::TrilinearSphereTrace);
  EXPECT_EQ(theSdf(*viewer).subdivisions, 5u);
  EXPECT_EQ(theSdf(*viewer).normals, hsdf::NormalMode::CentralDifferences);
  EXPECT_GT(coverage(*viewer), 0.05);
  EXPECT_EQ(viewer->framesRendered(), 3u);
  const engine::Status closed = viewer->close();
  EXPECT_TRUE(closed.ok()) << closed.error().message;
}

// Tricky: a re-bake that fails (K = 3 leaves no cell inside the padding) must report why and
// leave the old asset drawing, not an entity without a field.
TEST(Viewer, FailedRebakeKeepsTheOldAsset) {
  auto viewer = viewTorus(12);
  ASSERT_NE(viewer, nullptr);
  TuningState tuning = viewer->tuning();
  const std::uint64_t id = theSdf(*viewer).asset->id;
  tuning.resolution = 3;
  viewer->setTuning(tuning);
  const engine::Status baked = viewer->waitForBake();
  ASSERT_FALSE(baked.ok());
  EXPECT_NE(baked.error().message.find("re-baking at resolution 3: fitting the grid"), std::string::npos)
      << baked.error().message;
  EXPECT_EQ(theSdf(*viewer).asset->id, id);
  tuning.resolution = 12;
  viewer->setTuning(tuning);
  EXPECT_EQ(viewer->bakeJob(), nullptr) << "K back to the one drawn: nothing to re-bake";
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_GT(coverage(*viewer), 0.05);
  EXPECT_TRUE(viewer->close().ok());
}

// Tricky: an explicit camera must put the eye exactly there (the orbit controller stores it as
// yaw/pitch/radius), and an orbit view must replace it.
TEST(Viewer, ExplicitCameraAndOrbitViews) {
  auto viewer = viewTorus(12);
  ASSERT_NE(viewer, nullptr);
  viewer->setCamera(glm::dvec3(1.0, 2.0, 4.0), glm::dvec3(0.5, 0.0, 0.0));
  const glm::vec3 eye = viewer->cameraView().position;
  EXPECT_NEAR(eye.x, 1.0f, 1e-5f);
  EXPECT_NEAR(eye.y, 2.0f, 1e-5f);
  EXPECT_NEAR(eye.z, 4.0f, 1e-5f);
  viewer->setOrbitView(2);
  const glm::vec3 view2 = viewer->cameraView().position;
  viewer->setOrbitView(5);
  EXPECT_GT(glm::length(viewer->cameraView().position - view2), 0.1f);
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_GT(coverage(*viewer), 0.05);
  EXPECT_TRUE(viewer->close().ok());
}

// Tricky: the panel's storage table must count what the methods store: every cell in exactly one
// class, 32 scalars per kept cell record (8 corners x value + gradient), K^3 values for trilinear
// and 4 K^3 for dense Hermite; fp16 records are smaller than fp32 ones. A re-bake must change them.
TEST(Viewer, StatsCountEveryCellAndMethod) {
  auto viewer = viewTorus(12);
  ASSERT_NE(viewer, nullptr);
  const SdfStats s = sdfStats(*viewer->sdfAsset());
  EXPECT_EQ(s.resolution, 12);
  EXPECT_EQ(s.cells.cells, 11u * 11u * 11u);
  EXPECT_EQ(s.cells.crossing + s.cells.ambiguous + s.cells.empty, s.cells.cells);
  EXPECT_EQ(s.cellScalars, 32u * viewer->sdfAsset()->cells.records.size());
  EXPECT_GT(s.cellScalars, 0u);
  EXPECT_LT(s.cellBytesHalf, s.cellBytes);
  EXPECT_EQ(s.trilinearScalars, 12u * 12u * 12u);
  EXPECT_EQ(s.hermiteScalars, 4u * 12u * 12u * 12u);
  EXPECT_NE(describeSdfStats(s).find("stored scalars: cells " + std::to_string(s.cellScalars)), std::string::npos);
  TuningState tuning = viewer->tuning();
  tuning.resolution = 20;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->waitForBake().ok());
  EXPECT_EQ(sdfStats(*viewer->sdfAsset()).trilinearScalars, 20u * 20u * 20u);
  EXPECT_NE(sdfStats(*viewer->sdfAsset()).cellScalars, s.cellScalars);
  EXPECT_TRUE(viewer->close().ok());
}

bool sameView(const engine::render::CameraView& a, const engine::render::CameraView& b) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (std::abs(a.view[c][r] - b.view[c][r]) > 1e-4f) return false;
  return true;
}

// Tricky: switching between the orbit and the fly camera must keep the eye and the view direction
// (the fly controller stores yaw/pitch with its own sign conventions), both ways, else the image
// jumps when a user presses F2.
TEST(Viewer, CameraModesKeepTheView) {
  auto viewer = viewTorus(12);
  ASSERT_NE(viewer, nullptr);
  viewer->setCamera(glm::dvec3(1.0, 2.0, 4.0), glm::dvec3(0.5, 0.0, 0.0));
  const engine::render::CameraView orbit = viewer->cameraView();
  viewer->setCameraMode(CameraMode::Fly);
  EXPECT_EQ(viewer->cameraMode(), CameraMode::Fly);
  EXPECT_TRUE(sameView(viewer->cameraView(), orbit)) << "orbit -> fly moved the camera";
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_GT(coverage(*viewer), 0.05);
  viewer->setCameraMode(CameraMode::Orbit);
  EXPECT_TRUE(sameView(viewer->cameraView(), orbit)) << "fly -> orbit moved the camera";
  EXPECT_TRUE(viewer->close().ok());
}

std::size_t meshCount(Viewer& viewer) {
  std::size_t count = 0;
  viewer.registry().view<engine::render::MeshRenderable>().each(
      [&count](engine::ecs::Entity, const engine::render::MeshRenderable&) { ++count; });
  return count;
}

std::size_t sdfCount(Viewer& viewer) {
  std::size_t count = 0;
  viewer.registry().view<hsdf::HermiteSdfRenderable>().each(
      [&count](engine::ecs::Entity, const hsdf::HermiteSdfRenderable&) { ++count; });
  return count;
}

// Tricky: a glTF scene loaded as meshes has no SDF yet: picking an SDF method must bake it on the
// worker thread while the meshes keep drawing, then show only the SDF; picking the mesh again must
// bring the same mesh entities back and hide (not drop) the SDF, which returns without a re-bake.
// Tricky: the baked SDF stands for the scene's meshes and takes their colour: the bunny's material,
// and for a mesh without a material the grey its triangles are drawn in (it was the SDF
// component's own terracotta default, found by a helper).
TEST(Viewer, TheSdfTakesTheColourOfTheMeshItStandsFor) {
  for (const auto& [file, colour] : {std::pair{hsdftest::sampleAsset("bunny.glb"), glm::vec4(0.8f, 0.45f, 0.3f, 1.0f)},
                                     std::pair{hsdftest::testData("gltf/tilted_cube.gltf"),
                                               engine::scene::MaterialData{}.baseColor}}) {
    auto viewer = makeViewer();
    ASSERT_NE(viewer, nullptr);
    SceneDesc scene;
    scene.gltf = file;
    TuningState tuning;
    tuning.method = hsdf::RenderMethod::Cells;
    tuning.resolution = 16;
    ASSERT_TRUE(viewer->loadScene(scene, tuning).ok());
    EXPECT_EQ(theSdf(*viewer).color, colour) << file;
    EXPECT_TRUE(viewer->close().ok());
  }
}

// Which of the two-material box's colours a pixel shows: 0 red, 1 blue, -1 neither (background,
// ground, a grey pixel).
int redOrBlue(const std::uint8_t* rgba) {
  const double r = rgba[0], b = rgba[2];
  return r > 1.3 * b + 4.0 ? 0 : (b > 1.3 * r + 4.0 ? 1 : -1);
}

// Tricky: a glTF mesh of two primitives in two materials (red top, blue bottom) baked as one SDF
// must draw both, where its triangles draw them: before, the SDF took the first primitive's colour
// and drew the blue half red. The entity is white (its colour multiplies the palette). The mesh's
// and the cells' images are compared pixel by pixel: the colours may differ only along the seam,
// where the SDF's colour follows the nearest grid sample (within a cell of the triangles' split).
TEST(Viewer, AMeshOfTwoMaterialsDrawsBothAsAnSdf) {
  auto viewer = makeTestViewer(128, 96);
  ASSERT_NE(viewer, nullptr);
  SceneDesc scene;
  scene.gltf = hsdftest::testData("materials/two_material_box.glb");
  scene.groundPlane = false;
  TuningState tuning;
  tuning.method = hsdf::RenderMethod::Cells;
  tuning.resolution = 32;
  ASSERT_TRUE(viewer->loadScene(scene, tuning).ok());
  EXPECT_EQ(theSdf(*viewer).color, glm::vec4(1.0f));
  ASSERT_NE(viewer->sdfAsset(), nullptr);
  EXPECT_EQ(viewer->sdfAsset()->palette.size(), 2u);
  const auto frame = [&viewer](Method method, TuningState t) {
    t.method = method;
    viewer->setTuning(t);
    EXPECT_TRUE(viewer->step().ok());
    viewer->renderer().finish();
    return viewer->renderer().readbackColor();
  };
  const std::vector<std::uint8_t> sdf = frame(hsdf::RenderMethod::Cells, tuning);
  const std::vector<std::uint8_t> mesh = frame(Method::Mesh, tuning);
  ASSERT_EQ(sdf.size(), mesh.size());
  int red = 0, blue = 0, compared = 0, differ = 0;
  for (std::size_t i = 0; i < sdf.size(); i += 4) {
    const int s = redOrBlue(&sdf[i]), m = redOrBlue(&mesh[i]);
    red += s == 0;
    blue += s == 1;
    if (m < 0) continue;
    ++compared;
    differ += s != m;
  }
  std::printf("[ two materials ] SDF: %d red, %d blue px; %d of %d mesh px in another colour\n", red, blue, differ,
              compared);
  EXPECT_GT(red, 500);
  EXPECT_GT(blue, 500);
  // The seam: one row of cells (a cell is about 1.2 px here) along the split's outline.
  EXPECT_LT(differ, compared / 25);
  EXPECT_TRUE(viewer->close().ok());
}

TEST(Viewer, SwitchesBetweenMeshAndSdfAtRunTime) {
  auto viewer = makeViewer();
  ASSERT_NE(viewer, nullptr);
  SceneDesc scene;
  scene.gltf = hsdftest::sampleAsset("bunny.glb");
  scene.groundPlane = false;
  TuningState tuning;
  tuning.method = Method::Mesh;
  tuning.resolution = 16;
  // Loaded as SDF first: the meshes are hidden from the start (another renderer may draw the
  // registry before the first step, as the perf capture's measurement does).
  {
    auto sdfFirst = makeViewer();
    ASSERT_NE(sdfFirst, nullptr);
    TuningState cells = tuning;
    cells.method = hsdf::RenderMethod::Cells;
    ASSERT_TRUE(sdfFirst->loadScene(scene, cells).ok());
    EXPECT_EQ(meshCount(*sdfFirst), 0u);
    EXPECT_EQ(sdfCount(*sdfFirst), 1u);
    EXPECT_TRUE(sdfFirst->close().ok());
  }
  ASSERT_TRUE(viewer->loadScene(scene, tuning).ok());
  const std::size_t meshes = meshCount(*viewer);
  ASSERT_GT(meshes, 0u);
  EXPECT_EQ(viewer->sdfAsset(), nullptr);
  EXPECT_TRUE(viewer->hasMeshes());

  tuning.method = hsdf::RenderMethod::Cells;
  viewer->setTuning(tuning);
  ASSERT_NE(viewer->bakeJob(), nullptr) << "the first SDF method bakes the scene";
  ASSERT_TRUE(viewer->step().ok());
  ASSERT_TRUE(viewer->waitForBake().ok());
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_EQ(meshCount(*viewer), 0u);
  EXPECT_EQ(sdfCount(*viewer), 1u);
  ASSERT_NE(viewer->sdfAsset(), nullptr);
  const std::uint64_t id = viewer->sdfAsset()->id;
  EXPECT_GT(coverage(*viewer), 0.05);

  tuning.method = Method::Mesh;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_EQ(meshCount(*viewer), meshes);
  EXPECT_EQ(sdfCount(*viewer), 0u);
  EXPECT_GT(coverage(*viewer), 0.05);

  tuning.method = hsdf::RenderMethod::TrilinearSphereTrace;
  viewer->setTuning(tuning);
  EXPECT_EQ(viewer->bakeJob(), nullptr) << "the hidden SDF is still at this K";
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_EQ(theSdf(*viewer).asset->id, id);
  EXPECT_EQ(theSdf(*viewer).method, hsdf::RenderMethod::TrilinearSphereTrace);
  EXPECT_EQ(meshCount(*viewer), 0u);
  EXPECT_TRUE(viewer->close().ok());
}

// Tricky: a K past the budget must be refused by the worker before it allocates, with the reason
// kept for the panel, and the tuning must go back to the K on screen (else the panel would show a
// K that is not drawn, and the next unrelated change would re-bake it again).
TEST(Viewer, BakePastTheBudgetIsRefusedAndCancelKeepsTheOldK) {
  hsdf::BakeBudget budget;
  budget.maxBytes = 1u << 20;  // 1 MiB: K = 12 fits (28 KiB), K = 64 (4 MiB) does not
  auto viewer = makeViewer(budget);
  ASSERT_NE(viewer, nullptr);
  // The bunny, not an analytic shape: its bake (BVH distance queries) takes long enough that the
  // cancel below lands while it runs rather than racing a bake of a few microseconds.
  SceneDesc scene;
  scene.gltf = hsdftest::sampleAsset("bunny.glb");
  scene.groundPlane = false;
  TuningState tuning;
  tuning.resolution = 12;
  ASSERT_TRUE(viewer->loadScene(scene, tuning).ok());
  tuning.resolution = 64;
  viewer->setTuning(tuning);
  const engine::Status refused = viewer->waitForBake();
  ASSERT_FALSE(refused.ok());
  EXPECT_TRUE(viewer->bakeError().find("over the bake budget") != std::string::npos) << viewer->bakeError();
  EXPECT_EQ(viewer->tuning().resolution, 12);
  EXPECT_EQ(viewer->sdfAsset()->cells.grid.resolution, 12);

  tuning.resolution = 36;  // 0.8 MiB: within the budget
  viewer->setTuning(tuning);
  EXPECT_TRUE(viewer->bakeError().empty()) << "a new bake clears the old reason";
  viewer->cancelBake();
  const engine::Status cancelled = viewer->waitForBake();
  ASSERT_FALSE(cancelled.ok());
  EXPECT_TRUE(viewer->bakeError().find("cancelled") != std::string::npos) << viewer->bakeError();
  EXPECT_EQ(viewer->tuning().resolution, 12);
  EXPECT_EQ(viewer->sdfAsset()->cells.grid.resolution, 12);
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_GT(coverage(*viewer), 0.05);
  EXPECT_TRUE(viewer->close().ok());
}

// Tricky: the panel's and the script's cancel is followed by frames, not by waitForBake. The step
// after the cancel must finish the cancelled job (however far its worker got) and report it, and
// put the tuning back to the K drawn; a new K asked for right after must then bake. Before, a new
// K could replace the cancelled job before its worker noticed, with no word of the cancellation
// (the CI failure of scene_runner_panel_script_xvfb, stop 28).
TEST(Viewer, CancelIsReportedOnTheNextStepBeforeANewBake) {
  auto viewer = makeViewer();
  ASSERT_NE(viewer, nullptr);
  SceneDesc scene;
  scene.gltf = hsdftest::sampleAsset("bunny.glb");  // a bake long enough to be cancelled
  scene.groundPlane = false;
  TuningState tuning;
  tuning.resolution = 12;
  ASSERT_TRUE(viewer->loadScene(scene, tuning).ok());
  tuning.resolution = 64;
  viewer->setTuning(tuning);
  viewer->cancelBake();
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_TRUE(viewer->bakeError().find("cancelled") != std::string::npos) << viewer->bakeError();
  EXPECT_EQ(viewer->tuning().resolution, 12);
  EXPECT_EQ(viewer->sdfAsset()->cells.grid.resolution, 12);

  tuning.resolution = 16;
  viewer->setTuning(tuning);
  EXPECT_TRUE(viewer->bakeError().empty());
  ASSERT_TRUE(viewer->waitForBake().ok());
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_EQ(viewer->sdfAsset()->cells.grid.resolution, 16);
  EXPECT_TRUE(viewer->close().ok());
}

// Tricky: the level is chosen inside the one frame step, from that frame's camera: near (K's cells
// about 1 px on the 48-pixel image, target 1) draws K, 6 times farther draws a coarser level
// of the same source, and turning levels off draws K again; the levels are baked once per asset
// (the far frame reuses the near frame's levels: same level-0 asset, no re-bake), on worker
// threads that waitForBake waits for.
TEST(Viewer, LevelsOfDetailFollowTheCameraInTheFrameStep) {
  auto viewer = viewTorus(64);
  ASSERT_NE(viewer, nullptr);
  TuningState tuning = viewer->tuning();
  tuning.lod = true;
  tuning.lodPixelsPerCell = 1.0f;
  viewer->setTuning(tuning);
  viewer->setOrbitView(0);
  ASSERT_TRUE(viewer->step().ok());
  ASSERT_TRUE(viewer->waitForBake().ok());
  const auto finest = theSdf(*viewer).asset;
  EXPECT_EQ(finest->cells.grid.resolution, 64);
  const glm::vec3 target = 0.5f * (viewer->boundsMin() + viewer->boundsMax());
  const glm::vec3 eye = viewer->cameraView().position;
  viewer->setCamera(glm::dvec3(target + 6.0f * (eye - target)), glm::dvec3(target));
  ASSERT_TRUE(viewer->step().ok());
  const int far = theSdf(*viewer).asset->cells.grid.resolution;
  EXPECT_LT(far, 64);
  EXPECT_EQ(far % 16, 0) << "a level is K / 2^i";
  EXPECT_GT(coverage(*viewer), 0.0) << "the far torus is still drawn";
  tuning.lod = false;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_EQ(theSdf(*viewer).asset, finest) << "levels off: the asset baked at K again";
  // Levels on, a far frame, then levels off together with a new K: the new bake must stay drawn
  // (not level 0 of the old levels), and levels on again must build the new K's levels.
  tuning.lod = true;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->waitForBake().ok());
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_LT(theSdf(*viewer).asset->cells.grid.resolution, 64);
  tuning.lod = false;
  tuning.resolution = 48;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->waitForBake().ok());
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_EQ(theSdf(*viewer).asset->cells.grid.resolution, 48);
  tuning.lod = true;
  viewer->setTuning(tuning);
  viewer->setCamera(glm::dvec3(target + 1000.0f * (eye - target)), glm::dvec3(target));
  ASSERT_TRUE(viewer->waitForBake().ok());
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_EQ(theSdf(*viewer).asset->cells.grid.resolution, 48 / 2) << "the coarsest level of K = 48 (floor 16)";
  EXPECT_TRUE(viewer->close().ok());
}

// Tricky because the frame must not wait for the levels (seconds at K = 1024): the step that turns
// them on, far from the object, starts their bakes and still draws level 0 (a K = 32 bake takes
// far longer than the few microseconds between its start and the frame's look at it); the levels
// arrive in later steps without a call that waits, finer first, and the far object then draws a
// coarser one.
// Tricky because these values used to live only in the features' own panels: TuningState (the one
// settings struct of the command line, the panel and the scripts) must reach the features in the
// frame step, or the command line's and the scripts' values would be ignored.
TEST(Viewer, SearchLimitsOfTheTuningReachTheFeatures) {
  auto viewer = viewTorus(32);
  ASSERT_NE(viewer, nullptr);
  TuningState tuning = viewer->tuning();
  tuning.method = hsdf::RenderMethod::HermiteSphereTrace;
  tuning.traceEpsilon = 0.001953125f;
  tuning.traceMaxSteps = 1;
  tuning.centralDifferenceStep = 0.25f;
  tuning.maxRunLength = 5;
  tuning.tileSize = 4;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->waitForBake().ok());
  ASSERT_TRUE(viewer->step().ok());
  const auto& tracers = viewer->renderer().feature<hsdf::SphereTraceFeature>()->settings();
  EXPECT_EQ(tracers.epsilon, 0.001953125f);
  EXPECT_EQ(tracers.maxSteps, 1u);
  EXPECT_EQ(tracers.centralDifferenceStep, 0.25f);
  EXPECT_EQ(viewer->renderer().feature<hsdf::HermiteCellFeature>()->settings().maxRunLength, 5u);
  EXPECT_EQ(viewer->renderer().feature<hsdf::HermiteCellFeature>()->settings().tileSize, 4u);
  EXPECT_TRUE(viewer->close().ok());
}

// Why: a headless viewer's frames are captured (screenshots, scripts, perf captures): each must
// draw whole assets, so an upload budget asked for (by the command line, a settings file, a
// script) must not reach the cell feature there, while applyTuning itself must carry it (a
// windowed viewer's); and no pipeline warmer may compile beside the frames measured. Tricky: the
// viewer applies the tuning every step; the override must come after it, not once at start.
TEST(Viewer, AHeadlessViewerUploadsWithoutABudgetAndWarmsNoPipelines) {
  auto viewer = viewTorus(32);
  ASSERT_NE(viewer, nullptr);
  TuningState tuning = viewer->tuning();
  tuning.uploadMiBPerFrame = 5;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_EQ(viewer->renderer().feature<hsdf::HermiteCellFeature>()->settings().uploadBytesPerFrame, 0u);
  EXPECT_FALSE(viewer->renderer().feature<hsdf::HermiteCellFeature>()->settings().warmPipelines);
  EXPECT_FALSE(viewer->renderer().feature<hsdf::SphereTraceFeature>()->settings().warmPipelines);
  hsdf::HermiteCellFeature::Settings cells;
  hsdf::SphereTraceFeature::Settings tracers;
  applyTuning(tuning, cells, tracers);
  EXPECT_EQ(cells.uploadBytesPerFrame, std::uint64_t(5) << 20);
  EXPECT_TRUE(cells.warmPipelines) << "a windowed viewer's cells warm";
  EXPECT_TRUE(tracers.warmPipelines) << "a windowed viewer's tracers warm";
  EXPECT_TRUE(viewer->close().ok());
}

TEST(Viewer, LevelsOfDetailBakeOffTheFrameThread) {
  auto viewer = viewTorus(64);
  ASSERT_NE(viewer, nullptr);
  viewer->setOrbitView(0);
  const glm::vec3 target = 0.5f * (viewer->boundsMin() + viewer->boundsMax());
  const glm::vec3 eye = viewer->cameraView().position;
  viewer->setCamera(glm::dvec3(target + 1000.0f * (eye - target)), glm::dvec3(target));
  TuningState tuning = viewer->tuning();
  tuning.lod = true;
  tuning.lodPixelsPerCell = 1.0f;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_EQ(theSdf(*viewer).asset->cells.grid.resolution, 64) << "the step did not wait: level 0 until a level is ready";
  int drawn = 64;
  for (int frame = 0; frame < 2000 && drawn != 16; ++frame) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    ASSERT_TRUE(viewer->step().ok());
    const int now = theSdf(*viewer).asset->cells.grid.resolution;
    EXPECT_LE(now, drawn) << "finer levels arrive first";
    drawn = now;
  }
  EXPECT_EQ(drawn, 16) << "the coarsest level of K = 64 (floor 16) arrived without waitForBake";
  EXPECT_TRUE(viewer->close().ok());
}

// Tricky: the panel's controls reach the Viewer through TuningPanel::apply, which must refuse what
// the settings file and the command line refuse (a value typed past a slider's range: n = 200 was
// taken, saved into a settings file that then failed to load, and silently blocked every control
// of the comparison section) and what this scene cannot draw, keep the tuning as it was, and show
// why until a change is applied.
TEST(Viewer, ThePanelRefusesWhatTheSettingsWouldRefuse) {
  auto viewer = viewTorus(16);
  ASSERT_NE(viewer, nullptr);
  TuningPanel panel(*viewer);
  const TuningState before = viewer->tuning();
  TuningState typed = before;
  typed.subdivisions = 200;
  EXPECT_FALSE(panel.apply(typed));
  EXPECT_NE(panel.refusal().find("subdivisions"), std::string::npos) << panel.refusal();
  EXPECT_EQ(viewer->tuning().subdivisions, before.subdivisions);
  TuningState black = before;
  black.centralDifferenceStep = 0.0f;
  EXPECT_FALSE(panel.apply(black)) << "a step of 0 drew the object black";
  TuningState mesh = before;
  mesh.method = Method::Mesh;
  EXPECT_FALSE(panel.apply(mesh)) << "an analytic torus has no triangles";
  EXPECT_EQ(viewer->tuning().method, before.method);
  TuningState fine = before;
  fine.subdivisions = 5;
  EXPECT_TRUE(panel.apply(fine));
  EXPECT_TRUE(panel.refusal().empty());
  EXPECT_EQ(viewer->tuning().subdivisions, 5u);
  EXPECT_TRUE(viewer->close().ok());
}

// Tricky: ImGui clips what a window's content puts past its right edge and shows no scroll bar for
// it, so a control laid out there is drawn cut or not at all, and nothing fails: in the panel as
// scene_runner opens it (420 pixels wide) a row of toggles ran on past "certified", out of reach,
// and the longer labels of the sliders were cut. Every control the open sections draw must end
// inside the panel's work area (the window less its padding).
TEST(Viewer, EveryControlOfThePanelLiesInsideIt) {
  ViewerDesc desc;
  desc.width = 1280;
  desc.height = 720;
  desc.headless = true;
  desc.headlessUi = true;
  desc.validation = true;
  const auto device = hsdftest::testDevicePreference();
  ASSERT_TRUE(device.ok()) << device.error().message;
  desc.device = *device;
  auto viewer = Viewer::create(desc);
  ASSERT_TRUE(viewer.ok()) << viewer.error().message;
  SceneDesc scene;
  scene.shape = "torus";
  scene.groundPlane = false;
  TuningState tuning;
  tuning.resolution = 16;
  tuning.split = SplitMode::Vertical;  // the comparison's controls too
  ASSERT_TRUE((*viewer)->loadScene(scene, tuning).ok());
  ASSERT_TRUE((*viewer)->waitForBake().ok());
  ASSERT_TRUE((*viewer)->step().ok());
  ImGuiWindow* panel = ImGui::FindWindowByName(kProgramName);
  ASSERT_NE(panel, nullptr);
  // The sections that start closed are opened as a click would: their header's state, under the
  // ID of the panel that draws it (UiLayer pushes each panel's name).
  std::vector<std::string> panels{"tuning"};
  for (const auto& feature : (*viewer)->renderer().features()) panels.emplace_back(feature->name());
  for (const std::string& name : panels)
    for (const char* header : {"Screenshot and settings", "Meshes", "Sphere tracing"})
      panel->StateStorage.SetInt(ImHashStr(header, 0, ImHashStr(name.c_str(), 0, panel->ID)), 1);
  ASSERT_TRUE((*viewer)->step().ok());
  EXPECT_LE(panel->DC.CursorMaxPos.x, panel->WorkRect.Max.x + 0.5f)
      << "the panel's controls reach " << panel->DC.CursorMaxPos.x - panel->Pos.x << " px into a panel of "
      << panel->Size.x << " px (work area to " << panel->WorkRect.Max.x - panel->Pos.x << ")";
  EXPECT_TRUE((*viewer)->close().ok());
}

// Tricky: the cancel button stands beside the bake it names. With no re-bake running it cancels
// the level of detail being baked, and that is not a failure: levels of detail stay on with the
// levels baked so far, no error is shown and no level bake starts again by itself (before, the
// cancelled level turned levels of detail off with the error "cancelled"). Off and on again bakes
// every level.
TEST(Viewer, CancellingALevelOfDetailKeepsLevelsOfDetailOn) {
  auto viewer = makeViewer();
  ASSERT_NE(viewer, nullptr);
  SceneDesc scene;
  scene.gltf = hsdftest::sampleAsset("bunny.glb");  // level K = 64 of a mesh: ~0.4 s, a bake the cancel catches
  scene.groundPlane = false;
  TuningState loaded;
  loaded.resolution = 128;
  ASSERT_TRUE(viewer->loadScene(scene, loaded).ok());
  ASSERT_TRUE(viewer->step().ok());  // the pipelines built: the step that starts the levels is short
  const glm::vec3 target = 0.5f * (viewer->boundsMin() + viewer->boundsMax());
  viewer->setOrbitView(0);
  const glm::vec3 eye = viewer->cameraView().position;
  viewer->setCamera(glm::dvec3(target + 1000.0f * (eye - target)), glm::dvec3(target));
  TuningState tuning = viewer->tuning();
  tuning.lod = true;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->step().ok());
  ASSERT_NE(viewer->levelBakeJob(), nullptr) << "the step started the levels' bakes";
  viewer->cancelBake();
  for (int frame = 0; frame < 3; ++frame) ASSERT_TRUE(viewer->step().ok());
  EXPECT_TRUE(viewer->tuning().lod) << "a cancelled level keeps levels of detail on";
  EXPECT_TRUE(viewer->bakeError().empty()) << viewer->bakeError();
  EXPECT_EQ(viewer->levelBakeJob(), nullptr) << "no level bakes again by itself after a cancel";
  tuning.lod = false;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->step().ok());
  tuning.lod = true;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->waitForBake().ok());
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_EQ(theSdf(*viewer).asset->cells.grid.resolution, 16) << "off and on again: every level, the coarsest drawn";
  EXPECT_TRUE(viewer->close().ok());
}

// Tricky: past K = 256 the cells bake sparse (no dense field); switching to a dense tracer at a K
// it allows must re-bake with the field, not hand the tracer an asset without one.
TEST(Viewer, SparseCellBakeRebakesDenseForTheTracers) {
  auto viewer = viewTorus(16);
  ASSERT_NE(viewer, nullptr);
  TuningState tuning = viewer->tuning();
  tuning.resolution = 260;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->waitForBake().ok());
  EXPECT_EQ(theSdf(*viewer).asset->cells.grid.resolution, 260);
  EXPECT_TRUE(theSdf(*viewer).asset->field.samples.empty()) << "the cells past 256 bake sparse";
  // The log and the panel say the tracers' storage is what they would store, not what is held.
  const SdfStats sparse = sdfStats(*theSdf(*viewer).asset);
  EXPECT_FALSE(sparse.denseField);
  EXPECT_NE(describeSdfStats(sparse).find("no dense field"), std::string::npos) << describeSdfStats(sparse);
  ASSERT_TRUE(viewer->step().ok());
  tuning.method = hsdf::RenderMethod::TrilinearSphereTrace;
  viewer->setTuning(tuning);
  ASSERT_NE(viewer->bakeJob(), nullptr) << "a tracer needs the dense field";
  // Until it lands, the frames draw the cells (drawableMethod); before, the frame failed.
  ASSERT_TRUE(viewer->step().ok()) << "a frame while the dense re-bake runs";
  EXPECT_EQ(theSdf(*viewer).method, hsdf::RenderMethod::Cells);
  ASSERT_TRUE(viewer->waitForBake().ok());
  EXPECT_EQ(theSdf(*viewer).asset->field.grid.resolution, 260);
  EXPECT_FALSE(theSdf(*viewer).asset->field.samples.empty());
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_GT(coverage(*viewer), 0.05);
  EXPECT_TRUE(viewer->close().ok());
}

// tests/data/gltf/tilted_cube.gltf under a root node translated by `offset`, in a file of its own.
std::filesystem::path tiltedCubeAt(const glm::vec3& offset, const std::string& name) {
  std::ifstream in(hsdftest::testData("gltf/tilted_cube.gltf"));
  nlohmann::json doc = nlohmann::json::parse(in);
  doc["nodes"].push_back({{"name", "placed"}, {"translation", {offset.x, offset.y, offset.z}}, {"children", {0}}});
  doc["scenes"][0]["nodes"] = {doc["nodes"].size() - 1};
  const std::filesystem::path path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << doc.dump();
  return path;
}

// Why: a glTF scene 2^17 units from the world origin, baked whole (not --objects): float holds
// 1/64 there, and the grid, baked in world coordinates, put 1.3e5 into the cells' own float
// arithmetic (a unit cube 1e6 units away drew scattered specks). The scene is baked about its
// centre (Viewer::bakeOrigin, flattened in double) and its SDF entity placed there, so it draws
// the image of the same scene at the origin, seen from the same place relative to it.
TEST(Viewer, ASceneFarFromTheOriginIsBakedAboutItsCentre) {
  const glm::vec3 far(131072.0f, -65536.0f, 131072.0f);
  std::vector<float> depth[2];
  std::vector<std::uint8_t> rgba[2];
  glm::dvec3 eye(0.0), target(0.0);
  for (int i = 0; i < 2; ++i) {
    const glm::vec3 offset = i == 0 ? glm::vec3(0.0f) : far;
    auto viewer = makeTestViewer(96, 64);
    ASSERT_NE(viewer, nullptr);
    SceneDesc scene;
    scene.gltf = tiltedCubeAt(offset, "tilted_cube_at_" + std::to_string(i) + ".gltf");
    scene.groundPlane = false;
    TuningState tuning;
    tuning.method = hsdf::RenderMethod::Cells;
    tuning.resolution = 24;
    const engine::Status loaded = viewer->loadScene(scene, tuning);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    const hsdf::Aabb grid = theSdf(*viewer).asset->cells.grid.bounds();
    const double size = glm::length(grid.size());
    if (i == 0) {
      // An orbit view's eye and the scene's centre on a 1/64 grid: moved by `far` they stay exact.
      viewer->setOrbitView(2);
      const auto snap = [](const glm::dvec3& p) { return glm::round(p * 64.0) / 64.0; };
      eye = snap(glm::dvec3(viewer->cameraView().position));
      target = snap(grid.center());
    } else {
      EXPECT_LT(glm::length(grid.center()), size) << "the far scene was not baked about its centre";
    }
    viewer->setCamera(eye + glm::dvec3(offset), target + glm::dvec3(offset));
    ASSERT_TRUE(viewer->step().ok());
    viewer->renderer().finish();
    depth[i] = viewer->renderer().readbackDepth();
    rgba[i] = viewer->renderer().readbackColor();
    EXPECT_TRUE(viewer->close().ok());
  }
  int hits = 0, coverage = 0, colour = 0;
  for (std::size_t p = 0; p < depth[0].size(); ++p) {
    hits += depth[0][p] > 0.0f;
    coverage += (depth[0][p] > 0.0f) != (depth[1][p] > 0.0f);
    for (std::size_t c = 0; c < 3; ++c) colour += std::abs(int(rgba[0][4 * p + c]) - int(rgba[1][4 * p + c])) > 24;
  }
  ASSERT_GT(hits, 500);
  EXPECT_LE(coverage, 2) << "of " << hits << " covered pixels";
  EXPECT_LE(colour, 6) << "of " << hits << " covered pixels";
}

// Tricky: the panel, a script and a settings file loaded while running write the same TuningState
// the command line checks up front, but after the scene is known. A .hsdf file has no triangles and
// no source to bake (before: a script's method=mesh drew only the ground, a new K was ignored and
// the saved settings named the default K, not the file's); an analytic shape has no triangles but
// bakes again at any K.
TEST(Viewer, TuningTheSceneCannotDrawIsRefused) {
  auto shape = viewTorus(20);
  ASSERT_NE(shape, nullptr);
  TuningState t = shape->tuning();
  EXPECT_TRUE(shape->checkTuning(t).ok());
  t.resolution = 24;
  t.lod = true;
  t.split = SplitMode::Vertical;
  EXPECT_TRUE(shape->checkTuning(t).ok()) << "a shape bakes again and compares";
  t = shape->tuning();
  t.method = Method::Mesh;
  const engine::Status mesh = shape->checkTuning(t);
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.error().message.find("method mesh: this scene has no triangles"), std::string::npos);

  const hsdf::SdfAsset& asset = *theSdf(*shape).asset;
  hsdf::HsdfContentsView contents;
  contents.grid = asset.field.grid;
  contents.dense = &asset.field;
  contents.cells = &asset.cells;
  const auto bytes = hsdf::serializeHsdf(contents);
  ASSERT_TRUE(bytes.ok()) << bytes.error().message;
  const hsdftest::ScopedTempPath temp("viewer_tuning_refused.hsdf");
  const std::filesystem::path& file = temp.path();
  std::ofstream(file, std::ios::binary).write(reinterpret_cast<const char*>(bytes->data()), std::streamsize(bytes->size()));
  EXPECT_TRUE(shape->close().ok());

  auto viewer = makeViewer();
  ASSERT_NE(viewer, nullptr);
  SceneDesc scene;
  scene.sdfFile = file;
  TuningState tuning;
  tuning.method = hsdf::RenderMethod::Cells;
  ASSERT_EQ(tuning.resolution, 64) << "the default must differ from the file's K for this test";
  ASSERT_TRUE(viewer->loadScene(scene, tuning).ok());
  EXPECT_EQ(viewer->tuning().resolution, 20) << "the K the file was baked with";
  t = viewer->tuning();
  t.method = hsdf::RenderMethod::HermiteSphereTrace;
  t.subdivisions = 5;
  EXPECT_TRUE(viewer->checkTuning(t).ok()) << "what the file can draw";
  for (const auto& [change, expected] :
       std::vector<std::pair<void (*)(TuningState&), std::string>>{
           {[](TuningState& s) { s.method = Method::Mesh; }, "this scene has no triangles"},
           {[](TuningState& s) { s.resolution = 24; }, "drawn as it was baked (K = 20)"},
           {[](TuningState& s) { s.padding += 1; }, "drawn as it was baked (K = 20)"},
           {[](TuningState& s) { s.shellThickness = 0.1f; }, "shell 0.1: a .hsdf file is drawn as it was baked"},
           {[](TuningState& s) { s.lod = true; }, "a .hsdf file has no source"}}) {
    t = viewer->tuning();
    change(t);
    const engine::Status refused = viewer->checkTuning(t);
    ASSERT_FALSE(refused.ok()) << expected;
    EXPECT_NE(refused.error().message.find(expected), std::string::npos) << refused.error().message;
  }
  EXPECT_FALSE(viewer->canRebake());
  EXPECT_TRUE(viewer->close().ok());
}

}  // namespace
}  // namespace samples
