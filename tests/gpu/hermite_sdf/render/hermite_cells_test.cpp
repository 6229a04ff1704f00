// The Hermite cell renderer (the paper's method) on lavapipe, against the CPU reference ray caster
// of the same tricubic interpolant: coverage, holes, depth and normal errors, from outside, from
// inside the grid bounds and from inside a cell; the early depth stage, counted and thin variants,
// runs and bricks, proxy boxes; occlusion with meshes; many instances; mirrored, non-uniformly
// scaled and sheared objects; extreme cameras and viewports. The tiles are in cell_tiler_test.cpp,
// the culling passes in cell_culling_test.cpp.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <optional>
#include <set>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "engine/core/image_io.h"
#include "engine/core/math.h"
#include "engine/gpu/pipeline_statistics.h"
#include "engine/render/components.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/render/cell_feature.h"
#include "cell_test_support.h"
#include "device_tolerances.h"
#include "hermite_test_support.h"
#include "shared/host_device.h"

namespace gputest {
namespace {

using namespace engine;

// Why: the torus has a hole and saddle regions (ambiguous cells, rays grazing the inner ring).
TEST_F(HermiteCellsTest, TorusMatchesReferenceFromSixViews) {
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("torus", 16);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  for (int view = 0; view < 6; ++view) {
    SCOPED_TRACE("torus view " + std::to_string(view));
    expectMatchesReference(compareView(*asset, orbitCamera(*asset, view), "torus"));
  }
}

// Why: the box has flat faces seen at grazing angles and sharp edges where, at K = 16, the
// interpolant turns within a fraction of a cell: a ray can enter and leave the surface between two
// of the paper's 3 samples. Sharp features at coarse resolution need more subdivisions; with 5 the
// renderer must match the reference like the smooth shapes do at 3.
TEST_F(HermiteCellsTest, BoxMatchesReferenceFromSixViewsWithFiveSubdivisions) {
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("box", 16);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells, glm::mat4(1.0f), 5);
  for (int view = 0; view < 6; ++view) {
    SCOPED_TRACE("box view " + std::to_string(view));
    expectMatchesReference(compareView(*asset, orbitCamera(*asset, view), "box"));
  }
}

// Why: the bunny's kept cells are the paper's case; thin ears give silhouettes one cell thick.
TEST_F(HermiteCellsTest, BunnyMatchesReferenceAtK32) {
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("bunny", 32);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  for (int view = 0; view < 6; ++view) {
    SCOPED_TRACE("bunny K=32 view " + std::to_string(view));
    expectMatchesReference(compareView(*asset, orbitCamera(*asset, view), "bunny K=32"));
  }
}

TEST_F(HermiteCellsTest, BunnyMatchesReferenceAtK64) {
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("bunny", 64);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  for (int view = 0; view < 6; view += 2) {
    SCOPED_TRACE("bunny K=64 view " + std::to_string(view));
    expectMatchesReference(compareView(*asset, orbitCamera(*asset, view), "bunny K=64"));
  }
}

// Why: from inside the grid bounds the eye sits among the cells, and from inside a cell the near
// plane cuts the cell's front faces away: only the back-face path can find that surface.
TEST_F(HermiteCellsTest, CameraInsideBoundsAndInsideACell) {
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("torus", 16);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  // In the torus hole (inside the grid bounds, outside the surface), looking at the inner ring.
  expectMatchesReference(compareView(
      *asset, render::CameraView::lookAt(torusHole(*asset), torusRing(*asset), 1.2f, 1e-3f, 1.0f), "inside bounds"));

  // Half a cell from the surface, with a near plane of a quarter cell.
  const std::optional<render::CameraView> close = insideACellCamera(*asset);
  ASSERT_TRUE(close);
  const ImageComparison c = compareView(*asset, *close, "inside a cell");
  expectMatchesReference(c);
  const hsdf::HermiteCellFeature::Stats& stats = renderer_->feature<hsdf::HermiteCellFeature>()->stats();
  EXPECT_GT(stats.nearCells, 0u);
  EXPECT_EQ(stats.drawRecords, 2u) << "the object's record and its near cells' (HERMITE_FLAG_NEAR_CELL)";
}

// Why: a proxy box is its cell dilated by at least 2^-12 cells. An eye a hair outside a kept cell,
// inside that dilation and farther than the near plane reaches, sees only the box's back faces:
// unless the cell counts as near the eye (drawn by its back faces), the surface straight ahead
// vanished and the tube behind it showed through (the torus 1e-5 outside its outer equator, with a
// glTF camera's znear of 1e-6: 28,668 of 32,400 pixels wrong). Boxes and tiles, whole and proxy.
TEST_F(HermiteCellsTest, EyeInsideABoxDilationButOutsideItsCell) {
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("torus", 32);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  const std::optional<render::CameraView> camera = justOutsideAKeptCellCamera(*asset);
  ASSERT_TRUE(camera) << "no kept cell of the torus fits the set-up";
  auto& settings = renderer_->feature<hsdf::HermiteCellFeature>()->settings();
  using Tiles = hsdf::HermiteCellFeature::Tiles;
  for (const Tiles tiles : {Tiles::Off, Tiles::On})
    for (const bool proxy : {true, false}) {
      settings.tiles = tiles;
      settings.proxyBoxes = proxy;
      const std::string label = std::string(tiles == Tiles::On ? "tiles" : "boxes") + (proxy ? "" : ", whole cells");
      SCOPED_TRACE(label);
      expectMatchesReference(compareView(*asset, *camera, label.c_str()));
    }
  for (const hsdf::RenderMethod method : {hsdf::RenderMethod::CellRuns, hsdf::RenderMethod::CellBricks}) {
    registry_ = ecs::Registry();
    addSdf(registry_, asset, method);
    const char* label = method == hsdf::RenderMethod::CellRuns ? "runs" : "bricks";
    SCOPED_TRACE(label);
    expectMatchesReference(compareView(*asset, *camera, label));
  }
}

// Why: float holds ~1e-3 at 2^14 = 16,384 units from the world origin and ~1e-2 at 2^17. A cell box
// rasterized in world coordinates there lands a few percent of a cell (the torus at K = 64) away
// from where its fragments search, in exact cell space: cracks and specks between cells (a helper
// counted 57 wrong pixels 2e4 units away, 1,775 at 1e5, the torus at K = 32 as boxes). The renderer
// draws relative to the eye (GpuScene::setOrigin, CameraView::viewFrom) and the culling's matrices
// are made in double, so an object and a camera moved together by an offset that floats hold
// exactly (the eye and target on a 1/64 grid) draw, bit for bit, the image drawn at the origin.
TEST_F(HermiteCellsTest, FarFromTheWorldOriginDrawsTheImageDrawnAtIt) {
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("torus", 64);
  ASSERT_NE(asset, nullptr);
  const render::CameraView orbit = orbitCamera(*asset, 2);
  const auto snap = [](const glm::vec3& p) { return glm::round(p * 64.0f) / 64.0f; };
  const glm::vec3 eye = snap(orbit.position), target = snap(glm::vec3(asset->surfaceBounds.center()));
  auto& settings = renderer_->feature<hsdf::HermiteCellFeature>()->settings();
  using Tiles = hsdf::HermiteCellFeature::Tiles;
  struct Case {
    const char* name;
    hsdf::RenderMethod method;
    Tiles tiles;
  };
  for (const Case& c : {Case{"boxes", hsdf::RenderMethod::Cells, Tiles::Off}, Case{"tiles", hsdf::RenderMethod::Cells, Tiles::On},
                        Case{"runs", hsdf::RenderMethod::CellRuns, Tiles::Off},
                        Case{"bricks", hsdf::RenderMethod::CellBricks, Tiles::Off}}) {
    settings.tiles = c.tiles;
    Frame atOrigin;
    for (const float offset : {0.0f, 16384.0f, 131072.0f}) {
      const std::string label = std::string(c.name) + ", offset " + std::to_string(int(offset));
      const glm::vec3 shift(offset, -offset, 0.5f * offset);
      registry_ = ecs::Registry();
      addSdf(registry_, asset, c.method, glm::translate(glm::mat4(1.0f), shift));
      const render::CameraView camera = render::CameraView::lookAt(eye + shift, target + shift, 0.9f, orbit.znear, 1.0f);
      (void)renderWith(camera, DEBUG_VIEW_NONE);  // both frame slots
      const Frame frame = renderWith(camera, DEBUG_VIEW_NONE);
      if (offset == 0.0f) {
        atOrigin = frame;
        ASSERT_GT(std::count_if(frame.depth.begin(), frame.depth.end(), [](float d) { return d > 0.0f; }), 10000) << label;
        continue;
      }
      int coverage = 0, colour = 0;
      for (std::size_t i = 0; i < frame.depth.size(); ++i) {
        coverage += (frame.depth[i] > 0.0f) != (atOrigin.depth[i] > 0.0f);
        for (int k = 0; k < 3; ++k) colour += std::abs(int(frame.rgba[4 * i + k]) - int(atOrigin.rgba[4 * i + k])) > 24 ? 1 : 0;
      }
      EXPECT_EQ(coverage, 0) << label;
      EXPECT_EQ(colour, 0) << label;
      EXPECT_TRUE(frame.depth == atOrigin.depth) << label << ": the depth is not the origin's, bit for bit";
      EXPECT_EQ(countIsolatedPixels(frame), countIsolatedPixels(atOrigin)) << label << ": specks of its own";
    }
  }
}

// The cell forms that base their rays on HermiteDraw::rayAnchor, and how the feature draws each.
struct CellForm {
  const char* name;
  hsdf::RenderMethod method;
  bool thin;
  hsdf::HermiteCellFeature::Tiles tiles;
};
constexpr CellForm kCellForms[] = {{"boxes", hsdf::RenderMethod::Cells, false, hsdf::HermiteCellFeature::Tiles::Off},
                                   {"thin boxes", hsdf::RenderMethod::Cells, true, hsdf::HermiteCellFeature::Tiles::Off},
                                   {"tiles", hsdf::RenderMethod::Cells, false, hsdf::HermiteCellFeature::Tiles::On},
                                   {"runs", hsdf::RenderMethod::CellRuns, false, hsdf::HermiteCellFeature::Tiles::Off},
                                   {"bricks", hsdf::RenderMethod::CellBricks, false, hsdf::HermiteCellFeature::Tiles::Off}};

void useForm(hsdf::HermiteCellFeature& feature, const CellForm& form) {
  feature.settings().thinBoxes = form.thin ? hsdf::HermiteCellFeature::ThinBoxes::On : hsdf::HermiteCellFeature::ThinBoxes::Off;
  feature.settings().tiles = form.tiles;
}

// Why: a far camera framed as near, a telephoto lens or an orthographic camera placed back along its
// axis (its znear and zfar around the object), puts the eye ~5e5 cells from the cells here. They
// searched in the camera's t, t = 1 at the rasterized face, which a float holds there to ~0.03
// cells (a quarter of a cell at 3e6: the cube 1e5 units away at K = 32 drew 650 / 637 px unlike its
// frame at 300 units, tiles; docs/reliability.md): the ends of each cell's segment and its roots
// moved by that much. Each cell form bases its rays near the object instead (pixel_ray.glsl,
// HermiteDraw::rayAnchor) and must draw the reference's interpolant: its coverage but for a rim
// along the outline, no interior hole or extra, its normals (rebuilt from the hit offsets the
// prepass stores, not from the depth buffer, whose float holds ~0.03 cells there: depth itself is
// not compared). With the camera's t (the old
// shaders in HSDF_SHADER_DIR): 5-16 interior extras and a normal error p99 of 7.7-10.3 degrees in
// every form; based near the object, 0 and 3.1-4.7.
TEST_F(HermiteCellsTest, AFarCameraDrawsTheReferenceForEveryCellForm) {
  createCellRenderer(kSize, kSize);
  hsdf::HermiteCellFeature& feature = *renderer_->feature<hsdf::HermiteCellFeature>();
  const auto asset = bakeAsset("torus", 16);
  ASSERT_NE(asset, nullptr);
  const auto [telephoto, orthographic] = farCameras(*asset, 5.0e5);
  for (const auto& [cameraName, camera] : {std::pair{"telephoto", telephoto}, std::pair{"orthographic", orthographic}}) {
    auto reference = hsdf::renderReference(asset->field, camera.view, camera.proj, {int(kSize), int(kSize)});
    ASSERT_TRUE(reference.ok()) << reference.error().message;
    for (const CellForm& form : kCellForms) {
      const std::string label = std::string(cameraName) + ", " + form.name;
      SCOPED_TRACE(label);
      useForm(feature, form);
      const ImageComparison c = compareAlone(asset, form.method, camera, *reference, camera, "far " + label);
      expectFarCoverage(c, int(kSize * kSize) / 100);
      EXPECT_LT(c.normalErrorP99Degrees, 5.5);
    }
  }
}

// Every cell form's frame against `reference` (`compare`: the fixture's compareAlone with the
// cameras), its coverage (at most `coverage` px differ) and normals (expectFarNormals).
template <class Compare>
void expectEveryFormFar(hsdf::HermiteCellFeature& feature, const hsdf::ReferenceImage& reference, const std::string& name,
                        int coverage, double outlierShare, double p99Degrees, Compare compare) {
  for (const CellForm& form : kCellForms) {
    const std::string label = name + " " + form.name;
    SCOPED_TRACE(label);
    useForm(feature, form);
    Frame normals;
    const ImageComparison c = compare(form, label, &normals);
    expectFarCoverage(c, coverage);
    expectFarNormals(normals, reference, c, label, outlierShare, p99Degrees);
  }
}

// Why: the anchor (HermiteDraw::rayAnchor) is made in double on the host, where the eye in grid units
// is exact; made in float from the eye (the shaders did, per vertex and fragment) it held ~0.5 cell
// 7.5e6 cells out (3e5 object sizes: docs/reliability.md), and every ray of the object moved with
// it. An orthographic camera draws the same image from anywhere along its axis, so placed 1e7
// cells back it must draw the coverage the CPU reference draws for it placed 3 radii back (the same
// rotation, its point moved along the axis in double), in every form: 0 px differ; with the anchor
// made from the eye rounded to float, 902 (118 interior holes, 119 extras).
// And its normals (kFarHitCells): the resolve rebuilt each hit from the prepass depth, first through
// float world space (the view point and the model's inverse translation as long as the distance,
// each rounded by a float ulp of it on all three axes), then on the pixel's ray from the object's
// anchor (session 38), where the depth's own rounding was left: ~0.6 cell along the ray here. The
// prepass stores each hit's view depth past the anchor beside the visibility
// (RendererFormats::hitOffset, pixelRayHitOffset) and the resolve rebuilds the hit from it
// (pixelRayStoredPoint): the normals are those of the camera placed near (kFarNormalOutlierShare).
// Rebuilt from the depth: 12,297-13,011 px more than 3 degrees off, the limit 44.
TEST_F(HermiteCellsTest, AnOrthographicCameraFarBackDrawsWhatItDrawsNear) {
  createCellRenderer(kSize, kSize);
  hsdf::HermiteCellFeature& feature = *renderer_->feature<hsdf::HermiteCellFeature>();
  const auto asset = bakeAsset("torus", 16);
  ASSERT_NE(asset, nullptr);
  const auto [far, near] = farBackCameras(*asset, kFarHitCells);
  auto reference = hsdf::renderReference(asset->field, near.view, near.proj, {int(kSize), int(kSize)});
  ASSERT_TRUE(reference.ok()) << reference.error().message;
  expectEveryFormFar(feature, *reference, "far back", 20, kFarNormalOutlierShare, kFarNormalP99Degrees,
                     [&](const CellForm& form, const std::string& label, Frame* normals) {
                       return compareAlone(asset, form.method, far, *reference, near, label, normals);
                     });
}

// Why: a telephoto camera's depth (reverse-Z znear / d, an infinite far plane) holds ~6e-8 of d:
// 1e6 cells from the torus, ~0.06 cell along the ray, which the resolve's normals showed when it
// rebuilt each hit from the depth: 604-658 of the 22,349 hits more than 3 degrees off the CPU
// reference of the same camera (2.7-2.9 %), p99 5.1 degrees (3e6 cells: 19-22 %, 1e7: 49 %). Every
// form stores its hit's offset from the anchor beside the visibility (the tiles the winner's, in its
// own object's t) and the resolve rebuilds the hit from it. The reference casts from the eye the
// renderer draws from (referenceFromTheEye): 0 px of coverage and 0 hits off, p99 0.60 degrees, in
// every form at 1e6 and 3e6 cells; at 1e7 (kFarHitCells, compared here) 0 px and 0-7 hits, p99
// 0.61-0.62. The limits are those the orthographic far-back test keeps on every device (20 px,
// kFarNormalOutlierShare, kFarNormalP99Degrees: margins of 20 px, 37 hits and 0.9 degree over
// lavapipe here). Cast from the view matrix's float translation (0.04 / 0.29 / 0.26 cells off the
// eye at 1e6 / 3e6 / 1e7) the reference showed 41 / 85 / 833 hits off and a rim of 257-303 px:
// the test ran at 1e6 with 1 %, p99 5.5 and 655 px, which let through the anchor made from the eye
// rounded to float (ray_anchor.cpp: 24 px, 0 hits, p99 0.69 at 1e6); here it fails, 639 px and
// 5,390 hits off, p99 9.6-10.1.
TEST_F(HermiteCellsTest, AFarTelephotoCameraShadesTheHitsItsPrepassStored) {
  createCellRenderer(kSize, kSize);
  hsdf::HermiteCellFeature& feature = *renderer_->feature<hsdf::HermiteCellFeature>();
  const auto asset = bakeAsset("torus", 16);
  ASSERT_NE(asset, nullptr);
  const render::CameraView telephoto = farCameras(*asset, kFarHitCells).first;
  const hsdf::ReferenceImage reference = referenceFromTheEye(asset->field, telephoto, {int(kSize), int(kSize)});
  expectEveryFormFar(feature, reference, "far telephoto", 20, kFarNormalOutlierShare, kFarNormalP99Degrees,
                     [&](const CellForm& form, const std::string& label, Frame* normals) {
                       return compareAlone(asset, form.method, telephoto, reference, telephoto, label, normals);
                     });
}

// Why: the tiles walk the entries of every object whose cells cover the tile, keep the best hit
// converted into each object's t as they go (cell_tiles_depth.glsl: `best`, compared across
// objects) and store the winner's own t (`hitT`), from which the resolve rebuilds the hit on the
// winner's anchor; every other form draws an object at a time, and the resolve reads each
// object's anchor through its draw record. One object per test told neither apart. Two objects
// with different anchors, overlapping on screen (twoOverlappingObjects: the second partly behind
// the first, partly beside it), 1e7 cells back (kFarHitCells): every form's normals must be those
// of the CPU reference of both placed near (nearerHits): 4-21 of 26,186 hits more than 3 degrees
// off, p99 0.62-0.63. The resolve with the first object's anchor for both (the mutant): 12,870-12,884
// off in every form, p99 47 degrees. The tiles storing the converted `best` instead of `hitT`
// differ only where another object's cell is walked after the winner's, which in a sorted list
// (nearest box first, the walk stopping at the first box behind the hit) needs that cell's box to
// begin within the winner's depth span: where the surfaces cross, 11 px off here against 4 without
// it, not told from the rest (unsorted lists, past CELL_TILE_SORT_MAX entries a tile, walk every
// entry).
TEST_F(HermiteCellsTest, TwoFarObjectsShadeEachHitFromItsOwnAnchor) {
  createCellRenderer(kSize, kSize);
  hsdf::HermiteCellFeature& feature = *renderer_->feature<hsdf::HermiteCellFeature>();
  const auto asset = bakeAsset("torus", 16);
  ASSERT_NE(asset, nullptr);
  const TwoObjects two = twoOverlappingObjects(*asset);
  const auto [far, near] = farBackCameras(two.frame, kFarHitCells * asset->field.grid.spacing);
  hsdf::ReferenceImage references[2];
  for (int i = 0; i < 2; ++i) {
    hsdf::RenderOptions options;
    options.model = two.models[i];
    auto image = hsdf::renderReference(asset->field, near.view, near.proj, {int(kSize), int(kSize)}, nullptr, options);
    ASSERT_TRUE(image.ok()) << image.error().message;
    references[i] = std::move(*image);
  }
  const hsdf::ReferenceImage reference = nearerHits(references[0], references[1]);
  expectEveryFormFar(feature, reference, "two far", 40, kFarNormalOutlierShare, kFarNormalP99Degrees,
                     [&](const CellForm& form, const std::string& label, Frame* normals) {
                       registry_ = ecs::Registry();
                       for (const glm::mat4& model : two.models) addSdf(registry_, asset, form.method, model);
                       const Frame shaded = renderWith(far, DEBUG_VIEW_NONE);
                       *normals = renderWith(far, DEBUG_VIEW_NORMALS);
                       const ImageComparison c =
                           compareWithReference(shaded, &normals->rgba, reference, near, asset->field.grid.spacing);
                       std::printf("[ %s ] hits ref %d gpu %d, disagree %d, holes %d, extras %d, normal err p99 %.2f deg\n",
                                   label.c_str(), c.referenceHits, c.gpuHits, c.disagreements, c.interiorHoles,
                                   c.interiorExtras, c.normalErrorP99Degrees);
                       return c;
                     });
}

// Why: the resolve rebuilds each hit from its object's anchor of the view region it shades
// (HermiteObject::drawRecord, the region's own draw table): a split screen may place an entity
// otherwise in each region, and each anchor is made for its region's placement. The orthographic
// camera 1e7 cells back (kFarHitCells), the torus moved across the view by a third of its size, to
// the left in the left half and to the right in the right half: each half's normals must be those
// of the CPU reference of its placement seen from near: 0 of 26,667 hits more than 3 degrees off,
// p99 0.62. With the hit rebuilt from the depth (not from the offsets the prepass stored): 14,917
// (the limit 53), p99 21.2. Session 38, 1e6 cells back: the first region's draw table (its anchors)
// in both regions' resolve, 11,685 of 27,043; the world-space rebuild, 699.
TEST_F(HermiteCellsTest, EachViewRegionRebuildsItsFarHitsFromItsOwnAnchor) {
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("torus", 16);
  ASSERT_NE(asset, nullptr);
  const auto [far, near] = farBackCameras(*asset, kFarHitCells);
  const glm::vec3 across = glm::vec3(glm::inverse(far.view)[0]) * float(glm::length(asset->surfaceBounds.size()) / 3.0);
  const glm::mat4 placements[2] = {glm::translate(glm::mat4(1.0f), -across), glm::translate(glm::mat4(1.0f), across)};
  const std::uint32_t half = kSize / 2;
  // The reference: each half from the near camera's reference of that half's placement.
  hsdf::ReferenceImage reference;
  for (int side = 0; side < 2; ++side) {
    hsdf::RenderOptions options;
    options.model = placements[side];
    auto image = hsdf::renderReference(asset->field, near.view, near.proj, {int(kSize), int(kSize)}, nullptr, options);
    ASSERT_TRUE(image.ok()) << image.error().message;
    if (side == 0) {
      reference = *image;
      continue;
    }
    for (int y = 0; y < int(kSize); ++y)
      for (int x = int(half); x < int(kSize); ++x) {
        const std::size_t i = reference.pixel(x, y);
        reference.depth[i] = image->depth[i];
        reference.normal[i] = image->normal[i];
        reference.hit[i] = image->hit[i];
        reference.cellId[i] = image->cellId[i];
      }
  }
  const ecs::Entity entity = addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  const auto place = [&](int side) { registry_.get<scene::WorldTransform>(entity).matrix = placements[side]; };
  render::FrameSettings settings;
  settings.regions = {{{{0, 0}, {half, kSize}}, [&] { place(0); }}, {{{int(half), 0}, {kSize - half, kSize}}, [&] { place(1); }}};
  const Frame shaded = renderWith(far, settings);
  settings.debugView = DEBUG_VIEW_NORMALS;
  const Frame normals = renderWith(far, settings);
  const ImageComparison c = compareWithReference(shaded, &normals.rgba, reference, near, asset->field.grid.spacing);
  std::printf("[ far split ] hits ref %d gpu %d, disagree %d, holes %d, extras %d, normal err p99 %.2f deg, flipped %d\n",
              c.referenceHits, c.gpuHits, c.disagreements, c.interiorHoles, c.interiorExtras, c.normalErrorP99Degrees,
              c.normalFlips);
  expectFarCoverage(c, 40);
  expectFarNormals(normals, reference, c, "far split");
}

// Why: the rays' anchor (HermiteDraw::rayAnchor) is made per object and view region on the host,
// from the region's own placement of the object: each region calls the feature's prepare, and a
// split screen may draw an entity placed otherwise in each (here moved across the view by a third
// of its size, to the left in the left half and to the right in the right half). Each half must be
// the frame drawn with that placement alone, bit for bit, in every cell form.
TEST_F(HermiteCellsTest, EachViewRegionBasesItsRaysOnItsOwnAnchor) {
  createCellRenderer(kSize, kSize);
  hsdf::HermiteCellFeature& feature = *renderer_->feature<hsdf::HermiteCellFeature>();
  const auto asset = bakeAsset("torus", 16);
  ASSERT_NE(asset, nullptr);
  const render::CameraView camera = orbitCamera(*asset, 1);
  const glm::vec3 across = glm::vec3(glm::inverse(camera.view)[0]) * float(glm::length(asset->surfaceBounds.size()) / 3.0);
  const glm::mat4 left = glm::translate(glm::mat4(1.0f), -across), right = glm::translate(glm::mat4(1.0f), across);
  const std::uint32_t half = kSize / 2;
  for (const CellForm& form : kCellForms) {
    SCOPED_TRACE(form.name);
    registry_ = ecs::Registry();
    const ecs::Entity entity = addSdf(registry_, asset, form.method);
    useForm(feature, form);
    const auto place = [&](const glm::mat4& m) { registry_.get<scene::WorldTransform>(entity).matrix = m; };
    place(left);
    const Frame leftAlone = renderWith(camera, DEBUG_VIEW_NORMALS);
    place(right);
    const Frame rightAlone = renderWith(camera, DEBUG_VIEW_NORMALS);
    render::FrameSettings settings;
    settings.debugView = DEBUG_VIEW_NORMALS;
    settings.regions = {{{{0, 0}, {half, kSize}}, [&] { place(left); }}, {{{int(half), 0}, {kSize - half, kSize}}, [&] { place(right); }}};
    const Frame split = renderWith(camera, settings);
    int wrong = 0, covered[2] = {0, 0};
    for (std::uint32_t y = 0; y < kSize; ++y)
      for (std::uint32_t x = 0; x < kSize; ++x) {
        const std::size_t i = std::size_t(y) * kSize + x;
        const Frame& alone = x < half ? leftAlone : rightAlone;
        covered[x < half ? 0 : 1] += alone.depth[i] > 0.0f;
        wrong += !std::equal(split.rgba.begin() + long(4 * i), split.rgba.begin() + long(4 * i + 4), alone.rgba.begin() + long(4 * i));
      }
    EXPECT_EQ(wrong, 0) << "pixels of the split screen unlike the frame of their half's placement";
    EXPECT_GT(covered[0], 2000) << "the left placement must show in the left half for the test to mean something";
    EXPECT_GT(covered[1], 2000) << "and the right one in the right half";
  }
}

// Early depth (the default) tests each box at its own face's depth and writes the hits' depths in
// a fix-up pass; with it off every box writes its hit's depth. Both must draw the same surface.
// Why these cases: orbit views of the bunny (front-to-back rows, silhouettes where boxes are grazed
// and find no root), cell runs (one box per run, the same stage), a mesh plane through the bunny
// (meshes draw after the fix-up and must be tested against the hits, not the faces), and a camera
// inside a cell of the torus (near-plane cells drawn by their back faces, writing depth in both
// modes, beside front boxes tested at their faces).
// Why not bit for bit: a root on a face shared by two cells is found by both (each searches its
// box dilated by a margin), at depths that differ in the last bits. Writing depth keeps the nearer
// of the two; early depth keeps the one of the box drawn first, whose face hides the other. So a
// few pixels may name the neighbouring cell, at a depth equal to 1e-5 relative.
// The point of the stage is work: boxes behind a hit skip their search, so the root-search
// evaluations summed over the frame's pixels (the work counters) must drop where fragments are
// shaded in primitive order (lavapipe). A GPU shades the boxes of a pixel in parallel: on an H200
// the evaluations were the same with and without the stage (DeviceTolerances).
TEST_F(HermiteCellsTest, EarlyDepthDrawsTheSameSurfaceWithFewerEvaluations) {
  createCellRenderer(kSize, kSize);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  feature->settings().cullOcclusion = false;  // occlusion culling keeps the stage off
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;  // and so do tiles
  // The stage belongs to the attribute boxes (thin ones have none, and ThinBoxes::Auto picks them
  // on a GPU for cells this small on screen).
  feature->settings().thinBoxes = hsdf::HermiteCellFeature::ThinBoxes::Off;
  const auto bunny = bakeAsset("bunny", 32);
  const auto torus = bakeAsset("torus", 16);
  ASSERT_NE(bunny, nullptr);
  ASSERT_NE(torus, nullptr);

  struct Buffers {
    std::vector<float> depth;
    std::vector<glm::uvec2> visibility;
    std::uint64_t evaluations = 0;
  };
  const auto draw = [&](const render::CameraView& camera, bool early) {
    feature->settings().earlyDepth = early ? hsdf::HermiteCellFeature::EarlyDepth::On : hsdf::HermiteCellFeature::EarlyDepth::Off;
    render::FrameSettings settings;
    settings.countWork = true;
    renderer_->renderFrame(registry_, camera, settings);
    Buffers b;
    b.depth = renderer_->readbackDepth();
    b.visibility = renderer_->readbackVisibility();
    for (std::uint32_t count : renderer_->readbackWorkCounters()) b.evaluations += count;
    EXPECT_EQ(feature->stats().earlyDepth, early);
    return b;
  };
  const auto neighbours = [](const hsdf::SdfAsset& asset, std::uint32_t a, std::uint32_t b) {
    const auto& records = asset.cells.records;
    if (a >= records.size() || b >= records.size()) return false;
    return std::abs(int(records[a].x) - int(records[b].x)) <= 1 && std::abs(int(records[a].y) - int(records[b].y)) <= 1 &&
           std::abs(int(records[a].z) - int(records[b].z)) <= 1;
  };
  const auto expectSame = [&](const hsdf::SdfAsset& asset, const render::CameraView& camera, const char* label,
                              bool fewer) {
    const Buffers late = draw(camera, false);
    const Buffers early = draw(camera, true);
    int covered = 0, differs = 0, farApart = 0;
    double worst = 0.0;
    for (std::size_t i = 0; i < late.depth.size(); ++i) {
      covered += late.depth[i] > 0.0f;
      if (late.depth[i] == early.depth[i] && late.visibility[i] == early.visibility[i]) continue;
      ++differs;
      worst = std::max(worst, double(std::abs(late.depth[i] - early.depth[i]) / std::max(late.depth[i], 1e-30f)));
      const bool sameObject = late.visibility[i].x == early.visibility[i].x;
      // Cell records are global to the feature's buffer: one asset per frame here, so index = record.
      if (!sameObject || !neighbours(asset, late.visibility[i].y, early.visibility[i].y)) ++farApart;
    }
    std::printf("[ %s ] covered %d, differ %d (depth rel. %.1e at most), not neighbours %d, evaluations %llu -> %llu\n",
                label, covered, differs, worst, farApart, static_cast<unsigned long long>(late.evaluations),
                static_cast<unsigned long long>(early.evaluations));
    EXPECT_GT(covered, 500) << label;
    EXPECT_LE(differs, covered / 500) << label;
    EXPECT_LT(worst, 1e-5) << label;
    EXPECT_EQ(farApart, 0) << label;
    if (fewer && tolerancesFor(*context_).fragmentsShadeInPrimitiveOrder) {
      EXPECT_LT(double(early.evaluations), 0.8 * double(late.evaluations)) << label;
    } else {
      EXPECT_LE(early.evaluations, late.evaluations) << label;  // never more work
    }
  };

  const ecs::Entity object = addSdf(registry_, bunny, hsdf::RenderMethod::Cells);
  for (int view = 0; view < 6; view += 2) expectSame(*bunny, orbitCamera(*bunny, view), "bunny", true);
  registry_.get<hsdf::HermiteSdfRenderable>(object).method = hsdf::RenderMethod::CellRuns;
  expectSame(*bunny, orbitCamera(*bunny, 1), "bunny runs", true);
  registry_.get<hsdf::HermiteSdfRenderable>(object).method = hsdf::RenderMethod::Cells;

  const glm::vec3 center(bunny->surfaceBounds.center());
  const ecs::Entity plane = addQuad(center, 3.0f * float(glm::length(bunny->surfaceBounds.size())), {0.3f, 0.3f, 0.9f, 1.0f});
  registry_.get<scene::Transform>(plane).rotation = glm::angleAxis(-1.5707963f, glm::vec3(1, 0, 0));
  scene::updateWorldTransforms(registry_);
  expectSame(*bunny, orbitCamera(*bunny, 0, 2.2f), "bunny and a mesh plane", false);

  registry_.clear();
  addSdf(registry_, torus, hsdf::RenderMethod::Cells);
  const std::optional<render::CameraView> inside = insideACellCamera(*torus);
  ASSERT_TRUE(inside);
  expectSame(*torus, *inside, "inside a cell", false);
  EXPECT_GT(feature->stats().nearCells, 0u);
}

// The production prepass holds no buffer write and no discard (a miss writes the far plane's depth,
// which the GREATER test rejects; hit_depth.glsl); counting frames use the *_counted variants.
// Both must draw bit for bit the same depth and visibility, for the front faces (conservative
// depth), the near-plane cells (drawn by their back faces; the inside-a-cell camera) and the runs,
// in fp32 and fp16, and the variant must be chosen by whether the frame counts (the renderer's
// work counters or the evaluation heat map), and never in the early depth stage, whose own
// variants count.
TEST_F(HermiteCellsTest, CountedVariantDrawsTheProductionImage) {
  createCellRenderer(kSize, kSize);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  feature->settings().cullOcclusion = false;  // the early stage's variants are checked below
  feature->settings().earlyDepth = hsdf::HermiteCellFeature::EarlyDepth::Off;
  const auto torus = bakeAsset("torus", 16);
  ASSERT_NE(torus, nullptr);
  const ecs::Entity object = addSdf(registry_, torus, hsdf::RenderMethod::Cells);
  // Half a cell in front of the ring, seen from the hole: the near plane cuts cells, which are drawn
  // by their back faces (as in EarlyDepthDrawsTheSameSurfaceWithFewerEvaluations).
  const std::optional<render::CameraView> insideCamera = insideACellCamera(*torus);
  ASSERT_TRUE(insideCamera);
  const render::CameraView inside = *insideCamera;

  struct Buffers {
    std::vector<float> depth;
    std::vector<glm::uvec2> visibility;
    std::uint64_t evaluations = 0;
  };
  const auto draw = [&](const render::CameraView& camera, bool count) {
    render::FrameSettings settings;
    settings.countWork = count;
    renderer_->renderFrame(registry_, camera, settings);
    Buffers b;
    b.depth = renderer_->readbackDepth();
    b.visibility = renderer_->readbackVisibility();
    if (count)
      for (std::uint32_t n : renderer_->readbackWorkCounters()) b.evaluations += n;
    EXPECT_EQ(feature->stats().countedVariant, count);
    EXPECT_FALSE(feature->stats().earlyDepth);
    return b;
  };
  struct Case {
    const char* label;
    hsdf::RenderMethod method;
    bool half;
    render::CameraView camera;
  };
  const Case cases[] = {{"cells", hsdf::RenderMethod::Cells, false, orbitCamera(*torus, 1)},
                        {"cells fp16", hsdf::RenderMethod::Cells, true, orbitCamera(*torus, 2)},
                        {"cells inside", hsdf::RenderMethod::Cells, false, inside},
                        {"runs", hsdf::RenderMethod::CellRuns, false, orbitCamera(*torus, 1)},
                        {"runs inside", hsdf::RenderMethod::CellRuns, false, inside},
                        {"bricks", hsdf::RenderMethod::CellBricks, false, orbitCamera(*torus, 1)},
                        {"bricks fp16", hsdf::RenderMethod::CellBricks, true, orbitCamera(*torus, 2)},
                        {"bricks inside", hsdf::RenderMethod::CellBricks, false, inside}};
  for (const Case& c : cases) {
    auto& renderable = registry_.get<hsdf::HermiteSdfRenderable>(object);
    renderable.method = c.method;
    renderable.halfPrecision = c.half;
    const Buffers plain = draw(c.camera, false);
    const Buffers counted = draw(c.camera, true);
    const bool near = feature->stats().nearCells > 0;
    int covered = 0, differ = 0;
    for (std::size_t i = 0; i < plain.depth.size(); ++i) {
      covered += plain.depth[i] > 0.0f;
      differ += plain.depth[i] != counted.depth[i] || plain.visibility[i] != counted.visibility[i];
    }
    std::printf("[ %s ] covered %d, differ %d, near cells %s, evaluations %llu\n", c.label, covered, differ,
                near ? "yes" : "no", static_cast<unsigned long long>(counted.evaluations));
    EXPECT_GT(covered, 500) << c.label;
    EXPECT_EQ(differ, 0) << c.label;
    EXPECT_GT(counted.evaluations, std::uint64_t(covered)) << c.label << ": every covered pixel searched at least once";
    if (std::string(c.label).ends_with("inside")) {
      EXPECT_TRUE(near) << c.label << ": the near-plane variant was not drawn";
    }
  }

  // The heat map counts with the feature's own counters: the counted variant too.
  registry_.get<hsdf::HermiteSdfRenderable>(object).method = hsdf::RenderMethod::Cells;
  (void)renderWith(orbitCamera(*torus, 1), DEBUG_VIEW_EVALS);
  EXPECT_TRUE(feature->stats().countedVariant);
  (void)renderWith(orbitCamera(*torus, 1), DEBUG_VIEW_NORMALS);
  EXPECT_FALSE(feature->stats().countedVariant);
  // The early depth stage counts in its own variants (it draws boxes: tiles have none).
  feature->settings().earlyDepth = hsdf::HermiteCellFeature::EarlyDepth::On;
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;
  render::FrameSettings counting;
  counting.countWork = true;
  renderer_->renderFrame(registry_, orbitCamera(*torus, 1), counting);
  EXPECT_TRUE(feature->stats().earlyDepth);
  EXPECT_FALSE(feature->stats().countedVariant);
  std::uint64_t earlyEvaluations = 0;
  for (std::uint32_t n : renderer_->readbackWorkCounters()) earlyEvaluations += n;
  EXPECT_GT(earlyEvaluations, 0u);
  // Bricks have no early depth variant: a frame that draws them keeps the stage off, and counts
  // with the bricks' counted variant.
  registry_.get<hsdf::HermiteSdfRenderable>(object).method = hsdf::RenderMethod::CellBricks;
  renderer_->renderFrame(registry_, orbitCamera(*torus, 1), counting);
  EXPECT_FALSE(feature->stats().earlyDepth);
  EXPECT_TRUE(feature->stats().countedVariant);
  EXPECT_GT(feature->stats().bricks, 0u);
}

// Auto: the early depth stage is for software rasterizers (in-order shading), not for GPUs, where
// its atomicMax costs early depth rejection (../shared/gpu/h100-b505968/README.md §3b).
TEST_F(HermiteCellsTest, EarlyDepthAutoFollowsTheDevice) {
  using EarlyDepth = hsdf::HermiteCellFeature::EarlyDepth;
  EXPECT_TRUE(hsdf::HermiteCellFeature::earlyDepthWanted(EarlyDepth::Auto, true));
  EXPECT_FALSE(hsdf::HermiteCellFeature::earlyDepthWanted(EarlyDepth::Auto, false));
  EXPECT_TRUE(hsdf::HermiteCellFeature::earlyDepthWanted(EarlyDepth::On, false));
  EXPECT_FALSE(hsdf::HermiteCellFeature::earlyDepthWanted(EarlyDepth::Off, true));
  createCellRenderer(64, 64);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  EXPECT_EQ(feature->settings().earlyDepth, EarlyDepth::Auto);
  feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;  // the stage draws boxes (TilesAutoFollowsTheDevice)
  const auto torus = bakeAsset("torus", 16);
  ASSERT_NE(torus, nullptr);
  addSdf(registry_, torus, hsdf::RenderMethod::Cells);
  (void)renderWith(orbitCamera(*torus, 0), DEBUG_VIEW_NONE);
  EXPECT_EQ(feature->stats().earlyDepth, context_->capabilities().isSoftwareRasterizer);
  // Occlusion culling (off by default) keeps the stage off whatever the device.
  feature->settings().cullOcclusion = true;
  (void)renderWith(orbitCamera(*torus, 0), DEBUG_VIEW_NONE);
  EXPECT_FALSE(feature->stats().earlyDepth);
}

// Cell runs (RenderMethod::CellRuns) draw the same cells as one box per run along x and walk them
// in the fragment shader; cell bricks (RenderMethod::CellBricks) as one box per 4x4x4 brick, walked
// in 3D along the ray. Why these cases: the torus's rows hold long runs whose inner faces the
// rays cross (the walk must continue into the next cell and stop at the first root); the box's
// flat faces lie on the faces shared by cells of one run (the walk's per-cell dilated segments
// must keep that root); fp16 records are read by address with the half layout; the bunny at K = 64
// has runs cut at the maximum length inside long rows. For the bricks, the rays cross brick faces and
// the faces between cells of one brick along every axis, and the box's flat faces lie on both.
TEST_F(HermiteCellsTest, CellRunsAndBricksMatchReferenceForTorusBoxAndBunny) {
  createCellRenderer(kSize, kSize);
  for (const hsdf::RenderMethod method : {hsdf::RenderMethod::CellRuns, hsdf::RenderMethod::CellBricks}) {
  struct Case {
    const char* shape;
    int k;
    std::uint32_t subdivisions;
    bool half;
  };
  for (const Case& test : {Case{"torus", 16, 3, false}, Case{"box", 16, 5, false}, Case{"torus", 16, 3, true},
                           Case{"bunny", 64, 3, false}}) {
    registry_ = ecs::Registry();
    const auto asset = bakeAsset(test.shape, test.k);
    ASSERT_NE(asset, nullptr);
    const ecs::Entity entity = addSdf(registry_, asset, method, glm::mat4(1.0f), test.subdivisions);
    registry_.get<hsdf::HermiteSdfRenderable>(entity).halfPrecision = test.half;
    for (int view = 0; view < 6; view += 2) {
      const std::string label = std::string(test.shape) + " " + hsdf::renderMethodName(method) + (test.half ? " fp16" : "");
      SCOPED_TRACE(label + " view " + std::to_string(view));
      const ImageComparison c = compareView(*asset, orbitCamera(*asset, view), label.c_str());
      if (test.half) {  // fp16 corners: the coverage and the surface, not the last digits of depth
        EXPECT_GE(c.agreement(kSize * kSize), 0.999);
        EXPECT_EQ(c.interiorHoles, 0);
        EXPECT_EQ(c.interiorExtras, 0);
      } else {
        expectMatchesReference(c);
      }
    }
    const hsdf::HermiteCellFeature::Stats& stats = renderer_->feature<hsdf::HermiteCellFeature>()->stats();
    const std::uint64_t boxes = method == hsdf::RenderMethod::CellRuns ? stats.runs : stats.bricks;
    EXPECT_GT(boxes, 0u);
    EXPECT_LT(boxes, stats.cells) << "some kept cells must share a box";
    if (method == hsdf::RenderMethod::CellBricks) {
      EXPECT_EQ(stats.draws, 1u + stats.nearCells) << "one indirect command per object, plus near-plane bricks";
    }
  }
  }
}

// Why: an orthographic camera has no eye point. Every cell form (the paper's boxes, thin boxes,
// screen tiles, runs, bricks) must build parallel rays from the
// camera's plane (not from one point), pick each box's front faces by the view direction (an eye
// point's side of the box is meaningless), size the proxies' dilation by the constant pixel size,
// and turn t into linear depth. The last view puts the near plane through the torus's centre, so
// cells it cuts are drawn by their back faces with rays starting on the near plane inside them; the
// fourth has the camera's point off to the side of the torus. Any of these done the perspective
// way draws a distorted or holed torus.
TEST_F(HermiteCellsTest, OrthographicCameraMatchesReferenceForEveryCellForm) {
  createCellRenderer(kSize, kSize);
  hsdf::HermiteCellFeature& feature = *renderer_->feature<hsdf::HermiteCellFeature>();
  const auto asset = bakeAsset("torus", 16);
  ASSERT_NE(asset, nullptr);
  const float radius = 0.5f * float(glm::length(asset->surfaceBounds.size()));
  using Tiles = hsdf::HermiteCellFeature::Tiles;
  struct Form {
    hsdf::RenderMethod method;
    bool thin;
    Tiles tiles;
  };
  for (const Form form : {Form{hsdf::RenderMethod::Cells, false, Tiles::Off}, Form{hsdf::RenderMethod::Cells, true, Tiles::Off},
                          Form{hsdf::RenderMethod::Cells, false, Tiles::On}, Form{hsdf::RenderMethod::CellRuns, false, Tiles::Off},
                          Form{hsdf::RenderMethod::CellBricks, false, Tiles::Off}}) {
    registry_ = ecs::Registry();
    addSdf(registry_, asset, form.method);
    feature.settings().thinBoxes =
        form.thin ? hsdf::HermiteCellFeature::ThinBoxes::On : hsdf::HermiteCellFeature::ThinBoxes::Off;
    feature.settings().tiles = form.tiles;
    for (int view = 0; view < 4; ++view) {
      const bool cut = view == 2;
      // View 3: the camera's point lies 3 radii to the side of the torus, on the -x side of most of
      // its cells while the rays run towards -x: the side of a box the viewer is on is the view
      // direction's, not the camera point's (whose side would pick back faces, left as holes).
      const glm::vec3 center(asset->surfaceBounds.center());
      const glm::vec3 back = glm::normalize(glm::vec3(1.0f, 0.3f, 1.0f)), side = glm::normalize(glm::vec3(-1.0f, 0.0f, 1.0f));
      const glm::vec3 offAxis = center + 1.9f * radius * back + 3.0f * radius * side;
      const render::CameraView camera =
          view == 3 ? orthographicLike(render::CameraView::lookAt(offAxis, offAxis - back, 0.9f, 0.01f, 1.0f), 4.2f * radius,
                                       0.01f * radius, 6.0f * radius)
                    : orthographicLike(orbitCamera(*asset, view), 0.8f * radius, cut ? 1.9f * radius : 0.01f * radius,
                                       4.0f * radius);
      const std::string label = std::string(hsdf::renderMethodName(form.method)) + (form.thin ? " thin" : "") +
                                (form.tiles == Tiles::On ? " tiles" : "") + " orthographic view " + std::to_string(view);
      SCOPED_TRACE(label);
      expectMatchesReference(compareView(*asset, camera, label.c_str()));
      if (cut && form.tiles == Tiles::Off) {
        EXPECT_GT(feature.stats().nearCells, 0u) << "the near plane cuts cells: drawn by back faces";
      }
    }
  }
}

// Why: the projection must be checked independently of the reference caster, which shares the
// engine's camera maths: a sphere of radius r under an orthographic camera is a circle of r / ymag
// * height / 2 pixels at every distance (a perspective camera's would shrink with distance).
TEST_F(HermiteCellsTest, OrthographicSphereIsACircleOfTheProjectedRadius) {
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("sphere", 32);  // radius 1 about the origin
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  const float ymag = 1.6f;
  const double expected = 1.0 / double(ymag) * double(kSize) / 2.0;
  for (const float distance : {3.0f, 12.0f}) {
    const render::CameraView perspective =
        render::CameraView::lookAt(glm::vec3(0.6f, 0.3f, 0.74f) * distance, glm::vec3(0.0f), 0.9f, 0.1f, 1.0f);
    const Frame frame = renderWith(orthographicLike(perspective, ymag, 0.5f, 2.0f * distance), DEBUG_VIEW_NONE);
    int covered = 0;
    double sumX = 0.0, sumY = 0.0;
    for (std::uint32_t y = 0; y < frame.height; ++y)
      for (std::uint32_t x = 0; x < frame.width; ++x)
        if (frame.depthAt(x, y) > 0.0f) ++covered, sumX += x + 0.5, sumY += y + 0.5;
    const double radius = std::sqrt(double(covered) / 3.14159265358979);
    EXPECT_NEAR(radius, expected, 0.5) << "at distance " << distance;
    EXPECT_NEAR(sumX / covered, kSize / 2.0, 0.25) << "centred";
    EXPECT_NEAR(sumY / covered, kSize / 2.0, 0.25);
  }
}

// Why: a telephoto camera (1 degree field of view, the torus ~125 radii away) makes every ray
// nearly parallel and puts all depths in a narrow band near 0 under reverse-Z; the near plane is
// 12000x closer than the surface. Rays rebuilt from the fragment's depth must still meet the
// reference's surface without cracks.
TEST_F(HermiteCellsTest, TelephotoCameraMatchesReference) {
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("torus", 16);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  const glm::vec3 center(asset->surfaceBounds.center());
  const float radius = 0.5f * float(glm::length(asset->surfaceBounds.size()));
  const float fovY = 0.01745f;
  const float distance = 0.8f * radius / std::tan(0.5f * fovY);
  for (int view = 0; view < 2; ++view) {
    const render::CameraView camera = render::CameraView::lookAt(
        math::orbitEye(center, distance, 0.4f + 1.3f * float(view), view == 0 ? 0.3f : -0.45f), center, fovY,
        0.01f * radius, 1.0f);
    const std::string label = "telephoto view " + std::to_string(view);
    SCOPED_TRACE(label);
    const ImageComparison c = compareView(*asset, camera, label.c_str());
    expectMatchesReference(c);
    EXPECT_EQ(countIsolatedPixels(renderWith(camera, DEBUG_VIEW_NORMALS)), 0) << "cracks";
  }
}

// Settings::thinBoxes draws the same cells with 8 vertices and 12 bytes of varyings per box
// (cells_thin.vert), the fragment shader reading each cell's 32 scalars by address. It must draw
// the cells' surface: against the reference, and against the paper's boxes (the same search over
// the same dilated box along the same ray: equal coverage but for a few edge pixels, where the fan
// and the list split the faces into triangles differently, and equal depth to float rounding).
// Why these cases: the torus from orbit views (every octant picks other front faces for the fan),
// fp16 records (the half layout read by address, not converted by the vertex fetch), the box's flat
// faces on cell faces (roots on faces two boxes share), a mirrored model matrix (the fan's winding
// flips), and an eye inside a cell (near-plane cells as a 14-vertex strip of back faces).
TEST_F(HermiteCellsTest, ThinBoxesDrawThePapersBoxesSurface) {
  createCellRenderer(kSize, kSize);
  hsdf::HermiteCellFeature& feature = *renderer_->feature<hsdf::HermiteCellFeature>();
  const auto torus = bakeAsset("torus", 16);
  const auto box = bakeAsset("box", 16);
  ASSERT_NE(torus, nullptr);
  ASSERT_NE(box, nullptr);
  const auto expectSameAsPapers = [&](const hsdf::SdfAsset& asset, const render::CameraView& camera, bool half,
                                      const glm::mat4& model, const std::string& label) {
    SCOPED_TRACE(label);
    feature.settings().thinBoxes = hsdf::HermiteCellFeature::ThinBoxes::Off;
    const Frame paper = renderWith(camera, DEBUG_VIEW_NONE);
    feature.settings().thinBoxes = hsdf::HermiteCellFeature::ThinBoxes::On;
    const ImageComparison c = compareView(asset, camera, label.c_str(), model);
    const Frame thin = renderWith(camera, DEBUG_VIEW_NONE);
    if (half) {
      EXPECT_GE(c.agreement(kSize * kSize), 0.999);
      EXPECT_EQ(c.interiorHoles, 0);
      EXPECT_EQ(c.interiorExtras, 0);
    } else {
      expectMatchesReference(c);
    }
    // The two rasterize the same faces as different triangles, so each pixel's search starts from
    // a slightly different face point: depths agree to float rounding, except on the few pixels
    // whose root lies on a face two cells share (found by either cell, at depths that differ in the
    // refinement's last step; up to 1.2e-4 relative on an H200's box views).
    int covered = 0, coverageDiffers = 0, depthDiffers = 0;
    double worst = 0.0;
    for (std::size_t i = 0; i < paper.depth.size(); ++i) {
      const bool a = paper.depth[i] > 0.0f, b = thin.depth[i] > 0.0f;
      covered += a;
      coverageDiffers += a != b;
      if (!a || !b) continue;
      const double relative = double(std::abs(paper.depth[i] - thin.depth[i]) / paper.depth[i]);
      worst = std::max(worst, relative);
      depthDiffers += relative > 1e-5;
    }
    std::printf("[ %s ] thin vs paper's boxes: covered %d, coverage differs %d, depth rel. > 1e-5 at %d, %.1e at most\n",
                label.c_str(), covered, coverageDiffers, depthDiffers, worst);
    EXPECT_GT(covered, 500);
    EXPECT_LE(coverageDiffers, covered / 1000);
    EXPECT_LE(depthDiffers, covered / 1000);
    EXPECT_LT(worst, 1e-3);
  };
  const ecs::Entity entity = addSdf(registry_, torus, hsdf::RenderMethod::Cells);
  for (int view = 0; view < 6; ++view)
    expectSameAsPapers(*torus, orbitCamera(*torus, view), false, glm::mat4(1.0f), "torus view " + std::to_string(view));
  registry_.get<hsdf::HermiteSdfRenderable>(entity).halfPrecision = true;
  expectSameAsPapers(*torus, orbitCamera(*torus, 1), true, glm::mat4(1.0f), "torus fp16");
  registry_.get<hsdf::HermiteSdfRenderable>(entity).halfPrecision = false;

  // Mirrored: the torus scaled by -1 along x about its centre.
  const glm::vec3 centre(torus->surfaceBounds.center());
  const glm::mat4 mirror = glm::translate(glm::mat4(1.0f), centre) * glm::scale(glm::mat4(1.0f), {-1.0f, 1.0f, 1.0f}) *
                           glm::translate(glm::mat4(1.0f), -centre);
  registry_ = ecs::Registry();
  addSdf(registry_, torus, hsdf::RenderMethod::Cells, mirror);
  expectSameAsPapers(*torus, orbitCamera(*torus, 2), false, mirror, "torus mirrored");

  registry_ = ecs::Registry();
  addSdf(registry_, box, hsdf::RenderMethod::Cells, glm::mat4(1.0f), 5);
  for (int view = 0; view < 6; view += 2)
    expectSameAsPapers(*box, orbitCamera(*box, view), false, glm::mat4(1.0f), "box view " + std::to_string(view));

  // Half a cell from the torus's inner ring with a near plane of a quarter cell (as in
  // CameraInsideBoundsAndInsideACell): the eye's own cell is cut by the near plane.
  registry_ = ecs::Registry();
  addSdf(registry_, torus, hsdf::RenderMethod::Cells);
  const std::optional<render::CameraView> inside = insideACellCamera(*torus);
  ASSERT_TRUE(inside);
  expectSameAsPapers(*torus, *inside, false, glm::mat4(1.0f), "inside a cell");
  EXPECT_GT(feature.stats().nearCells, 0u);
  EXPECT_FALSE(feature.stats().earlyDepth) << "thin boxes have no early depth variant";

  // Auto: thin boxes on hardware rasterizers when the cells are small on screen, never on a
  // software rasterizer (which would lose its early depth stage). The torus at K = 16 from the
  // orbit distance (cells of ~14 pixels here) and 12x farther (~1 pixel); the cell size the
  // feature reports against the pinhole projection of one cell at the grid centre's distance.
  using hsdf::HermiteCellFeature;
  feature.settings().thinBoxes = HermiteCellFeature::ThinBoxes::Auto;
  const bool hardware = !context_->capabilities().isSoftwareRasterizer;
  for (const float distanceScale : {1.9f, 23.0f}) {
    SCOPED_TRACE("orbit distance x" + std::to_string(distanceScale));
    const render::CameraView camera = orbitCamera(*torus, 1, distanceScale);
    (void)renderWith(camera, DEBUG_VIEW_NONE);
    const double distance = glm::length(glm::dvec3(camera.position) - torus->cells.grid.bounds().center());
    const double expected = torus->cells.grid.spacing / distance * kSize / (2.0 * std::tan(0.5 * double(camera.fovY)));
    EXPECT_NEAR(feature.stats().largestCellPixels, expected, 1e-3 * expected);
    const bool small = feature.stats().largestCellPixels <= HermiteCellFeature::kThinBoxesMaxCellPixels;
    EXPECT_EQ(small, distanceScale > 2.0f) << "the two distances must fall on both sides of the threshold";
    EXPECT_EQ(feature.stats().thinBoxes, hardware && small);
  }
}


// Why: every cell method draws and searches each cell's proxy box (Settings::proxyBoxes; cells.h,
// "Proxy boxes"), the part of the cell its zero set can reach, instead of the whole cell. A box that
// missed part of the zero set would lose those roots (a hole, a farther hit, a neighbour's colour);
// the point of the boxes is less work. Each method and record precision against the whole cells:
// the bunny at K = 16 (cells of ~20 pixels) and K = 64 from two sides, and the torus from inside one
// of its cells (near-plane boxes, drawn by their back faces). Root-search evaluations fall for every
// method (a ray that misses a cell's proxy box skips its search); prepass fragments fall for the
// boxes and the runs (the union of their cells' boxes), whose rasterized proxies shrink (summed over the views: on a GPU the early depth test
// depends on the order of parallel fragments). The roots are placed on another segment, so their
// depth may move by the default search's placement error (one Newton step from the control
// polygon's zero: up to 1.1e-4 of the depth at K = 16 on lavapipe), and by little more than the
// rounding in the certified search, which solves to 2^-18 of its interval.
TEST_F(HermiteCellsTest, ProxyBoxesDrawTheWholeCellsImageWithLessWork) {
  createCellRenderer(kSize, kSize);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  using Tiles = hsdf::HermiteCellFeature::Tiles;
  using ThinBoxes = hsdf::HermiteCellFeature::ThinBoxes;
  struct Case {
    const char* label;
    hsdf::RenderMethod method;
    Tiles tiles;
    ThinBoxes thin;
    bool half;
    bool boxes;  // its proxies shrink with the cells' boxes (fewer fragments expected): boxes, runs
    bool certified = false;
  };
  const Case cases[] = {{"attribute boxes", hsdf::RenderMethod::Cells, Tiles::Off, ThinBoxes::Off, false, true},
                        {"thin boxes fp16", hsdf::RenderMethod::Cells, Tiles::Off, ThinBoxes::On, true, true},
                        {"tiles", hsdf::RenderMethod::Cells, Tiles::On, ThinBoxes::Auto, false, false},
                        {"tiles fp16", hsdf::RenderMethod::Cells, Tiles::On, ThinBoxes::Auto, true, false},
                        {"runs", hsdf::RenderMethod::CellRuns, Tiles::Off, ThinBoxes::Auto, false, true},
                        {"bricks fp16", hsdf::RenderMethod::CellBricks, Tiles::Off, ThinBoxes::Auto, true, false},
                        {"certified boxes", hsdf::RenderMethod::Cells, Tiles::Off, ThinBoxes::Off, false, true, true},
                        {"certified tiles", hsdf::RenderMethod::Cells, Tiles::On, ThinBoxes::Auto, false, false, true}};
  struct Work {
    std::uint64_t fragments = 0, evaluations = 0;
  };
  const auto draw = [&](const render::CameraView& camera, bool proxies, Work& work) {
    feature->settings().proxyBoxes = proxies;
    render::FrameSettings settings;
    settings.countWork = true;
    const Frame frame = renderWith(camera, settings);
    work.fragments += prepassFragments(*renderer_);
    for (std::uint32_t count : renderer_->readbackWorkCounters()) work.evaluations += count;
    return frame;
  };
  const auto expectSame = [&](const render::CameraView& camera, const std::string& label, bool certified, Work& whole,
                              Work& proxy) {
    const Frame wholeFrame = draw(camera, false, whole);
    const Frame proxyFrame = draw(camera, true, proxy);
    const TileComparison c = compareTilesWithBoxes(wholeFrame, proxyFrame);
    std::printf("[ %s ] hits %d / %d, coverage differs %d, colour differs %d, depth rel max %.2e\n", label.c_str(),
                c.hitsBoxes, c.hitsTiles, c.coverageDiffers, c.colourDiffers, c.depthRelativeMax);
    EXPECT_GE(c.hitsBoxes, 200) << label;
    EXPECT_EQ(c.coverageDiffers, 0) << label;
    EXPECT_LE(c.colourDiffers, c.hitsBoxes / 500 + 2) << label;
    EXPECT_LT(c.depthRelativeMax, certified ? 3e-5 : 3e-4) << label;
    EXPECT_EQ(countIsolatedPixels(proxyFrame), countIsolatedPixels(wholeFrame)) << label << ": a speck of its own";
  };
  const auto torus = bakeAsset("torus", 16);
  ASSERT_NE(torus, nullptr);
  const std::optional<render::CameraView> inside = insideACellCamera(*torus);
  ASSERT_TRUE(inside);
  for (int k : {16, 64}) {
    const auto bunny = bakeAsset("bunny", k);
    ASSERT_NE(bunny, nullptr);
    for (const Case& c : cases) {
      feature->settings().tiles = c.tiles;
      feature->settings().thinBoxes = c.thin;
      Work whole, proxy;
      const auto add = [&](const std::shared_ptr<const hsdf::SdfAsset>& asset) {
        registry_ = ecs::Registry();
        auto& renderable = registry_.get<hsdf::HermiteSdfRenderable>(addSdf(registry_, asset, c.method));
        renderable.halfPrecision = c.half;
        renderable.certified = c.certified;
      };
      add(bunny);
      const std::string label = std::string(c.label) + ", bunny K=" + std::to_string(k);
      for (int view : {0, 3})
        expectSame(orbitCamera(*bunny, view), label + " view " + std::to_string(view), c.certified, whole, proxy);
      if (k == 16) {
        add(torus);
        expectSame(*inside, std::string(c.label) + ", inside a cell of the torus", c.certified, whole, proxy);
      }
      std::printf("[ %s ] prepass fragments %llu -> %llu, evaluations %llu -> %llu\n", label.c_str(),
                  static_cast<unsigned long long>(whole.fragments), static_cast<unsigned long long>(proxy.fragments),
                  static_cast<unsigned long long>(whole.evaluations), static_cast<unsigned long long>(proxy.evaluations));
      EXPECT_LT(proxy.evaluations, whole.evaluations) << label;
      if (c.boxes) {
        EXPECT_LT(proxy.fragments, whole.fragments) << label;
      }
    }
  }
}

// Why: inside a cell the near plane cuts the run's (brick's) front faces away; the back-face path
// (the near list) must find the surface in front of the eye, as the cells' does.
TEST_F(HermiteCellsTest, CellRunsAndBricksFromInsideACell) {
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("torus", 16);
  ASSERT_NE(asset, nullptr);
  const ecs::Entity entity = addSdf(registry_, asset, hsdf::RenderMethod::CellRuns);
  const std::optional<render::CameraView> inside = insideACellCamera(*asset);
  ASSERT_TRUE(inside);
  const render::CameraView close = *inside;
  expectMatchesReference(compareView(*asset, close, "runs inside a cell"));
  EXPECT_GT(renderer_->feature<hsdf::HermiteCellFeature>()->stats().nearCells, 0u);
  registry_.get<hsdf::HermiteSdfRenderable>(entity).method = hsdf::RenderMethod::CellBricks;
  expectMatchesReference(compareView(*asset, close, "bricks inside a cell"));
  EXPECT_GT(renderer_->feature<hsdf::HermiteCellFeature>()->stats().nearCells, 0u);
}

// Why: view regions call the feature's prepare once per region, and here each region draws the
// entity with another cell asset (K = 16 on the left, K = 24 on the right, as the split screen
// can). The second region's asset is new to the feature, whose rebuilt record buffers must not
// free the ones the first region's recorded draws read, nor drop the first asset (which would
// rebuild every frame). Each half must equal the frame drawn with its asset alone, over several
// frames, with no validation message.
TEST_F(HermiteCellsTest, TwoCellAssetsInTwoViewRegionsOfOneFrame) {
  createCellRenderer(kSize, kSize);
  const auto coarse = bakeAsset("torus", 16);
  const auto fine = bakeAsset("torus", 24);
  ASSERT_NE(coarse, nullptr);
  ASSERT_NE(fine, nullptr);
  const ecs::Entity entity = addSdf(registry_, coarse, hsdf::RenderMethod::Cells);
  const render::CameraView camera = orbitCamera(*coarse, 1);
  scene::updateWorldTransforms(registry_);
  auto single = [&](const std::shared_ptr<const hsdf::SdfAsset>& asset) {
    registry_.get<hsdf::HermiteSdfRenderable>(entity).asset = asset;
    return renderWith(camera, DEBUG_VIEW_NORMALS);
  };
  const Frame left = single(coarse), right = single(fine);
  const std::uint32_t half = kSize / 2;
  for (int frame = 0; frame < 3; ++frame) {
    SCOPED_TRACE("frame " + std::to_string(frame));
    render::FrameSettings settings;
    settings.debugView = DEBUG_VIEW_NORMALS;
    settings.regions.push_back({{{0, 0}, {half, kSize}}, [&] { registry_.get<hsdf::HermiteSdfRenderable>(entity).asset = coarse; }});
    settings.regions.push_back({{{int(half), 0}, {kSize - half, kSize}}, [&] { registry_.get<hsdf::HermiteSdfRenderable>(entity).asset = fine; }});
    renderer_->renderFrame(registry_, camera, settings);
    const std::vector<std::uint8_t> both = renderer_->readbackColor();
    int wrong = 0;
    for (std::uint32_t y = 0; y < kSize; ++y)
      for (std::uint32_t x = 0; x < kSize; ++x) {
        const std::size_t i = (std::size_t(y) * kSize + x) * 4;
        const Frame& expected = x < half ? left : right;
        if (!std::equal(both.begin() + long(i), both.begin() + long(i) + 4, expected.rgba.begin() + long(i))) ++wrong;
      }
    EXPECT_EQ(wrong, 0);
  }
  EXPECT_NE(left.rgba, right.rgba) << "the two assets must draw differently for the test to mean something";
}

// Why: SDF depth written through gl_FragDepth and mesh depth from the rasterizer meet in one
// depth buffer; the plane must cut the bunny exactly where the two surfaces cross.
TEST_F(HermiteCellsTest, MeshPlaneCutsSdfWhereTheReferenceSays) {
  createCellRenderer(kSize, kSize);
  const auto asset = bakeAsset("bunny", 32);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  const glm::vec3 center(asset->surfaceBounds.center());
  const float size = 3.0f * float(glm::length(asset->surfaceBounds.size()));
  // A horizontal quad through the bunny's middle (the fixture's quad faces +Z: rotate it to +Y).
  const ecs::Entity plane = addQuad(center, size, {0.3f, 0.3f, 0.9f, 1.0f});
  registry_.get<scene::Transform>(plane).rotation = glm::angleAxis(-1.5707963f, glm::vec3(1, 0, 0));
  scene::updateWorldTransforms(registry_);

  const render::CameraView camera = orbitCamera(*asset, 0, 2.2f);
  const Frame frame = renderWith(camera, DEBUG_VIEW_NONE);
  auto reference = hsdf::renderReference(asset->field, camera.view, camera.proj, {int(kSize), int(kSize)});
  ASSERT_TRUE(reference.ok());
  const glm::dvec3 forward = -glm::dvec3(glm::inverse(camera.view)[2]);
  int checked = 0, wrong = 0, sdfWins = 0, planeWins = 0;
  for (int y = 1; y + 1 < int(kSize); ++y) {
    for (int x = 1; x + 1 < int(kSize); ++x) {
      const math::Ray ray = math::pixelRay(camera.view, camera.proj, {float(x) + 0.5f, float(y) + 0.5f}, {int(kSize), int(kSize)});
      const double tPlane = (double(center.y) - ray.origin.y) / ray.direction.y;
      const glm::dvec3 p = ray.origin + tPlane * ray.direction;
      const double half = 0.5 * double(size);
      const bool planeHit = tPlane > 0.0 && std::abs(p.x - double(center.x)) < half && std::abs(p.z - double(center.z)) < half;
      const double planeDistance = planeHit ? tPlane * glm::dot(ray.direction, forward) : 0.0;
      const std::size_t i = reference->pixel(x, y);
      const bool sdfHit = reference->hit[i] != 0;
      if (!planeHit && !sdfHit) continue;
      bool silhouette = false;  // the SDF's own silhouette: coverage may differ there (see above)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) silhouette |= (reference->hit[reference->pixel(x + dx, y + dy)] != 0) != sdfHit;
      if (silhouette) continue;
      const double sdfDistance = sdfHit ? math::depthToViewDistance(reference->depth[i], camera.znear) : 0.0;
      // Skip the crossing line itself: pixels where the two surfaces are within 0.01 cells.
      if (planeHit && sdfHit && std::abs(planeDistance - sdfDistance) < 0.01 * asset->field.grid.spacing) continue;
      const bool planeInFront = planeHit && (!sdfHit || planeDistance < sdfDistance);
      const double planeDepth = planeHit ? math::viewDistanceToDepth(planeDistance, camera.znear) : 0.0;
      // The plane's depth comes straight from the rasterizer: the pixel shows the plane iff its
      // depth is nearer to the plane's than to the SDF's (or the background's). Not "equal to the
      // plane's within 1e-5": a GPU snaps the quad's vertices to its sub-pixel grid, which moves the
      // depth of a plane seen this obliquely by more than that (an H200 failed a third of the
      // pixels so, with every surface where it belonged).
      const double got = frame.depthAt(std::uint32_t(x), std::uint32_t(y));
      const double sdfDepth = sdfHit ? double(reference->depth[i]) : 0.0;
      const bool gpuShowsPlane = planeHit && std::abs(got - planeDepth) < std::abs(got - sdfDepth);
      ++checked;
      planeWins += planeInFront;
      sdfWins += !planeInFront;
      if (gpuShowsPlane != planeInFront) ++wrong;
    }
  }
  EXPECT_GT(planeWins, int(kSize * kSize) / 10);
  EXPECT_GT(sdfWins, 500);
  EXPECT_EQ(wrong, 0) << wrong << " of " << checked << " pixels show the wrong surface";
}

// Why: all instances share one pipeline and one multi-draw; per-instance transforms (rotation,
// scale, every third one mirrored: its boxes' winding flips per object inside the same draw) come
// from the GPU scene. One frame with 64 must equal 64 frames with one each.
TEST_F(HermiteCellsTest, SixtyFourInstancesInOneDrawMatchSeparateFrames) {
  constexpr std::uint32_t size = 128;
  createCellRenderer(size, size);
  const auto asset = bakeAsset("bunny", 16);
  ASSERT_NE(asset, nullptr);
  const glm::vec3 center(asset->surfaceBounds.center());
  const float extent = float(glm::length(asset->surfaceBounds.size()));
  std::vector<glm::mat4> transforms;
  for (int i = 0; i < 64; ++i) {
    const glm::vec3 offset(float(i % 8) - 3.5f, float(i / 8) - 3.5f, float((i * 5) % 7) * -0.3f);
    glm::mat4 m = glm::translate(glm::mat4(1.0f), offset * extent * 0.9f);
    m = glm::rotate(m, float(i) * 0.4f, glm::vec3(0, 1, 0));
    m = glm::scale(m, glm::vec3(i % 3 == 0 ? -1.0f : 1.0f, 1.0f, 1.0f) * (0.6f + 0.01f * float(i)));
    transforms.push_back(glm::translate(m, -center));
  }
  const render::CameraView camera =
      render::CameraView::lookAt(glm::vec3(0.0f, 0.0f, 9.0f * extent), glm::vec3(0.0f), 0.9f, 0.05f * extent, 1.0f);
  for (const glm::mat4& m : transforms) addSdf(registry_, asset, hsdf::RenderMethod::Cells, m);
  // With occlusion culling the instances hide each other's cells: the first frame (empty history)
  // and the third (the history of the same view) must both be the sum below. Boxes: occlusion
  // culling and the early depth stage are theirs (tiles: TiledCellsTest.TilesResolveOverlappingObjects).
  renderer_->feature<hsdf::HermiteCellFeature>()->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;
  renderer_->feature<hsdf::HermiteCellFeature>()->settings().cullOcclusion = true;
  const Frame first = renderWith(camera, DEBUG_VIEW_NONE);
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  const Frame all = renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_TRUE(first.depth == all.depth);
  const hsdf::HermiteCellFeature::Stats& stats = renderer_->feature<hsdf::HermiteCellFeature>()->stats();
  EXPECT_EQ(stats.objects, 64u);
  // Every command of an instance (its row ranges, phase 2's copies) shares the instance's one draw
  // record: a record per command made a million instances 4.9 GB of draw data.
  EXPECT_EQ(stats.nearCells, 0u);
  EXPECT_EQ(stats.drawRecords, 64u);
  EXPECT_GT(stats.draws, 4u * stats.drawRecords);
  // The instances overlap on screen: drawn by depth (early depth would let one object's nearer box
  // face hide another object's nearer hit), while each one alone is drawn by its faces below, so
  // the equality also checks the two prepasses against each other.
  EXPECT_FALSE(renderer_->feature<hsdf::HermiteCellFeature>()->stats().earlyDepth);

  std::vector<float> expected(std::size_t(size) * size, 0.0f);
  renderer_->feature<hsdf::HermiteCellFeature>()->settings().cullOcclusion = false;  // each alone: early depth
  for (const glm::mat4& m : transforms) {
    registry_.clear();
    addSdf(registry_, asset, hsdf::RenderMethod::Cells, m);
    const Frame one = renderWith(camera, DEBUG_VIEW_NONE);
    // Early depth is on (EarlyDepth::Auto) where fragments are shaded in order (lavapipe).
    EXPECT_EQ(renderer_->feature<hsdf::HermiteCellFeature>()->stats().earlyDepth,
              context_->capabilities().isSoftwareRasterizer);
    for (std::size_t i = 0; i < expected.size(); ++i) expected[i] = std::max(expected[i], one.depth[i]);
  }
  int covered = 0, different = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    covered += expected[i] > 0.0f;
    different += expected[i] != all.depth[i];
  }
  EXPECT_GT(covered, int(size * size) / 10);
  EXPECT_EQ(different, 0);
}


}  // namespace
}  // namespace gputest

namespace gputest {
namespace {

// Why: a game destroys objects and gives entities other assets; the cell buffers hold every
// uploaded asset, and were rebuilt only when a new one came, so a destroyed object's asset stayed,
// CPU and GPU, for good (found by a helper: 0.5 MB after 300 empty frames). Assets no entity draws
// for Settings::releaseAfterFrames frames go once they hold half of the records, or when nothing
// is drawn; not before (an object hidden for a moment is not uploaded again), and not a small one
// beside a larger one drawn (each removal would re-upload the rest).
TEST_F(HermiteCellsTest, AssetsNoEntityDrawsAreReleased) {
  createCellRenderer(64, 64);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  feature->settings().releaseAfterFrames = 4;
  std::shared_ptr<const hsdf::SdfAsset> big = bakeAsset("torus", 32);
  std::shared_ptr<const hsdf::SdfAsset> small = bakeAsset("sphere", 12);
  ASSERT_TRUE(big && small);
  ASSERT_GT(big->cells.records.size(), 2 * small->cells.records.size());
  const std::weak_ptr<const hsdf::SdfAsset> bigAlive = big, smallAlive = small;
  const render::CameraView camera = orbitCamera(*big, 0);
  const auto frames = [&](int count) {
    for (int i = 0; i < count; ++i) (void)renderWith(camera, DEBUG_VIEW_NONE);
  };
  const ecs::Entity bigEntity = addSdf(registry_, big, hsdf::RenderMethod::Cells);
  const ecs::Entity smallEntity = addSdf(registry_, small, hsdf::RenderMethod::CellRuns,
                                         glm::translate(glm::mat4(1.0f), glm::vec3(3.0f, 0.0f, 0.0f)));
  big.reset();
  small.reset();
  frames(2);
  const std::uint64_t both = feature->stats().gpuBytes;
  ASSERT_GT(both, 0u);

  ASSERT_TRUE(registry_.destroy(smallEntity));  // the smaller share: kept while the torus is drawn
  frames(10);
  EXPECT_FALSE(smallAlive.expired()) << "a small idle asset beside a larger drawn one is not worth a rebuild";
  EXPECT_EQ(feature->stats().gpuBytes, both);

  ASSERT_TRUE(registry_.destroy(bigEntity));  // nothing drawn
  frames(3);
  EXPECT_FALSE(bigAlive.expired()) << "released before releaseAfterFrames";
  frames(3);
  EXPECT_TRUE(bigAlive.expired()) << "the destroyed object's asset is still held";
  EXPECT_TRUE(smallAlive.expired());
  EXPECT_EQ(feature->stats().gpuBytes, 0u);

  // The scene drawn again from nothing: the same image as a renderer that never dropped anything.
  const auto torus = bakeAsset("torus", 32);
  addSdf(registry_, torus, hsdf::RenderMethod::Cells);
  const Frame again = renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_GT(std::count_if(again.depth.begin(), again.depth.end(), [](float d) { return d > 0.0f; }), 500);
}

// Why: a game streams its assets in, one every few frames, while the others draw. Each new asset
// must be uploaded once (every new asset re-uploaded every drawn one before: n assets streamed in
// cost O(n^2) bytes), land after the others in buffers that grow under the frames in flight, and
// be drawn from its own records, runs, bricks and cones at their new offsets: the frame must be
// the one drawn when the buffers are built with every asset at once. Cells, runs and bricks take
// turns, so every stream is appended to; the grids differ, so no offset can stand in for another.
TEST_F(HermiteCellsTest, StreamedAssetsAreUploadedOnceAndDrawnAsIfGivenAtOnce) {
  constexpr std::uint32_t size = 96;
  createCellRenderer(size, size);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  feature->settings().releaseAfterFrames = 2;
  const char* shapes[] = {"sphere", "torus", "box", "bunny", "torus", "sphere", "bunny", "box"};
  const hsdf::RenderMethod methods[] = {hsdf::RenderMethod::Cells, hsdf::RenderMethod::CellRuns,
                                        hsdf::RenderMethod::CellBricks};
  struct Object {
    std::shared_ptr<const hsdf::SdfAsset> asset;
    hsdf::RenderMethod method;
    glm::mat4 transform;
  };
  std::vector<Object> objects;
  for (int i = 0; i < 8; ++i) {
    auto asset = bakeAsset(shapes[i], 10 + 2 * i);
    ASSERT_NE(asset, nullptr);
    const glm::vec3 center(asset->surfaceBounds.center());
    const float scale = 3.0f / float(glm::length(asset->surfaceBounds.size()));
    glm::mat4 m = glm::translate(glm::mat4(1.0f), glm::vec3((float(i % 4) - 1.5f) * 1.9f, (float(i / 4) - 0.5f) * 1.9f, 0.0f));
    m = glm::rotate(m, 0.5f * float(i), glm::vec3(0.3f, 1.0f, 0.1f));
    objects.push_back({asset, methods[i % 3], glm::translate(glm::scale(m, glm::vec3(scale)), -center)});
  }
  const render::CameraView camera =
      render::CameraView::lookAt(glm::vec3(0.0f, 0.0f, 9.0f), glm::vec3(0.0f), 0.9f, 0.1f, 1.0f);

  for (const Object& o : objects) {  // one more asset each frame
    addSdf(registry_, o.asset, o.method, o.transform);
    (void)renderWith(camera, DEBUG_VIEW_NONE);
    const hsdf::HermiteCellFeature::Stats& stats = feature->stats();
    EXPECT_EQ(stats.uploadedBytes, stats.gpuBytes) << "the assets uploaded before were uploaded again";
    EXPECT_GE(stats.gpuBytesHeld, stats.gpuBytes);
  }
  (void)renderWith(camera, DEBUG_VIEW_NONE);  // the tiles' and streams' sizes settle
  const Frame streamed = renderWith(camera, DEBUG_VIEW_NONE);
  const std::uint64_t streamedBytes = feature->stats().gpuBytes;
  EXPECT_EQ(feature->stats().objects, 8u);

  registry_.clear();  // every buffer dropped, then all eight at once: one upload of everything
  for (int frame = 0; frame < 4; ++frame) (void)renderWith(camera, DEBUG_VIEW_NONE);
  ASSERT_EQ(feature->stats().gpuBytes, 0u);
  for (const Object& o : objects) addSdf(registry_, o.asset, o.method, o.transform);
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_EQ(feature->stats().gpuBytes, streamedBytes);
  EXPECT_EQ(feature->stats().gpuBytesHeld, feature->stats().gpuBytes) << "built at once: no room to spare";
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  const Frame atOnce = renderWith(camera, DEBUG_VIEW_NONE);
  const auto covered = std::count_if(atOnce.depth.begin(), atOnce.depth.end(), [](float d) { return d > 0.0f; });
  EXPECT_GT(covered, std::int64_t(size * size / 8));
  EXPECT_TRUE(streamed.depth == atOnce.depth);
  EXPECT_TRUE(streamed.rgba == atOnce.rgba);
}

// Why: a level streams chunks out and in at once: each frame one object goes and another comes
// with its own asset. The new asset must be all that is uploaded (a rebuild whenever an uploaded
// asset was no longer drawn re-uploaded every asset every frame: O(n) a frame), until the assets
// no longer drawn hold half of the records; and what is drawn must still be what buffers holding
// only the drawn assets draw.
TEST_F(HermiteCellsTest, StreamingOutAndInUploadsOnlyTheNewAsset) {
  constexpr std::uint32_t size = 96;
  createCellRenderer(size, size);
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  feature->settings().releaseAfterFrames = 1000;  // no timed release: the half rule alone
  const char* shapes[] = {"sphere", "torus", "box"};
  const auto place = [](const hsdf::SdfAsset& asset, int slot) {
    const glm::vec3 center(asset.surfaceBounds.center());
    const float scale = 3.0f / float(glm::length(asset.surfaceBounds.size()));
    const glm::mat4 m = glm::translate(glm::mat4(1.0f), glm::vec3((float(slot % 4) - 1.5f) * 1.9f,
                                                                  (float(slot / 4) - 0.5f) * 1.9f, 0.0f));
    return glm::translate(glm::scale(m, glm::vec3(scale)), -center);
  };
  const render::CameraView camera =
      render::CameraView::lookAt(glm::vec3(0.0f, 0.0f, 9.0f), glm::vec3(0.0f), 0.9f, 0.1f, 1.0f);
  std::vector<ecs::Entity> entities;
  for (int slot = 0; slot < 8; ++slot) {
    const auto asset = bakeAsset(shapes[slot % 3], 14);
    entities.push_back(addSdf(registry_, asset, hsdf::RenderMethod::Cells, place(*asset, slot)));
  }
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  for (int frame = 0; frame < 4; ++frame) {  // the oldest goes, a new one takes its place
    const int slot = frame;
    ASSERT_TRUE(registry_.destroy(entities[std::size_t(slot)]));
    const auto arriving = bakeAsset(shapes[(slot + 1) % 3], 15 + frame);
    entities[std::size_t(slot)] = addSdf(registry_, arriving, hsdf::RenderMethod::Cells, place(*arriving, slot));
    const std::uint64_t uploadedBefore = feature->stats().uploadedBytes, heldBefore = feature->stats().gpuBytes;
    (void)renderWith(camera, DEBUG_VIEW_NONE);
    const std::uint64_t uploaded = feature->stats().uploadedBytes - uploadedBefore;
    EXPECT_EQ(uploaded, feature->stats().gpuBytes - heldBefore) << "frame " << frame << ": more than the new asset";
    EXPECT_LT(uploaded, heldBefore / 4) << "frame " << frame;
  }
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  const Frame streamed = renderWith(camera, DEBUG_VIEW_NONE);

  // The same entities drawn from buffers that hold only their assets.
  std::vector<std::pair<std::shared_ptr<const hsdf::SdfAsset>, glm::mat4>> drawn;
  for (ecs::Entity entity : entities)
    drawn.emplace_back(registry_.get<hsdf::HermiteSdfRenderable>(entity).asset,
                       registry_.get<scene::WorldTransform>(entity).matrix);
  registry_.clear();
  feature->settings().releaseAfterFrames = 1;
  for (int frame = 0; frame < 4; ++frame) (void)renderWith(camera, DEBUG_VIEW_NONE);
  ASSERT_EQ(feature->stats().gpuBytes, 0u);
  for (const auto& [asset, matrix] : drawn) addSdf(registry_, asset, hsdf::RenderMethod::Cells, matrix);
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  const Frame fresh = renderWith(camera, DEBUG_VIEW_NONE);
  EXPECT_GT(std::count_if(fresh.depth.begin(), fresh.depth.end(), [](float d) { return d > 0.0f; }),
            std::int64_t(size * size / 10));
  EXPECT_TRUE(streamed.depth == fresh.depth);
  EXPECT_TRUE(streamed.rgba == fresh.rgba);
}

// Why: a field the GPU could not take (out of memory) is replaced by the one the entity drew
// before; the entities of another registry are other objects, with nothing to fall back to (the
// tracers drew another registry's field for the same entity id, found by a helper).
TEST_F(HermiteCellsTest, ARefusedAssetFallsBackOnlyToItsOwnEntitysField) {
  createCellRenderer(64, 64);
  const auto torus = bakeAsset("torus", 16);
  const auto big = bakeAsset("sphere", 48);
  ASSERT_TRUE(torus && big);
  const render::CameraView camera = orbitCamera(*torus, 0);
  const auto covered = [&](const ecs::Registry& registry, VkDeviceSize budget) {
    engine::gpu::Allocator& allocator = context_->allocator();
    if (budget != 0) allocator.setBudget(allocator.stats().usedBytes + budget);
    renderer_->renderFrame(registry, camera, {});
    allocator.setBudget(engine::gpu::Allocator::kUnlimited);  // before the read-back's staging buffers
    const std::vector<float> depth = renderer_->readbackDepth();
    return std::count_if(depth.begin(), depth.end(), [](float d) { return d > 0.0f; });
  };
  ecs::Registry registry;
  const ecs::Entity entity = addSdf(registry, torus, hsdf::RenderMethod::Cells);
  std::int64_t torusPixels = 0;
  for (int slot = 0; slot < 8; ++slot) torusPixels = covered(registry, 0);  // every frame slot's buffers made
  ASSERT_GT(torusPixels, 500);
  registry.get<hsdf::HermiteSdfRenderable>(entity).asset = big;
  EXPECT_EQ(covered(registry, 512 << 10), torusPixels) << "the torus it replaced is drawn";  // the sphere needs 1.3 MB
  ASSERT_TRUE(renderer_->feature<hsdf::HermiteCellFeature>()->refused(big->id));
  ecs::Registry other;
  ASSERT_EQ(addSdf(other, big, hsdf::RenderMethod::Cells), entity) << "the case needs the same entity id";
  EXPECT_EQ(covered(other, 512 << 10), 0) << "another registry's entity drew the torus of this one";
  (void)renderer_->takeDroppedObjects();
}

// Why: cells refused for GPU memory must be drawn once the memory is there, not be refused for
// good (a game's object refused in a full scene stayed invisible after others were destroyed,
// found by a helper), and not be tried, and reported, again every frame while nothing changed.
// Two ways memory comes: the budget raised, and another object destroyed (its asset's buffers
// dropped after Settings::releaseAfterFrames idle frames, then freed once its frames completed).
TEST_F(HermiteCellsTest, RefusedCellsAreDrawnOnceTheMemoryIsThere) {
  createCellRenderer(64, 64);
  const auto big = bakeAsset("sphere", 48);
  const auto held = bakeAsset("torus", 48);
  ASSERT_TRUE(big && held);
  const render::CameraView camera = orbitCamera(*big, 0);
  engine::gpu::Allocator& allocator = context_->allocator();
  auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
  feature->settings().releaseAfterFrames = 2;
  const auto frames = [&](const ecs::Registry& registry, int count) {
    for (int frame = 0; frame < count; ++frame) renderer_->renderFrame(registry, camera, {});
  };
  const auto depthCovered = [&] {
    const std::vector<float> depth = renderer_->readbackDepth();
    return std::count_if(depth.begin(), depth.end(), [](float d) { return d > 0.0f; });
  };
  ecs::Registry alone;
  addSdf(alone, big, hsdf::RenderMethod::Cells);
  frames(alone, 8);  // every frame slot's buffers made
  const std::int64_t bigPixels = depthCovered();
  ASSERT_GT(bigPixels, 500);
  const VkDeviceSize bigBytes = feature->stats().gpuBytes;
  alone.clear();
  frames(alone, 8);  // its buffers dropped and freed
  ASSERT_EQ(feature->stats().gpuBytes, 0u);

  // The budget: short of the rebuild with both objects (it holds the old buffers and the new ones,
  // the torus's records again with the sphere's), room for the sphere's once the torus's are gone.
  ecs::Registry registry;
  const ecs::Entity heldEntity = addSdf(registry, held, hsdf::RenderMethod::Cells,
                                        glm::translate(glm::mat4(1.0f), glm::vec3(1000.0f, 0.0f, 0.0f)));
  frames(registry, 8);
  const VkDeviceSize heldBytes = feature->stats().gpuBytes;
  ASSERT_GT(heldBytes, 0u);
  allocator.setBudget(allocator.stats().usedBytes + bigBytes + heldBytes / 2);
  (void)renderer_->takeDroppedObjects();
  addSdf(registry, big, hsdf::RenderMethod::Cells);
  frames(registry, 1);
  EXPECT_TRUE(feature->refused(big->id));
  EXPECT_EQ(renderer_->takeDroppedObjects().size(), 1u);
  frames(registry, 3);
  EXPECT_TRUE(renderer_->takeDroppedObjects().empty()) << "refused again with nothing changed";

  // The held object destroyed: its buffers go (idle, then freed), and the refused sphere is drawn.
  registry.destroy(heldEntity);
  frames(registry, 8);
  EXPECT_FALSE(feature->refused(big->id));
  allocator.setBudget(engine::gpu::Allocator::kUnlimited);  // before the read-back's staging buffers
  EXPECT_EQ(depthCovered(), bigPixels);
  EXPECT_TRUE(renderer_->takeDroppedObjects().empty()) << "drawn without another refusal";

  // Refused again under a budget, then the budget raised: drawn.
  registry.clear();
  frames(registry, 8);
  allocator.setBudget(allocator.stats().usedBytes + 4096);
  addSdf(registry, big, hsdf::RenderMethod::Cells);
  frames(registry, 2);
  EXPECT_TRUE(feature->refused(big->id));
  allocator.setBudget(engine::gpu::Allocator::kUnlimited);
  frames(registry, 1);
  EXPECT_FALSE(feature->refused(big->id));
  EXPECT_EQ(depthCovered(), bigPixels);
  (void)renderer_->takeDroppedObjects();
}

// Why: the debug views are how a user inspects the method; each must show what it claims:
// cells in distinct colours, an evaluation heat map that varies, and the boxes' edges.
TEST_F(HermiteCellsTest, DebugViewsShowCellsEvaluationsAndBoxes) {
  constexpr std::uint32_t size = 128;
  createCellRenderer(size, size);
  const auto asset = bakeAsset("bunny", 16);
  ASSERT_NE(asset, nullptr);
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  const render::CameraView camera = orbitCamera(*asset, 0);
  const Frame shaded = renderWith(camera, DEBUG_VIEW_NONE);
  auto colours = [&](const Frame& frame) {
    std::set<std::uint32_t> distinct;
    int changed = 0;
    for (std::size_t i = 0; i < frame.depth.size(); ++i) {
      if (shaded.depth[i] == 0.0f) continue;
      const std::uint8_t* c = &frame.rgba[i * 4];
      distinct.insert(std::uint32_t(c[0]) << 16 | std::uint32_t(c[1]) << 8 | c[2]);
      changed += std::memcmp(c, &shaded.rgba[i * 4], 3) != 0;
    }
    return std::pair<std::size_t, int>(distinct.size(), changed);
  };
  const auto [cellColours, cellChanged] = colours(renderWith(camera, DEBUG_VIEW_CELLS));
  EXPECT_GT(cellColours, 50u) << "each visible cell gets its own colour";
  EXPECT_GT(cellChanged, 1000);
  const auto [heatColours, heatChanged] = colours(renderWith(camera, DEBUG_VIEW_EVALS));
  EXPECT_GT(heatColours, 5u) << "the heat map varies with the work per pixel";
  EXPECT_GT(heatChanged, 1000);

  // The boxes drawn, by every cell method: the runs' and the bricks' boxes (their wireframe drew
  // nothing: only the cell batches had line copies, found by a helper), the bricks with culling on,
  // whose commands start with no instance.
  for (const hsdf::RenderMethod method :
       {hsdf::RenderMethod::Cells, hsdf::RenderMethod::CellRuns, hsdf::RenderMethod::CellBricks}) {
    SCOPED_TRACE(hsdf::renderMethodName(method));
    registry_.clear();
    addSdf(registry_, asset, method);
    const Frame methodShaded = renderWith(camera, DEBUG_VIEW_NONE);
    const Frame wire = renderWith(camera, DEBUG_VIEW_WIREFRAME);
    EXPECT_GT(wireEdgePixels(wire, methodShaded), 200) << "box edges drawn over the surface";
    EXPECT_EQ(wire.depth, methodShaded.depth) << "debug views do not change depth";
  }
}

// Why: a mirroring model matrix reverses the winding of the cell boxes on screen, so a fixed
// cull mode keeps the back faces, whose conservative depth search starts behind the surface
// (the object vanishes); non-uniform scale and shear make the object-space ray, the world depth
// and the inverse-transpose normal differ from what a rigid transform gives. The asymmetric bunny
// shows a mirror that was not applied.
TEST_F(HermiteCellsTest, MirroredScaledAndShearedObjectsMatchReference) {
  constexpr std::uint32_t size = 128;
  createCellRenderer(size, size);
  const auto asset = bakeAsset("bunny", 24);
  ASSERT_NE(asset, nullptr);
  for (const NamedTransform& transform : userTransforms(glm::vec3(asset->surfaceBounds.center()))) {
    registry_.clear();
    addSdf(registry_, asset, hsdf::RenderMethod::Cells, transform.matrix());
    for (int view = 0; view < 2; ++view) {
      SCOPED_TRACE(transform.label + ", view " + std::to_string(view));
      const ImageComparison c = compareView(*asset, orbitAround(worldSphere(*asset, transform.matrix()), view),
                                            transform.label.c_str(), transform.matrix());
      expectMatchesReference(c, int(size * size), 1000);
      EXPECT_LT(c.normalFlips, c.referenceHits / 100) << "normals of a mirrored object must still point out of it";
    }
  }
}

// Why: close to the surface of a non-uniformly scaled object, the near plane's reach must be
// measured in the object's units along its most shrunk axis, or the cell it cuts is drawn only by
// its clipped front faces and its surface is lost; the eye's own cell holds surface in front of it.
TEST_F(HermiteCellsTest, CameraInsideACellOfANonUniformlyScaledObject) {
  constexpr std::uint32_t size = 128;
  createCellRenderer(size, size);
  const auto asset = bakeAsset("torus", 16);
  ASSERT_NE(asset, nullptr);
  const glm::vec3 center(asset->surfaceBounds.center());
  const glm::mat4 model = userTransforms(center)[1].matrix();
  addSdf(registry_, asset, hsdf::RenderMethod::Cells, model);
  // In object space: from the torus hole towards the inner ring, a third of a cell before the
  // surface; placed in the world by the model.
  const double h = asset->field.grid.spacing;
  const glm::dvec3 hole = glm::dvec3(center) + glm::dvec3(0.0, 0.05, 0.0);
  auto hit = hsdf::castRay(asset->field, {hole, glm::dvec3(1.0, 0.0, 0.0)});
  ASSERT_TRUE(hit.ok() && hit->has_value());
  const glm::dvec3 eyeObject = (*hit)->position - glm::dvec3(0.3 * h, 0.0, 0.0);
  const glm::dvec3 targetObject = (*hit)->position + glm::dvec3(0.0, 0.3 * h, 0.0);
  const glm::vec3 eye(model * glm::vec4(glm::vec3(eyeObject), 1.0f));
  const glm::vec3 target(model * glm::vec4(glm::vec3(targetObject), 1.0f));
  const render::CameraView camera = render::CameraView::lookAt(eye, target, 1.2f, 0.1f * float(h), 1.0f);
  const ImageComparison c = compareView(*asset, camera, "inside a scaled cell", model);
  expectMatchesReference(c, int(size * size));
  EXPECT_GT(renderer_->feature<hsdf::HermiteCellFeature>()->stats().nearCells, 0u);
}

// Why: 1-pixel and 7-pixel wide viewports, 10 and 150 degree fields of view and an object a few
// pixels wide push the projection, the near-plane reach and the viewport maths to their ends; each
// must render without a validation message and cover the pixels the reference covers.
TEST_F(HermiteCellsTest, ExtremeCamerasAndViewports) {
  const auto asset = bakeAsset("bunny", 16);
  ASSERT_NE(asset, nullptr);
  const glm::mat4 model = userTransforms(glm::vec3(asset->surfaceBounds.center()))[2].matrix();  // mirror, shear
  const WorldSphere sphere = worldSphere(*asset, model);
  for (const CameraSetup& setup : extremeCameras(sphere.center, sphere.radius)) {
    SCOPED_TRACE(setup.label);
    createCellRenderer(setup.size.x, setup.size.y);
    registry_.clear();
    addSdf(registry_, asset, hsdf::RenderMethod::Cells, model);
    const ImageComparison c = compareView(*asset, setup.camera, setup.label.c_str(), model);
    EXPECT_GT(c.referenceHits, 0);
    // Coverage may differ only on the silhouette (no interior holes or extras) and there rarely.
    // The bound is relative to the pixels covered: in a 7-pixel wide image most covered pixels
    // are near a silhouette, so 0.1% of all pixels (the bound of the square views) would be
    // stricter there than anywhere else.
    EXPECT_LE(c.disagreements, std::max(int(0.001 * double(setup.size.x * setup.size.y)), c.referenceHits / 100));
    EXPECT_EQ(c.interiorHoles, 0);
    EXPECT_EQ(c.interiorExtras, 0);
    EXPECT_LT(c.interiorDepthErrorP99, 1e-3);
    // With few hits the 99th percentile is the largest error, at a grazing silhouette pixel.
    if (c.referenceHits >= 500) {
      EXPECT_LT(c.depthErrorP99, 1e-2);
    }
  }
}

// Why: a node scaled to zero (a common way to hide an animated object) or a NaN from a broken
// animation has no inverse: rays and normals would be NaN, and the near-cell search would run on a
// NaN eye. Cells and meshes must skip such objects (counted) and still draw the rest.
TEST_F(HermiteCellsTest, ObjectsWithoutAnInverseAreSkipped) {
  createCellRenderer(64, 64);
  const auto asset = bakeAsset("sphere", 8);
  ASSERT_NE(asset, nullptr);
  // Local transforms, resolved into world matrices by the hierarchy pass as in an application.
  const ecs::Entity zero = addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  registry_.get<scene::Transform>(zero).scale = glm::vec3(0.0f);
  const ecs::Entity broken = addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  registry_.get<scene::Transform>(broken).translation.x = std::numeric_limits<float>::quiet_NaN();
  addSdf(registry_, asset, hsdf::RenderMethod::Cells);
  const ecs::Entity hidden = addQuad(glm::vec3(0.0f), 1.0f, {0.0f, 0.0f, 1.0f, 1.0f});
  registry_.get<scene::Transform>(hidden).scale = glm::vec3(0.0f);
  const Frame frame = render(render::CameraView::lookAt({0.0f, 0.0f, 4.0f}, glm::vec3(0.0f), 0.9f, 0.01f, 1.0f));
  const auto& stats = renderer_->feature<hsdf::HermiteCellFeature>()->stats();
  EXPECT_EQ(stats.objects, 1u);
  EXPECT_EQ(stats.skippedObjects, 2u);
  EXPECT_EQ(renderer_->feature<render::MeshFeature>()->drawnLastFrame(), 0u);
  EXPECT_GT(std::count_if(frame.depth.begin(), frame.depth.end(), [](float d) { return d > 0.0f; }), 500);
}

// Why: the split screen draws one entity with a different asset in each view region, and here
// both change every frame (an animation by asset on either side): the second region's prepare
// appends its new asset's cells to the feature's buffers, replacing buffers that the first region
// has just recorded draws with in this very frame, and the first region's prepare (releaseAfterFrames
// at 1) drops the asset no longer drawn and rebuilds them, while two frames are in flight. Every
// replaced buffer must wait in the frame's release list (FrameContext::retire): destroyed at once,
// the frame's own command buffer holds a destroyed buffer (a validation message at its submit).
// The list must stay bounded (no buffer kept for good), and the last asset must be drawn as the
// reference draws it.
TEST_F(HermiteCellsTest, AssetSwappedEveryFrameWithFramesInFlightDrawsTheLastOne) {
  createCellRenderer(kSize, kSize);
  renderer_->feature<hsdf::HermiteCellFeature>()->settings().releaseAfterFrames = 1;
  const std::vector<std::shared_ptr<const hsdf::SdfAsset>> assets = {bakeAsset("torus", 10), bakeAsset("sphere", 8),
                                                                    bakeAsset("box", 9)};
  for (const auto& asset : assets) ASSERT_NE(asset, nullptr);
  const ecs::Entity entity = addSdf(registry_, assets[0], hsdf::RenderMethod::Cells);
  const render::CameraView camera = orbitCamera(*assets[0], 0);
  scene::updateWorldTransforms(registry_);
  auto showing = [&](std::size_t index) {
    return [&, index] { registry_.get<hsdf::HermiteSdfRenderable>(entity).asset = assets[index % assets.size()]; };
  };
  constexpr std::size_t kFrames = 13;
  std::size_t mostPending = 0;
  for (std::size_t f = 0; f < kFrames; ++f) {
    engine::render::FrameSettings split;
    split.regions = {{{{0, 0}, {kSize / 2, kSize}}, showing(f)},
                     {{{kSize / 2, 0}, {kSize / 2, kSize}}, showing(f + 1)}};
    ASSERT_TRUE(renderer_->renderFrame(registry_, camera, split));
    if (f >= 3) mostPending = std::max(mostPending, renderer_->pendingReleases());
  }
  std::printf("[ swaps ] most objects waiting for their frames: %zu\n", mostPending);
  EXPECT_GT(mostPending, 0u) << "the swaps retired nothing: the case does not reach the release path";
  EXPECT_LE(mostPending, 24u) << "retired buffers pile up instead of going when their frames complete";
  showing(kFrames)();
  expectMatchesReference(compareView(*assets[kFrames % assets.size()], camera, "last swap"));
}

}  // namespace
}  // namespace gputest
