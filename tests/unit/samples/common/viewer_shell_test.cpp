// The Viewer's shell thickness (TuningState::shellThickness, hsdf::BakeSettings::shellThickness),
// headless on the test device with validation on: a sheet that bounds no volume is baked as a shell
// by every bake the Viewer makes (the re-bake, its levels of detail, the compared side, a scene's
// separate objects), and a change of thickness re-bakes as a change of K does.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "hermite_sdf/render/lod.h"
#include "log_capture.h"
#include "test_viewer.h"

namespace samples {
namespace {

// The unit square in z = 0 (one node, two triangles): an open sheet.
const std::filesystem::path kSheet = hsdftest::testData("gltf/flat_square.gltf");

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

const hsdf::HermiteSdfRenderable* theSdf(Viewer& viewer) {
  const hsdf::HermiteSdfRenderable* found = nullptr;
  viewer.registry().view<hsdf::HermiteSdfRenderable>().each(
      [&found](engine::ecs::Entity, const hsdf::HermiteSdfRenderable& r) { found = &r; });
  return found;
}

// Pixels that differ from the top-left one (the background: no ground plane).
std::size_t coveredPixels(Viewer& viewer) {
  EXPECT_TRUE(viewer.step().ok());
  viewer.renderer().finish();
  const std::vector<std::uint8_t> rgba = viewer.renderer().readbackColor();
  std::size_t count = 0;
  for (std::size_t i = 0; i < rgba.size(); i += 4)
    if (rgba[i] != rgba[0] || rgba[i + 1] != rgba[1] || rgba[i + 2] != rgba[2]) ++count;
  return count;
}

// The sheet loaded as triangles (Method::Mesh), seen from above its centre.
std::unique_ptr<Viewer> viewSheet(TuningState tuning, bool objects = false) {
  auto viewer = withGltfScene(makeTestViewer(96, 96), kSheet, tuning, objects);
  if (!viewer) return nullptr;
  viewer->setCamera({0.5, 0.5, 3.0}, {0.5, 0.5, 0.0});
  return viewer;
}

// Every kept cell of `asset` lies at the faces of the shell `thickness` thick around the square,
// and some on each side of it: the field is the shell's, not a solid's or a thinner shell's.
void expectCellsAtTheShell(const hsdf::SdfAsset& asset, double thickness) {
  const hsdf::CellStream& cells = asset.cells;
  const double h = cells.grid.spacing;
  int above = 0, below = 0;
  for (const hsdf::CellRecord& r : cells.records) {
    const glm::dvec3 centre = glm::dvec3(cells.grid.origin) + (glm::dvec3(r.x, r.y, r.z) + 0.5) * h;
    const glm::dvec2 past = glm::max(glm::abs(glm::dvec2(centre.x, centre.y) - 0.5) - 0.5, 0.0);
    const double toShell = std::sqrt(glm::dot(past, past) + centre.z * centre.z) - 0.5 * thickness;
    EXPECT_LE(std::abs(toShell), std::sqrt(3.0) * h) << "K " << cells.grid.resolution << ": " << r.x << " " << r.y << " " << r.z;
    above += centre.z > 0.0;
    below += centre.z < 0.0;
  }
  EXPECT_GT(above, 0);
  EXPECT_GT(below, 0);
  // The bounds grow by half the thickness off the triangles (z = 0).
  EXPECT_NEAR(asset.surfaceBounds.max.z, 0.5 * thickness, 1e-6);
}

// Tricky: the thickness is a bake setting the tuning carries, not part of the scene's source, so
// every bake must take it from the tuning: the first SDF bake of a scene loaded as meshes (refused
// without a shell, naming why), the re-bake when it changes (K unchanged: the old comparison of K
// and padding alone saw nothing to do), and each level of detail (a level baked as a solid is
// refused as the sheet is, which turned levels of detail off). The frame is checked against the
// triangles: seen from above, the shell covers the square and a rim half its thickness wide.
TEST(ViewerShell, ASheetBakesAsAShellOfTheTuningsThicknessAndReBakesWhenItChanges) {
  TuningState tuning;
  tuning.method = Method::Mesh;
  tuning.resolution = 32;
  auto viewer = viewSheet(tuning);
  ASSERT_NE(viewer, nullptr);
  const std::size_t square = coveredPixels(*viewer);
  ASSERT_GT(square, 1000u) << "the square seen from above";

  tuning.method = hsdf::RenderMethod::Cells;
  viewer->setTuning(tuning);
  EXPECT_FALSE(viewer->waitForBake().ok());
  EXPECT_TRUE(contains(viewer->bakeError(), "bounds no volume")) << viewer->bakeError();
  EXPECT_EQ(viewer->tuning().method, Method::Mesh) << "the failed first bake leaves the meshes drawn";

  for (const float thickness : {0.2f, 0.4f}) {
    tuning.shellThickness = thickness;
    viewer->setTuning(tuning);
    ASSERT_TRUE(viewer->waitForBake().ok()) << viewer->bakeError();
    const hsdf::HermiteSdfRenderable* sdf = theSdf(*viewer);
    ASSERT_NE(sdf, nullptr);
    expectCellsAtTheShell(*sdf->asset, double(thickness));
    // The square grown by the rim on each side; perspective makes the rim a little larger than
    // (1 + t)^2 of the square's pixels, the near face a little larger still.
    const double ratio = double(coveredPixels(*viewer)) / double(square);
    const double grown = (1.0 + double(thickness)) * (1.0 + double(thickness));
    EXPECT_GT(ratio, grown * 0.97) << "shell " << thickness;
    EXPECT_LT(ratio, grown * 1.15) << "shell " << thickness;
  }

  tuning.lod = true;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->waitForBake().ok()) << viewer->bakeError();
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_TRUE(viewer->tuning().lod) << viewer->bakeError();
  const hsdf::HermiteSdfLod* lod = nullptr;
  viewer->registry().view<hsdf::HermiteSdfLod>().each(
      [&lod](engine::ecs::Entity, const hsdf::HermiteSdfLod& levels) { lod = &levels; });
  ASSERT_NE(lod, nullptr) << "the entity has levels of detail";
  ASSERT_EQ(lod->levels.size(), 2u) << "K = 32 and 16";
  for (const auto& level : lod->levels) expectCellsAtTheShell(*level, 0.4);
  EXPECT_TRUE(viewer->close().ok());
}

// Tricky: the compared side bakes on its own (a tracer needs the dense field at its own K), from
// the same source: without the tuning's shell it bakes the sheet as a solid, which is refused, and
// the split screen then shows the main side twice with an error.
TEST(ViewerShell, TheComparedSideBakesTheSameShell) {
  TuningState tuning;
  tuning.method = hsdf::RenderMethod::Cells;
  tuning.resolution = 24;
  tuning.shellThickness = 0.25f;
  tuning.split = SplitMode::Vertical;
  tuning.compareMethod = hsdf::RenderMethod::TrilinearSphereTrace;
  tuning.compareResolution = 40;
  auto viewer = viewSheet(tuning);
  ASSERT_NE(viewer, nullptr);
  ASSERT_TRUE(viewer->waitForBake().ok()) << viewer->bakeError() << viewer->compareBakeError();
  EXPECT_TRUE(viewer->compareBakeError().empty()) << viewer->compareBakeError();
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_EQ(viewer->compareResolutionDrawn(), 40);
  // A new thickness bakes both sides again.
  tuning.shellThickness = 0.5f;
  viewer->setTuning(tuning);
  ASSERT_NE(viewer->compareBakeJob(), nullptr) << "the compared side follows the thickness";
  EXPECT_EQ(viewer->compareBakeJob()->settings().shellThickness, 0.5);
  ASSERT_TRUE(viewer->waitForBake().ok()) << viewer->bakeError() << viewer->compareBakeError();
  EXPECT_TRUE(viewer->compareBakeError().empty()) << viewer->compareBakeError();
  EXPECT_TRUE(viewer->close().ok());
}

// Tricky: a scene of separate objects bakes each mesh itself (bakeSceneObjects); a sheet with no
// shell falls back to its triangles (named in the log), with one it is an SDF object, and a new
// thickness bakes the objects again.
TEST(ViewerShell, ASceneOfObjectsBakesItsSheetsAsShells) {
  TuningState tuning;
  tuning.method = hsdf::RenderMethod::Cells;
  tuning.resolution = 24;
  auto solid = viewSheet(tuning, /*objects=*/true);
  ASSERT_NE(solid, nullptr);
  EXPECT_TRUE(solid->sdfObjects().empty()) << "a sheet bounds no volume: it draws its triangles";
  EXPECT_TRUE(solid->close().ok());

  tuning.shellThickness = 0.2f;
  auto viewer = viewSheet(tuning, /*objects=*/true);
  ASSERT_NE(viewer, nullptr);
  ASSERT_EQ(viewer->sdfObjects().size(), 1u);
  expectCellsAtTheShell(*theSdf(*viewer)->asset, 0.2);
  tuning.shellThickness = 0.3f;
  viewer->setTuning(tuning);
  EXPECT_TRUE(viewer->bakeError().empty()) << viewer->bakeError();
  expectCellsAtTheShell(*theSdf(*viewer)->asset, 0.3);
  EXPECT_TRUE(viewer->close().ok());
}

// Tricky: a shell thinner than a cell bakes rough or with holes; hsdf_bake warned, the runner (its
// command line, the panel, --objects) baked it without a word. Each bake says it once, naming the
// mesh, and a thick shell says nothing.
TEST(ViewerShell, AShellThinnerThanACellIsWarnedAboutByEveryBake) {
  TuningState tuning;
  tuning.method = Method::Mesh;
  tuning.resolution = 16;  // a cell of about 0.08 over the unit square
  auto viewer = viewSheet(tuning);
  ASSERT_NE(viewer, nullptr);
  hsdftest::LogCapture warnings;
  tuning.method = hsdf::RenderMethod::Cells;
  tuning.shellThickness = 0.2f;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->waitForBake().ok()) << viewer->bakeError();
  EXPECT_EQ(warnings.count("thinner than a grid cell"), 0u);
  tuning.shellThickness = 0.02f;
  viewer->setTuning(tuning);
  ASSERT_TRUE(viewer->waitForBake().ok()) << viewer->bakeError();
  EXPECT_EQ(warnings.count("scene sdf: a shell 0.02 thick is thinner than a grid cell"), 1u);
  EXPECT_TRUE(viewer->close().ok());

  tuning.shellThickness = 0.02f;
  auto objects = viewSheet(tuning, /*objects=*/true);
  ASSERT_NE(objects, nullptr);
  EXPECT_EQ(warnings.count("mesh 0: a shell 0.02 thick is thinner than a grid cell"), 1u);
  EXPECT_TRUE(objects->close().ok());
}

}  // namespace
}  // namespace samples
