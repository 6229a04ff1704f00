// The Viewer's split-screen comparison, difference view and shader reload (samples/common/viewer.h,
// difference_view.h), headless on the test device (HSDF_TEST_DEVICE, lavapipe unless set) with the
// validation layers on, at 128x96: real pixels read back from the frame, compared with frames
// drawn by one method alone.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/gpu/pipeline.h"
#include "engine/render/mesh_feature.h"
#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/render/sphere_trace_feature.h"
#include "test_viewer.h"

namespace samples {
namespace {

constexpr std::uint32_t kWidth = 128, kHeight = 96;

std::unique_ptr<Viewer> viewTorus(const TuningState& tuning) {
  auto viewer = createTestViewer(kWidth, kHeight);
  EXPECT_TRUE(viewer.ok()) << viewer.error().message;
  if (!viewer.ok()) return nullptr;
  SceneDesc scene;
  scene.shape = "torus";
  scene.groundPlane = false;
  const engine::Status loaded = (*viewer)->loadScene(scene, tuning);
  EXPECT_TRUE(loaded.ok()) << loaded.error().message;
  return loaded.ok() ? std::move(*viewer) : nullptr;
}

// One frame with `tuning` (re-bakes finished first), read back as RGBA8.
std::vector<std::uint8_t> frameWith(Viewer& viewer, const TuningState& tuning) {
  viewer.setTuning(tuning);
  EXPECT_TRUE(viewer.waitForBake().ok());
  EXPECT_TRUE(viewer.step().ok());
  return viewer.renderer().readbackColor();
}

struct Rect {
  std::uint32_t x0, y0, x1, y1;
};

// Pixels of `rect` whose colour differs between a and b by more than `tolerance` in a channel.
std::size_t differingPixels(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, Rect rect,
                            int tolerance = 0) {
  std::size_t count = 0;
  for (std::uint32_t y = rect.y0; y < rect.y1; ++y)
    for (std::uint32_t x = rect.x0; x < rect.x1; ++x)
      for (std::size_t c = 0; c < 3; ++c) {
        const std::size_t i = (std::size_t(y) * kWidth + x) * 4 + c;
        if (std::abs(int(a[i]) - int(b[i])) > tolerance) {
          ++count;
          break;
        }
      }
  return count;
}

TuningState cellsK16() {
  TuningState tuning;
  tuning.method = hsdf::RenderMethod::Cells;
  tuning.resolution = 16;
  return tuning;
}

// Tricky: each side of the split must be exactly the frame its method draws alone, with one
// camera: the regions share the projection (full viewport, scissored), and the compared side is a
// separate bake (2K = 32, central normals) swapped into the same entity only for its region. A
// renderer that let a region's per-frame data overwrite the other's (one frame slot for both), or
// shifted the projection to the rectangle, would break one half. The methods differ enough in each
// half that the comparison can fail.
TEST(ViewerCompare, SplitShowsEachMethodInItsRegion) {
  const TuningState main = cellsK16();
  auto viewer = viewTorus(main);
  ASSERT_NE(viewer, nullptr);
  TuningState trilinear = main;
  trilinear.method = hsdf::RenderMethod::TrilinearSphereTrace;
  trilinear.resolution = 32;  // 2K, the compared side's default
  trilinear.normals = hsdf::NormalMode::CentralDifferences;
  const std::vector<std::uint8_t> onlyTrilinear = frameWith(*viewer, trilinear);
  const std::vector<std::uint8_t> onlyCells = frameWith(*viewer, main);

  for (const SplitMode mode : {SplitMode::Vertical, SplitMode::Horizontal}) {
    SCOPED_TRACE(splitModeName(mode));
    TuningState split = main;
    split.split = mode;
    split.splitPosition = 0.4f;  // not the middle: the divider position reaches the rectangles
    const std::vector<std::uint8_t> both = frameWith(*viewer, split);
    EXPECT_EQ(viewer->compareResolutionDrawn(), 32);
    const bool vertical = mode == SplitMode::Vertical;
    const std::uint32_t at = vertical ? 51 : 38;  // round(0.4 * 128), round(0.4 * 96)
    const Rect first = vertical ? Rect{0, 0, at, kHeight} : Rect{0, 0, kWidth, at};
    const Rect second = vertical ? Rect{at, 0, kWidth, kHeight} : Rect{0, at, kWidth, kHeight};
    EXPECT_GT(differingPixels(onlyCells, onlyTrilinear, first), 20u) << "the methods must differ for the test to mean anything";
    EXPECT_GT(differingPixels(onlyCells, onlyTrilinear, second), 20u);
    EXPECT_EQ(differingPixels(both, onlyCells, first), 0u) << "the first region is the cells frame";
    EXPECT_EQ(differingPixels(both, onlyTrilinear, second), 0u) << "the second region is the trilinear frame";
  }
  // After a split frame the entity holds the main asset and method again.
  const std::vector<std::uint8_t> after = frameWith(*viewer, main);
  EXPECT_EQ(differingPixels(after, onlyCells, {0, 0, kWidth, kHeight}), 0u);
  const engine::Status closed = viewer->close();
  EXPECT_TRUE(closed.ok()) << closed.error().message;
}

// Tricky: with levels of detail the main side draws the level its view picks, and a compared side
// of cells at K must draw K (the field baked at K), not the level again: both sides drew the level
// while the labels said K (found by a helper). Each half is the frame of its field drawn alone.
TEST(ViewerCompare, SplitWithLevelsOfDetailComparesTheLevelWithK) {
  TuningState main = cellsK16();
  main.resolution = 32;
  auto viewer = viewTorus(main);
  ASSERT_NE(viewer, nullptr);
  const std::vector<std::uint8_t> onlyK = frameWith(*viewer, main);
  TuningState lod = main;
  lod.lod = true;
  lod.lodPixelsPerCell = 16.0f;  // cells this large on screen: a coarser level than K = 32
  (void)frameWith(*viewer, lod);
  const int level = viewer->resolutionDrawn();
  ASSERT_LT(level, 32) << "the view must pick a coarser level for the test to mean anything";
  TuningState atLevel = main;
  atLevel.resolution = level;
  const std::vector<std::uint8_t> onlyLevel = frameWith(*viewer, atLevel);

  TuningState split = lod;
  split.split = SplitMode::Vertical;
  split.compareMethod = hsdf::RenderMethod::Cells;
  split.compareNormals = hsdf::NormalMode::Exact;  // as the main side's (the compared default is central)
  const std::vector<std::uint8_t> both = frameWith(*viewer, split);
  EXPECT_EQ(viewer->resolutionDrawn(), level);
  EXPECT_EQ(viewer->compareResolutionDrawn(), 32);
  const Rect first{0, 0, kWidth / 2, kHeight}, second{kWidth / 2, 0, kWidth, kHeight};
  EXPECT_GT(differingPixels(onlyK, onlyLevel, second), 20u) << "K and the level must differ for the test to mean anything";
  EXPECT_EQ(differingPixels(both, onlyLevel, first), 0u) << "the main side is the level";
  EXPECT_EQ(differingPixels(both, onlyK, second), 0u) << "the compared side of cells is K";
  const engine::Status closed = viewer->close();
  EXPECT_TRUE(closed.ok()) << closed.error().message;
}

// Tricky: the difference view compares two frames drawn and read back within one step; the same
// method on both sides must give exactly 0 degrees and no coverage difference (so any asset or
// state leaking between the two frames shows up), and the heat map must be what reaches the
// frame (the overlay copies it before the UI).
TEST(ViewerCompare, DifferenceOfIdenticalMethodsIsZero) {
  TuningState tuning = cellsK16();
  tuning.method = hsdf::RenderMethod::TrilinearSphereTrace;
  tuning.normals = hsdf::NormalMode::Exact;
  tuning.compareMethod = hsdf::RenderMethod::TrilinearSphereTrace;
  tuning.compareResolution = 16;
  tuning.compareNormals = hsdf::NormalMode::Exact;
  tuning.difference = true;
  auto viewer = viewTorus(tuning);
  ASSERT_NE(viewer, nullptr);
  ASSERT_TRUE(viewer->waitForBake().ok());
  ASSERT_TRUE(viewer->step().ok());
  ASSERT_TRUE(viewer->difference().has_value());
  const NormalDifference& d = *viewer->difference();
  EXPECT_GT(d.coveredBoth, 500u) << "the torus covers a good part of the image";
  EXPECT_EQ(d.coverageDiffers, 0u);
  EXPECT_EQ(d.maxDegrees, 0.0);
  EXPECT_EQ(viewer->renderer().readbackColor(), heatMapImage(d, viewer->differenceRange()));
  EXPECT_TRUE(viewer->close().ok());
}

// Tricky: trilinear sphere tracing at K = 16 and the Hermite cells at K = 16 see different
// surfaces (the paper's point): the angles must be large on average, some pixels covered by one
// only, while turning the difference view off gives the shaded frame back.
TEST(ViewerCompare, DifferenceOfTrilinearAndCellsIsLarge) {
  TuningState tuning = cellsK16();
  tuning.compareResolution = 16;
  tuning.difference = true;
  auto viewer = viewTorus(tuning);
  ASSERT_NE(viewer, nullptr);
  ASSERT_TRUE(viewer->waitForBake().ok());
  ASSERT_TRUE(viewer->step().ok());
  ASSERT_TRUE(viewer->difference().has_value());
  const NormalDifference d = *viewer->difference();
  EXPECT_GT(d.coveredBoth, 500u);
  EXPECT_GT(d.meanDegrees, 1.0) << "trilinear K 16 normals are visibly off";
  EXPECT_GT(d.maxDegrees, 10.0);
  EXPECT_GT(d.coverageDiffers, 0u) << "the silhouettes differ";
  EXPECT_LT(d.coverageDiffersShare(), 0.2) << "but the same object is drawn";
  const std::vector<std::uint8_t> heat = viewer->renderer().readbackColor();
  tuning.difference = false;
  const std::vector<std::uint8_t> shaded = frameWith(*viewer, tuning);
  EXPECT_FALSE(viewer->difference().has_value());
  EXPECT_GT(differingPixels(heat, shaded, {0, 0, kWidth, kHeight}), 500u);
  EXPECT_TRUE(viewer->close().ok());
}

// A copy of the shader folder at `to` in which `replace` maps file names to the file copied in
// their place ("" : a file of garbage).
std::filesystem::path shaderCopy(const std::filesystem::path& to, const std::vector<std::pair<std::string, std::string>>& replace) {
  const std::filesystem::path from = engine::gpu::shaderDirectory();
  std::filesystem::copy(from, to);
  for (const auto& [file, source] : replace) {
    if (!std::filesystem::exists(to / file)) continue;  // e.g. the bindless variant
    std::filesystem::remove(to / file);
    if (source.empty()) {
      std::FILE* out = std::fopen((to / file).c_str(), "wb");
      std::fputs("this is not SPIR-V: 48 bytes of a broken build..", out);  // a multiple of 4: the header check
      std::fclose(out);
    } else {
      std::filesystem::copy_file(to / source, to / file);
    }
  }
  return to;
}

// Tricky: the renderer prepares each view region in turn, and each feature starts its stats afresh
// in prepare(), so a split frame's stats() are its right side's: the cells' panel of the default
// split (cells | trilinear) said "objects 0, draws 0" beside the cells it drew. regionStats() keeps
// every region's, in drawing order (left, then right), and only the last frame's.
TEST(ViewerCompare, EachSideOfASplitKeepsItsOwnStats) {
  TuningState split = cellsK16();
  split.split = SplitMode::Vertical;
  auto viewer = viewTorus(split);
  ASSERT_NE(viewer, nullptr);
  for (int frame = 0; frame < 2; ++frame) (void)frameWith(*viewer, split);
  const auto cells = viewer->renderer().feature<hsdf::HermiteCellFeature>()->regionStats();
  const auto trace = viewer->renderer().feature<hsdf::SphereTraceFeature>()->regionStats();
  ASSERT_EQ(cells.size(), 2u) << "one entry per region of the last frame";
  ASSERT_EQ(trace.size(), 2u);
  EXPECT_EQ(cells[0].objects, 1u) << "the left side draws the torus as cells";
  EXPECT_GT(cells[0].cells, 0u);
  EXPECT_EQ(cells[1].objects, 0u);
  EXPECT_EQ(trace[0].trilinearObjects, 0u);
  EXPECT_EQ(trace[1].trilinearObjects, 1u) << "the right side traces it";
  split.split = SplitMode::Off;
  (void)frameWith(*viewer, split);
  EXPECT_EQ(viewer->renderer().feature<hsdf::HermiteCellFeature>()->regionStats().size(), 1u)
      << "a frame of one region forgets the split's";
}

// Tricky: a reload must take the SPIR-V on disk now, not the modules made at start-up: the
// trilinear shading shader replaced by the Hermite one changes the colours (the prepass, not
// replaced, keeps the coverage). A broken file must fail with the file named, keep the old
// pipelines drawing the same frame, and cause no validation message; going back to the build's
// shaders restores the original frame.
TEST(ViewerCompare, ReloadShadersTakesFreshSpirvAndKeepsOldPipelinesOnFailure) {
  TuningState tuning = cellsK16();
  tuning.method = hsdf::RenderMethod::TrilinearSphereTrace;
  auto viewer = viewTorus(tuning);
  ASSERT_NE(viewer, nullptr);
  const std::vector<std::uint8_t> original = frameWith(*viewer, tuning);
  const std::string dir = engine::gpu::shaderDirectory().string();
  auto* mesh = viewer->renderer().feature<engine::render::MeshFeature>();
  auto* trace = viewer->renderer().feature<hsdf::SphereTraceFeature>();
  ASSERT_NE(mesh, nullptr);
  ASSERT_NE(trace, nullptr);

  const hsdftest::ScopedTempPath swappedFolder("swapped_shaders"), brokenFolder("broken_shaders");
  const auto swapped = shaderCopy(swappedFolder.path(), {{"sphere_trace_trilinear_shade.frag.spv", "sphere_trace_hermite_shade.frag.spv"},
                                                         {"sphere_trace_trilinear_shade_bindless.frag.spv", "sphere_trace_hermite_shade_bindless.frag.spv"}});
  hsdftest::ScopedEnvironment shaderDir("HSDF_SHADER_DIR", swapped.string());
  ASSERT_TRUE(trace->reloadShaders().ok());
  ASSERT_TRUE(viewer->step().ok());
  const std::vector<std::uint8_t> reloaded = viewer->renderer().readbackColor();
  EXPECT_GT(differingPixels(reloaded, original, {0, 0, kWidth, kHeight}), 100u) << "the new shading shader draws";

  const auto broken = shaderCopy(brokenFolder.path(), {{"mesh.frag.spv", ""}, {"sphere_trace_trilinear_shade.frag.spv", ""},
                                                       {"sphere_trace_trilinear_shade_bindless.frag.spv", ""},
                                                       {"cells_resolve.frag.spv", ""}});
  shaderDir.set(broken.string());
  const std::vector<engine::render::Renderer::ShaderReload> results = viewer->reloadShaders();
  ASSERT_EQ(results.size(), 3u);
  for (const auto& r : results) {
    SCOPED_TRACE(r.feature);
    ASSERT_FALSE(r.status.ok());
    EXPECT_NE(r.status.error().message.find("not SPIR-V"), std::string::npos) << r.status.error().message;
    const char* file = r.feature == "meshes"          ? "mesh.frag.spv"
                       : r.feature == "hermite cells" ? "cells_resolve.frag.spv"
                                                      : "sphere_trace_trilinear_shade";
    EXPECT_NE(r.status.error().message.find(file), std::string::npos) << r.status.error().message;
  }
  EXPECT_NE(viewer->shaderReloadReport().find("not SPIR-V"), std::string::npos) << viewer->shaderReloadReport();
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_EQ(viewer->renderer().readbackColor(), reloaded) << "the old (swapped) pipelines keep drawing";

  shaderDir.set(dir);
  EXPECT_TRUE(mesh->reloadShaders().ok());
  EXPECT_TRUE(trace->reloadShaders().ok());
  auto* cells = viewer->renderer().feature<hsdf::HermiteCellFeature>();
  ASSERT_NE(cells, nullptr);
  EXPECT_TRUE(cells->reloadShaders().ok()) << "the cells reload from the build's shaders";
  ASSERT_TRUE(viewer->step().ok());
  EXPECT_EQ(viewer->renderer().readbackColor(), original);
  const engine::Status closed = viewer->close();
  EXPECT_TRUE(closed.ok()) << closed.error().message;
}

}  // namespace
}  // namespace samples
