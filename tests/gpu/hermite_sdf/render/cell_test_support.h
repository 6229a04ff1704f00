#pragma once
// The cell renderer's GPU tests share this: a fixture that draws with the cell feature alone and
// compares frames with the CPU reference, cameras around and inside the test shapes, and the
// comparison of tiles with the boxes they replace (hermite_cells_test.cpp, cell_tiler_test.cpp,
// cell_culling_test.cpp).
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "hermite_sdf/render/cell_feature.h"
#include "hermite_test_support.h"
#include "shared/host_device.h"

namespace gputest {

inline constexpr std::uint32_t kSize = 256;

// With HSDF_TEST_DUMP=folder: the GPU normals, the reference normals and a map of disagreements
// (red: reference hit only, blue: GPU hit only) as PNGs, for looking at a failure.
void dumpImages(const std::string& folder, const char* label, const Frame& normals, const hsdf::ReferenceImage& reference);

class HermiteCellsTest : public HermiteGpuTest {
 protected:
  void createCellRenderer(std::uint32_t width, std::uint32_t height) {
    createRenderer(width, height);
    // The cell feature alone: the feature under test, without the tracers' pipelines.
    const engine::Status added = renderer_->addFeature(std::make_unique<hsdf::HermiteCellFeature>());
    ASSERT_TRUE(added.ok()) << added.error().message;
  }

  // A cell renderer that culls boxes by occlusion (tiles turn occlusion culling off); its feature.
  hsdf::HermiteCellFeature* createOcclusionCullingRenderer(std::uint32_t width, std::uint32_t height) {
    createCellRenderer(width, height);
    auto* feature = renderer_->feature<hsdf::HermiteCellFeature>();
    feature->settings().tiles = hsdf::HermiteCellFeature::Tiles::Off;
    feature->settings().cullOcclusion = true;
    return feature;
  }

  // Renders `asset` placed by `model` from `camera` and compares with the reference; returns the
  // comparison. The image size is the renderer's.
  ImageComparison compareView(const hsdf::SdfAsset& asset, const engine::render::CameraView& camera, const char* label,
                              const glm::mat4& model = glm::mat4(1.0f)) {
    const auto start = std::chrono::steady_clock::now();
    const Frame shaded = renderWith(camera, DEBUG_VIEW_NONE);
    const Frame normals = renderWith(camera, DEBUG_VIEW_NORMALS);
    const auto rendered = std::chrono::steady_clock::now();
    hsdf::RenderOptions options;
    options.model = model;
    auto reference = hsdf::renderReference(asset.field, camera.view, camera.proj,
                                           {int(shaded.width), int(shaded.height)}, nullptr, options);
    EXPECT_TRUE(reference.ok()) << reference.error().message;
    if (!reference) return {};
    const auto referenced = std::chrono::steady_clock::now();
    std::printf("[ %s ] gpu %.2f s, reference %.2f s\n", label, std::chrono::duration<double>(rendered - start).count(),
                std::chrono::duration<double>(referenced - rendered).count());
    if (const char* dump = std::getenv("HSDF_TEST_DUMP")) dumpImages(dump, label, normals, *reference);
    const ImageComparison c =
        compareWithReference(shaded, &normals.rgba, *reference, camera, asset.field.grid.spacing, model);
    std::printf("[ %s ] hits ref %d gpu %d, disagree %d (%.4f%%), holes %d, extras %d, depth err p50 %.1e p90 %.1e p99 %.1e (interior %.1e) max %.1e cells, "
                "normal err p99 %.3f deg, flipped %d\n",
                label, c.referenceHits, c.gpuHits, c.disagreements, 100.0 * (1.0 - c.agreement(pixels(shaded))),
                c.interiorHoles, c.interiorExtras, c.depthErrorP50, c.depthErrorP90, c.depthErrorP99, c.interiorDepthErrorP99, c.depthErrorMax, c.normalErrorP99Degrees,
                c.normalFlips);
    return c;
  }

  // `asset` alone in a new registry, drawn by `method` from `camera` and compared with `reference`,
  // the CPU reference of `referenceCamera` (the same pixel rays, placed otherwise); prints a line.
  // `normalsOut`, if given, receives the DEBUG_VIEW_NORMALS frame.
  ImageComparison compareAlone(const std::shared_ptr<const hsdf::SdfAsset>& asset, hsdf::RenderMethod method,
                               const engine::render::CameraView& camera, const hsdf::ReferenceImage& reference,
                               const engine::render::CameraView& referenceCamera, const std::string& label,
                               Frame* normalsOut = nullptr) {
    registry_ = engine::ecs::Registry();
    addSdf(registry_, asset, method);
    const Frame shaded = renderWith(camera, DEBUG_VIEW_NONE);
    Frame normals = renderWith(camera, DEBUG_VIEW_NORMALS);
    const ImageComparison c = compareWithReference(shaded, &normals.rgba, reference, referenceCamera, asset->field.grid.spacing);
    std::printf("[ %s ] hits ref %d gpu %d, disagree %d, holes %d, extras %d, normal err p99 %.2f deg, flipped %d\n",
                label.c_str(), c.referenceHits, c.gpuHits, c.disagreements, c.interiorHoles, c.interiorExtras,
                c.normalErrorP99Degrees, c.normalFlips);
    if (normalsOut) *normalsOut = std::move(normals);
    return c;
  }

  static int pixels(const Frame& frame) { return int(frame.width * frame.height); }
};

// One of six views around the asset (above and below), `distanceScale` bounding radii away.
engine::render::CameraView orbitCamera(const hsdf::SdfAsset& asset, int view, float distanceScale = 1.9f);

// The torus's hole (inside the grid bounds, outside the surface) and a point of its inner ring.
glm::vec3 torusHole(const hsdf::SdfAsset& torus);
glm::vec3 torusRing(const hsdf::SdfAsset& torus);

// Half a cell in front of the torus's inner ring, seen from the hole, with a near plane of a
// quarter cell: the eye's own cell holds surface in front of it and the near plane cuts cells,
// which only the back-face (near) path can draw. Empty if the ray from the hole meets no ring.
std::optional<engine::render::CameraView> insideACellCamera(const hsdf::SdfAsset& torus);
// An eye 2^-14 cells (a quarter of the least proxy dilation) outside the +x face of a kept cell
// whose proxy box reaches that face, whose +x neighbour is not kept and whose surface the ray
// back along -x meets within the cell; it looks along -x with a near plane of 1e-6 cells.
std::optional<engine::render::CameraView> justOutsideAKeptCellCamera(const hsdf::SdfAsset& asset);

// `minHits`: enough surface in view for the statistics to mean something.
void expectMatchesReference(const ImageComparison& c, int pixels = int(kSize * kSize), int minHits = 500);

// The depth prepass's fragment-shader invocations in the last frame (pipeline statistics).
std::uint64_t prepassFragments(const engine::render::Renderer& renderer);

// Tiled cells against the boxes they replace: the same cells and the same search, one fragment per
// pixel and tile instead of one per box. The images may differ only where two cells' roots tie
// (which visibility id wins) and in the last bits of depth (the ray is rebuilt from the tile's depth
// instead of the box face's), never in coverage.
struct TileComparison {
  int hitsBoxes = 0, hitsTiles = 0;
  int coverageDiffers = 0;  // a hit in one image, none in the other
  int colourDiffers = 0;    // some channel more than 8 levels apart
  double depthRelativeMax = 0.0;
};

TileComparison compareTilesWithBoxes(const Frame& boxes, const Frame& tiles);

}  // namespace gputest
