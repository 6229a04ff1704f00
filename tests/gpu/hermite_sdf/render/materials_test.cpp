// Multi-material SDF objects (hermite_sdf/core/materials.h) drawn by every cell method and both
// sphere tracers: a box whose upper part is red and lower part blue shows red above the split and
// blue below it, and every pixel takes the colour of the grid sample nearest to its hit, the one
// shading rule of every method.
#include <cmath>
#include <cstdio>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "hermite_sdf/core/bake_job.h"
#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/render/features.h"
#include "hermite_sdf/render/sphere_trace_feature.h"
#include "hermite_test_support.h"
#include "shared/host_device.h"
#include "two_material_box.h"

namespace gputest {
namespace {

using namespace engine;

constexpr std::uint32_t kImage = 160;

std::shared_ptr<const hsdf::SdfAsset> bakeBox(bool twoMaterials, int resolution) {
  auto source = hsdf::BakeSource::fromScene("two_material_box", hsdftest::twoMaterialBoxScene(twoMaterials));
  EXPECT_TRUE(source) << source.error().message;
  if (!source) return nullptr;
  hsdf::BakeSettings settings;
  settings.resolution = resolution;
  auto asset = hsdf::bakeAsset(*source, settings);
  EXPECT_TRUE(asset) << asset.error().message;
  return asset ? *asset : nullptr;
}

// Which palette colour a shaded pixel shows: red (slot 0) or blue (slot 1), by its dominant
// channel (a specular highlight whitens a red pixel to (255, 137, 126), the shadowed side darkens
// it: the ratio, not a margin, tells them); -1 for a pixel neither clearly is.
int slotShown(glm::u8vec4 pixel) {
  const double r = pixel.r, b = pixel.b;
  if (r > 1.3 * b + 4.0) return 0;
  if (b > 1.3 * r + 4.0) return 1;
  return -1;
}

// The object-space hit of a pixel, rebuilt from its depth as the shading passes do.
glm::dvec3 hitOf(const Frame& frame, const render::CameraView& camera, std::uint32_t x, std::uint32_t y) {
  const glm::dvec2 ndc = (glm::dvec2(x, y) + 0.5) / glm::dvec2(frame.width, frame.height) * 2.0 - 1.0;
  const glm::dvec4 p = glm::inverse(glm::dmat4(camera.proj) * glm::dmat4(camera.view)) *
                       glm::dvec4(ndc, double(frame.depthAt(x, y)), 1.0);
  return glm::dvec3(p) / p.w;
}

// Distance to the box's surface (the mesh), to check that the rebuilt hits are hits.
double boxDistance(const glm::dvec3& p) {
  const glm::dvec3 q = glm::abs(p) - glm::dvec3(hsdftest::kBoxHalf);
  return glm::length(glm::max(q, 0.0)) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0);
}

struct SlotCheck {
  int hits = 0;
  int farFromSplit = 0, wrongSide = 0;      // pixels more than a cell from the split: the analytic split
  int nearestChecked = 0, wrongNearest = 0;  // pixels not within 2 % of a cell of a rounding tie
  int offSurface = 0;                        // rebuilt hits farther than a cell from the box
};

// Every hit pixel against (1) the analytic split, where the nearest sample cannot lie across it,
// and (2) the slot the asset's dense field holds at the sample nearest to the hit (the shading
// rule), away from ties of the rounding.
SlotCheck checkSlots(const Frame& frame, const render::CameraView& camera, const hsdf::SdfAsset& asset) {
  SlotCheck c;
  const hsdf::GridSpec& grid = asset.field.grid;
  for (std::uint32_t y = 0; y < frame.height; ++y)
    for (std::uint32_t x = 0; x < frame.width; ++x) {
      if (frame.depthAt(x, y) == 0.0f) continue;
      ++c.hits;
      const glm::dvec3 p = hitOf(frame, camera, x, y);
      if (std::abs(boxDistance(p)) > grid.spacing) ++c.offSurface;
      const int shown = slotShown(frame.pixel(x, y));
      if (std::abs(p.y - double(hsdftest::kSplitY)) > grid.spacing) {
        ++c.farFromSplit;
        c.wrongSide += shown != (p.y > double(hsdftest::kSplitY) ? 0 : 1);
        if (shown != (p.y > double(hsdftest::kSplitY) ? 0 : 1) && c.wrongSide < 4)
          std::printf("wrong side: pixel (%u, %u) rgb %d %d %d at (%.3f, %.3f, %.3f)\n", x, y, frame.pixel(x, y).r,
                      frame.pixel(x, y).g, frame.pixel(x, y).b, p.x, p.y, p.z);
      }
      const glm::dvec3 g = (p - grid.origin) / grid.spacing;
      const glm::dvec3 fraction = g - glm::floor(g);
      if (glm::any(glm::lessThan(glm::abs(fraction - 0.5), glm::dvec3(0.02)))) continue;
      const glm::ivec3 s = glm::clamp(glm::ivec3(glm::floor(g + 0.5)), glm::ivec3(0), glm::ivec3(grid.resolution - 1));
      ++c.nearestChecked;
      c.wrongNearest += shown != int(asset.field.materials[grid.sampleIndex(s.x, s.y, s.z)]);
    }
  return c;
}

struct MethodCase {
  const char* label;
  hsdf::RenderMethod method;
  hsdf::HermiteCellFeature::Tiles tiles = hsdf::HermiteCellFeature::Tiles::Off;
};

const MethodCase kMethods[] = {
    {"cells (boxes)", hsdf::RenderMethod::Cells, hsdf::HermiteCellFeature::Tiles::Off},
    {"cells (tiles)", hsdf::RenderMethod::Cells, hsdf::HermiteCellFeature::Tiles::On},
    {"cell runs", hsdf::RenderMethod::CellRuns},
    {"cell bricks", hsdf::RenderMethod::CellBricks},
    {"trilinear tracer", hsdf::RenderMethod::TrilinearSphereTrace},
    {"hermite tracer", hsdf::RenderMethod::HermiteSphereTrace},
};

class MaterialsGpuTest : public GpuTest {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    createRenderer(kImage, kImage);
    ASSERT_TRUE(hsdf::addRenderFeatures(*renderer_).ok());
  }

  Frame draw(const std::shared_ptr<const hsdf::SdfAsset>& asset, const MethodCase& m, const render::CameraView& camera,
             const glm::vec4& color) {
    if (registry_.valid(drawn_)) registry_.destroy(drawn_);  // one object at a time
    renderer_->feature<hsdf::HermiteCellFeature>()->settings().tiles = m.tiles;
    drawn_ = addSdf(registry_, asset, m.method);
    registry_.get<hsdf::HermiteSdfRenderable>(drawn_).color = color;
    return renderWith(camera, DEBUG_VIEW_NONE);
  }

  ecs::Entity drawn_{};
};

// Tricky: the cell methods find the record of the hit through the visibility buffer and the
// tracers the sample through the grid position; the first must index the asset's slots relative to
// its first record in the shared record buffer and pick the corner by the hit's cell-local position,
// the second must round the grid position to the nearest sample. Always slot 0, the farthest
// corner, a palette not uploaded or a slot array off by an asset all show as wrong pixels: the
// split crosses cells (K = 28, the split at y = 0.1 lies between sample planes), so within a cell
// of it the nearest corner and the other corners disagree. Two views see the top, front and side
// faces, and the bottom. A box of one material, drawn throughout far out of view, is uploaded
// first, so that the two-material asset's records do not start at record 0 of the shared buffers.
TEST_F(MaterialsGpuTest, EveryMethodShadesEachHitWithItsNearestSamplesMaterial) {
  const auto asset = bakeBox(true, 28);
  const auto other = bakeBox(false, 20);
  ASSERT_TRUE(asset && other);
  ASSERT_EQ(asset->palette.size(), 2u);
  for (const hsdf::RenderMethod method : {hsdf::RenderMethod::Cells, hsdf::RenderMethod::CellRuns,
                                          hsdf::RenderMethod::CellBricks})
    (void)addSdf(registry_, other, method, glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 50.0f)));
  const render::CameraView views[] = {
      render::CameraView::lookAt(glm::vec3(2.2f, 1.6f, 2.6f), glm::vec3(0.0f), 0.9f, 0.1f, 1.0f),
      render::CameraView::lookAt(glm::vec3(-2.4f, -1.7f, 2.0f), glm::vec3(0.0f), 0.9f, 0.1f, 1.0f),
  };
  for (const MethodCase& m : kMethods)
    for (int v = 0; v < 2; ++v) {
      const Frame frame = draw(asset, m, views[v], glm::vec4(1.0f));
      const SlotCheck c = checkSlots(frame, views[v], *asset);
      std::printf("[ %s, view %d ] %d hits: %d far from the split (%d on the wrong side), %d checked against the "
                  "nearest sample (%d wrong), %d off the surface\n",
                  m.label, v, c.hits, c.farFromSplit, c.wrongSide, c.nearestChecked, c.wrongNearest, c.offSurface);
      EXPECT_GT(c.hits, 4000) << m.label;
      EXPECT_LT(c.offSurface, c.hits / 100) << m.label << ": the hits rebuilt from depth are not on the box";
      EXPECT_GT(c.farFromSplit, c.hits / 2) << m.label;
      EXPECT_EQ(c.wrongSide, 0) << m.label << ", view " << v;
      EXPECT_GT(c.nearestChecked, c.hits / 2) << m.label;
      // A hit on a cell face may take either cell's record; both name the same nearest sample, so
      // only rounding of the depth-rebuilt position (filtered above) could move it.
      EXPECT_LE(c.wrongNearest, c.nearestChecked / 1000) << m.label << ", view " << v;
    }
}

// The entity's colour multiplies the palette's: a green entity colour leaves neither red nor blue
// (both palette colours have little green), and white shows them as authored. A single-material
// asset keeps the entity's own colour (no palette: the shading of before).
TEST_F(MaterialsGpuTest, EntityColourTintsThePaletteAndSingleMaterialKeepsItsColour) {
  const auto multi = bakeBox(true, 20);
  const auto single = bakeBox(false, 20);
  ASSERT_TRUE(multi && single);
  EXPECT_TRUE(single->palette.empty());
  const render::CameraView camera = render::CameraView::lookAt(glm::vec3(2.2f, 1.6f, 2.6f), glm::vec3(0.0f), 0.9f, 0.1f, 1.0f);
  for (const MethodCase& m : {kMethods[0], kMethods[5]}) {
    const Frame tinted = draw(multi, m, camera, glm::vec4(0.0f, 1.0f, 0.0f, 1.0f));
    const Frame white = draw(multi, m, camera, glm::vec4(1.0f));
    const Frame own = draw(single, m, camera, glm::vec4(0.2f, 0.9f, 0.3f, 1.0f));
    int greenest = 0, hits = 0, ownGreen = 0;
    for (std::uint32_t y = 0; y < kImage; ++y)
      for (std::uint32_t x = 0; x < kImage; ++x) {
        if (tinted.depthAt(x, y) == 0.0f) continue;
        ++hits;
        const glm::u8vec4 t = tinted.pixel(x, y), w = white.pixel(x, y), o = own.pixel(x, y);
        // Tinted green, the palette's red and blue shrink to their small green parts: darker than white.
        greenest += int(t.r) + int(t.b) < int(w.r) + int(w.b);
        ownGreen += o.g > o.r && o.g > o.b;
      }
    std::printf("[ %s ] %d hits, %d darker when tinted, %d green in the single-material colour\n", m.label, hits,
                greenest, ownGreen);
    EXPECT_GT(hits, 4000) << m.label;
    EXPECT_GT(greenest, hits * 99 / 100) << m.label;
    EXPECT_GT(ownGreen, hits * 99 / 100) << m.label;
  }
}

// Tricky: the palette and slots are the asset's, not a method's: the trilinear and the Hermite
// tracer, in either precision, read the same bytes, so an asset drawn by three tracer textures in
// one frame has one materials buffer, and the two textures added to the first add their images'
// bytes only (K^3 texels of RGBA32F and of RGBA16F), not another K^3 bytes of slots each. The
// pixels of the frame still show both colours on each object: the shared buffer is the one each
// texture's draws read.
TEST_F(MaterialsGpuTest, BothTracersShareOneCopyOfAnAssetsMaterials) {
  constexpr std::uint64_t kK = 20;
  const auto asset = bakeBox(true, int(kK));
  ASSERT_TRUE(asset);
  const auto* tracer = renderer_->feature<hsdf::SphereTraceFeature>();
  ASSERT_NE(tracer, nullptr);
  const render::CameraView camera = render::CameraView::lookAt(glm::vec3(0.0f, 2.0f, 9.0f), glm::vec3(0.0f), 0.9f, 0.1f, 1.0f);
  (void)addSdf(registry_, asset, hsdf::RenderMethod::TrilinearSphereTrace,
               glm::translate(glm::mat4(1.0f), glm::vec3(-2.4f, 0.0f, 0.0f)));
  (void)renderWith(camera, DEBUG_VIEW_NONE);
  const hsdf::SphereTraceFeature::Stats first = tracer->stats();
  EXPECT_EQ(first.textures, 1u);
  EXPECT_EQ(first.materialBuffers, 1u);

  (void)addSdf(registry_, asset, hsdf::RenderMethod::HermiteSphereTrace);
  const ecs::Entity half = addSdf(registry_, asset, hsdf::RenderMethod::HermiteSphereTrace,
                                  glm::translate(glm::mat4(1.0f), glm::vec3(2.4f, 0.0f, 0.0f)));
  registry_.get<hsdf::HermiteSdfRenderable>(half).halfPrecision = true;
  const Frame frame = renderWith(camera, DEBUG_VIEW_NONE);
  const hsdf::SphereTraceFeature::Stats all = tracer->stats();
  EXPECT_EQ(all.hermiteObjects, 2u);
  EXPECT_EQ(all.textures, 3u);
  EXPECT_EQ(all.materialBuffers, 1u) << "one upload of the palette and slots per asset";
  EXPECT_EQ(all.textureBytes - first.textureBytes, kK * kK * kK * (16 + 8)) << "the images only";
  // Each object's third of the image shows red and blue.
  for (std::uint32_t third = 0; third < 3; ++third) {
    int red = 0, blue = 0;
    for (std::uint32_t y = 0; y < kImage; ++y)
      for (std::uint32_t x = third * kImage / 3; x < (third + 1) * kImage / 3; ++x) {
        if (frame.depthAt(x, y) == 0.0f) continue;
        red += slotShown(frame.pixel(x, y)) == 0;
        blue += slotShown(frame.pixel(x, y)) == 1;
      }
    EXPECT_GT(red, 100) << "object " << third;
    EXPECT_GT(blue, 100) << "object " << third;
  }
}

}  // namespace
}  // namespace gputest
