// Every cell method and both sphere tracers from random cameras, random object placements and
// random image sizes, against the CPU reference ray caster of the interpolant each one draws. The
// other GPU tests look from places someone chose (orbits, inside a cell, extreme viewports); a
// user's camera goes anywhere: inside the grid bounds, inside the surface, a near plane that cuts
// cells, a roll, a wide or narrow field of view, an image whose sides are no multiple of the
// tiles', an object rotated, mirrored and scaled unevenly, two objects in front of each other.
// Seeded, so a failure repeats; HSDF_RANDOM_VIEWS=N looks from N cameras per case instead of the
// default few, HSDF_RANDOM_SEED=S from another set (the views drawn depend on both: repeat a
// failure with the same pair).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "hermite_sdf/render/cell_feature.h"
#include "hermite_sdf/render/sphere_trace_feature.h"
#include "hermite_test_support.h"
#include "engine/scene/transform.h"
#include "shared/host_device.h"

namespace gputest {
namespace {

using namespace engine;

unsigned envCount(const char* name, unsigned fallback) {
  const char* value = std::getenv(name);
  return value != nullptr && std::atoi(value) > 0 ? unsigned(std::atoi(value)) : fallback;
}

glm::vec3 unitVector(std::mt19937& rng) {
  std::normal_distribution<float> normal;
  for (;;) {
    const glm::vec3 v(normal(rng), normal(rng), normal(rng));
    if (glm::length(v) > 1e-3f) return glm::normalize(v);
  }
}

// An object's linear part as a scene may hold it: a rotation, a scale of 0.5-2 per axis (uneven
// half of the time) and a mirror a quarter of the time.
glm::mat4 randomLinear(std::mt19937& rng, glm::vec3& scale) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const glm::mat4 rotation = glm::rotate(glm::mat4(1.0f), 6.2832f * unit(rng), unitVector(rng));
  const float s = 0.5f + 1.5f * unit(rng);
  scale = unit(rng) < 0.5f ? glm::vec3(0.5f + 1.5f * unit(rng), 0.5f + 1.5f * unit(rng), 0.5f + 1.5f * unit(rng)) : glm::vec3(s);
  if (unit(rng) < 0.25f) scale.x = -scale.x;
  return rotation * glm::scale(glm::mat4(1.0f), scale);
}

// `linear` about the asset's centre, the centre then moved by `offset`.
glm::mat4 placeAbout(const hsdf::SdfAsset& asset, const glm::mat4& linear, const glm::vec3& offset) {
  const glm::vec3 center(asset.surfaceBounds.center());
  return glm::translate(glm::mat4(1.0f), center + offset) * linear * glm::translate(glm::mat4(1.0f), -center);
}

struct RandomCamera {
  glm::uvec2 size;
  render::CameraView camera;
  std::string label;
};

// A camera around a sphere (the objects' bounds): a quarter of them inside it (often inside a grid,
// sometimes inside a surface), the rest up to 6 radii away, looking at a point near its centre with
// a random roll, a field of view of 15-120 degrees, a near plane from a thousandth of a cell
// (`cellWorld`) to a tenth of the radius, and an image of 24-140 pixels a side.
RandomCamera randomCamera(std::mt19937& rng, const WorldSphere& sphere, float cellWorld) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::uniform_int_distribution<std::uint32_t> side(24, 140);
  RandomCamera c;
  c.size = {side(rng), side(rng)};
  const bool inside = unit(rng) < 0.25f;
  const float distance = sphere.radius * (inside ? 0.05f + 0.9f * unit(rng) : 1.0f + 5.0f * unit(rng));
  const glm::vec3 eye = sphere.center + distance * unitVector(rng);
  const glm::vec3 target = sphere.center + 0.4f * sphere.radius * unit(rng) * unitVector(rng);
  const glm::vec3 forward = glm::normalize(target - eye);
  glm::vec3 right = glm::cross(forward, unitVector(rng));  // a random roll
  while (glm::length(right) < 1e-3f) right = glm::cross(forward, unitVector(rng));
  right = glm::normalize(right);
  const glm::vec3 up = glm::cross(right, forward);
  const glm::mat4 world(glm::vec4(right, 0.0f), glm::vec4(up, 0.0f), glm::vec4(-forward, 0.0f), glm::vec4(eye, 1.0f));
  const float fovY = glm::radians(15.0f + 105.0f * unit(rng));
  const float znear = std::exp(glm::mix(std::log(1e-3f * cellWorld), std::log(0.1f * sphere.radius), unit(rng)));
  c.camera = render::CameraView::fromWorld(world, fovY, znear, float(c.size.x) / float(c.size.y)).value();
  char label[160];
  std::snprintf(label, sizeof(label), "%ux%u, eye %.2f radii%s, fov %.0f deg, near %.1e", c.size.x, c.size.y,
                double(distance / sphere.radius), inside ? " (inside the sphere)" : "", double(glm::degrees(fovY)),
                double(znear));
  c.label = label;
  return c;
}

// One way to draw the SDF: a render method with the cell feature's settings it needs.
struct Method {
  std::string label;
  hsdf::RenderMethod method;
  hsdf::HermiteCellFeature::Tiles tiles = hsdf::HermiteCellFeature::Tiles::Auto;
  hsdf::HermiteCellFeature::ThinBoxes thin = hsdf::HermiteCellFeature::ThinBoxes::Auto;
  bool certified = false;
  bool half = false;  // fp16 records or textures: the reference is the rounded field's
  // Every other setting of the cell feature (tiles and thin boxes above win) and the search's.
  hsdf::HermiteCellFeature::Settings settings = {};
  std::uint32_t subdivisions = 3;
  std::uint32_t refineSteps = 1;
};

bool isTracer(hsdf::RenderMethod method) {
  return method == hsdf::RenderMethod::TrilinearSphereTrace || method == hsdf::RenderMethod::HermiteSphereTrace;
}

using Tiles = hsdf::HermiteCellFeature::Tiles;
using ThinBoxes = hsdf::HermiteCellFeature::ThinBoxes;

const std::vector<Method>& cellMethods() {
  static const std::vector<Method> methods = {
      {"tiles", hsdf::RenderMethod::Cells, Tiles::On},
      {"attribute boxes", hsdf::RenderMethod::Cells, Tiles::Off, ThinBoxes::Off},
      {"thin boxes", hsdf::RenderMethod::Cells, Tiles::Off, ThinBoxes::On},
      {"certified tiles", hsdf::RenderMethod::Cells, Tiles::On, ThinBoxes::Auto, true},
      {"certified boxes", hsdf::RenderMethod::Cells, Tiles::Off, ThinBoxes::Off, true},
      {"tiles fp16", hsdf::RenderMethod::Cells, Tiles::On, ThinBoxes::Auto, false, true},
      {"boxes fp16", hsdf::RenderMethod::Cells, Tiles::Off, ThinBoxes::Off, false, true},
      {"runs", hsdf::RenderMethod::CellRuns},
      {"bricks", hsdf::RenderMethod::CellBricks}};
  return methods;
}

// A cell method with random settings: any combination a user may set from the panel, the
// command line or a settings file.
Method randomCellMethod(std::mt19937& rng) {
  std::uniform_int_distribution<int> pick(0, 99);
  const auto chance = [&](int percent) { return pick(rng) < percent; };
  const auto oneOf3 = [&]() { return pick(rng) % 3; };
  Method m{"", hsdf::RenderMethod::Cells};
  const int method = pick(rng) % 5;
  m.method = method == 3 ? hsdf::RenderMethod::CellRuns : method == 4 ? hsdf::RenderMethod::CellBricks : hsdf::RenderMethod::Cells;
  m.tiles = Tiles(oneOf3());
  m.thin = ThinBoxes(oneOf3());
  m.certified = chance(20);
  m.half = chance(30);
  auto& s = m.settings;
  s.frontToBack = chance(70);
  s.earlyDepth = hsdf::HermiteCellFeature::EarlyDepth(oneOf3());
  s.cullCells = chance(75);
  s.cullBricks = chance(75);
  s.cullOcclusion = chance(30);
  s.proxyBoxes = chance(70);
  s.tileSize = 4u << (pick(rng) % 3);
  s.maxRunLength = 1u + std::uint32_t(pick(rng) % 8);
  // Small kept-cell streams: the first frames' culled rows fall back to unculled draws, which the
  // later frames' streams (sized by the demand) no longer need.
  if (chance(30)) s.keptStreamBytes = 4096u * (1u + std::uint32_t(pick(rng) % 64));
  m.subdivisions = 1u + std::uint32_t(pick(rng) % 6);
  m.refineSteps = std::uint32_t(pick(rng) % 4);
  const char* modes[] = {"auto", "on", "off"};
  char label[256];
  std::snprintf(label, sizeof(label),
                "%s n=%u r=%u%s%s, tiles %s %ux%u, thin %s, early depth %s, front to back %d, cull cells %d bricks %d "
                "occlusion %d, proxy boxes %d, run length %u, kept streams %llu KiB",
                hsdf::renderMethodName(m.method), m.subdivisions, m.refineSteps, m.certified ? " certified" : "",
                m.half ? " fp16" : "", modes[int(m.tiles)], s.tileSize, s.tileSize, modes[int(m.thin)],
                modes[int(s.earlyDepth)], int(s.frontToBack), int(s.cullCells), int(s.cullBricks), int(s.cullOcclusion),
                int(s.proxyBoxes), s.maxRunLength, static_cast<unsigned long long>(s.keptStreamBytes >> 10));
  m.label = label;
  return m;
}

// Pixel i of `to` becomes pixel i of `from` (hit, depth, normal, cell).
void takePixel(hsdf::ReferenceImage& to, const hsdf::ReferenceImage& from, std::size_t i) {
  to.hit[i] = from.hit[i];
  to.depth[i] = from.depth[i];
  to.normal[i] = from.normal[i];
  to.cellId[i] = from.cellId[i];
}

// An object of a view: an asset and where it stands.
struct Placed {
  std::shared_ptr<const hsdf::SdfAsset> asset;
  glm::mat4 model;
};

class RandomViewsTest : public GpuTest {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    createRenderer(64, 64);
    ASSERT_TRUE(renderer_->addFeature(std::make_unique<hsdf::HermiteCellFeature>()).ok());
    ASSERT_TRUE(renderer_->addFeature(std::make_unique<hsdf::SphereTraceFeature>()).ok());
  }

  // The torus (K = 16) and the bunny (K = 32) of the views with several objects; null where a bake
  // failed (the test has failed).
  static std::pair<std::shared_ptr<const hsdf::SdfAsset>, std::shared_ptr<const hsdf::SdfAsset>> torusAndBunny() {
    return {bakeAsset("torus", 16), bakeAsset("bunny", 32)};
  }

  // The cell feature's settings of `m` (its tiles and thin boxes win over its other settings').
  void useCellSettings(const Method& m) {
    auto& cells = renderer_->feature<hsdf::HermiteCellFeature>()->settings();
    cells = m.settings;
    cells.tiles = m.tiles;
    cells.thinBoxes = m.thin;
  }

  // Makes `entity`'s renderable draw as `m` says.
  void drawWith(const Method& m, ecs::Entity entity) {
    auto& renderable = registry_.get<hsdf::HermiteSdfRenderable>(entity);
    renderable.method = m.method;
    renderable.subdivisions = m.subdivisions;
    renderable.refineSteps = m.refineSteps;
    renderable.certified = m.certified;
    renderable.halfPrecision = m.half;
  }

  // Checks one image against its reference (see expectViewMatches).
  void expectMatches(const Method& m, const Frame& shaded, const Frame& normals, const hsdf::ReferenceImage& reference,
                     const RandomCamera& c, double spacing, const glm::mat4& model, int& shown) {
    const ImageComparison r = compareWithReference(shaded, &normals.rgba, reference, c.camera, spacing, model);
    std::printf("[ %s, %s ] hits ref %d gpu %d, disagree %d, holes %d, extras %d, outliers %d, flips %d (interior %d), "
                "interior depth p99 %.1e cells\n",
                c.label.c_str(), m.label.c_str(), r.referenceHits, r.gpuHits, r.disagreements, r.interiorHoles,
                r.interiorExtras, r.interiorDepthOutliers, r.normalFlips, r.interiorNormalFlips, r.interiorDepthErrorP99);
    // A sphere tracer steps by the interpolant's value, which is no distance bound: where the ray
    // grazes a bump (two roots within one step) it may step over it and hit the surface just
    // behind, a pixel or so in a thousand (once in the sweeps a trilinear ray at an occlusion edge
    // hit nothing at all, not out of steps; docs/root-finding.md). The cells' search never passes
    // a root.
    const int passedRoots = isTracer(m.method) ? std::max(1, r.referenceHits / 1000) : 0;
    EXPECT_LE(r.interiorHoles, passedRoots);
    EXPECT_EQ(r.interiorExtras, 0);
    // Without a refinement step a root is placed at the zero of its interval's control polygon:
    // within the interval, not within 0.05 cells (docs/root-finding.md).
    if (m.refineSteps > 0 || m.certified) {
      EXPECT_LE(r.interiorDepthOutliers, passedRoots);
    }
    EXPECT_LE(r.interiorNormalFlips, passedRoots);
    EXPECT_LE(r.disagreements, std::max(4, r.referenceHits / 100));
    shown += r.referenceHits > 0;
  }

  // The reference of what `m` draws of the objects: each object's own, the nearer hit per pixel.
  hsdf::ReferenceImage referenceOf(const Method& m, const std::vector<Placed>& objects, const RandomCamera& c) {
    hsdf::ReferenceImage nearest;
    for (const Placed& object : objects) {
      const hsdf::HermiteField field = m.half ? roundedToHalf(object.asset->field) : object.asset->field;
      hsdf::ReferenceImage image = referenceFor(m.method, field, c.camera, glm::ivec2(c.size), object.model);
      if (nearest.hit.empty()) {
        nearest = std::move(image);
        continue;
      }
      for (std::size_t i = 0; i < image.hit.size(); ++i)
        if (image.hit[i] && (!nearest.hit[i] || image.depth[i] > nearest.depth[i]))  // reverse-Z: nearer is greater
          takePixel(nearest, image, i);
    }
    return nearest;
  }

  // Draws the objects with each method from camera `c` and checks each image against the reference
  // of the interpolant that method draws: inside the silhouettes (the outline, and where a nearer
  // part passes in front of a farther one) no hole, no extra hit, no depth more than 0.05 cells off
  // and no flipped normal; on them, few differences. Returns how many images showed some surface.
  int expectViewMatches(const std::vector<Method>& methods, const std::vector<Placed>& objects, const RandomCamera& c) {
    renderer_->resize({c.size.x, c.size.y});
    // Depth errors in cells of the finest grid; the objects share their linear part (placeAbout).
    double spacing = objects[0].asset->field.grid.spacing;
    for (const Placed& object : objects) spacing = std::min(spacing, object.asset->field.grid.spacing);
    std::map<std::pair<bool, bool>, hsdf::ReferenceImage> references;  // (trilinear, fp16): each cast once
    int shown = 0;
    for (const Method& m : methods) {
      SCOPED_TRACE(c.label + ", " + m.label);
      const std::pair<bool, bool> key(m.method == hsdf::RenderMethod::TrilinearSphereTrace, m.half);
      if (!references.count(key)) references[key] = referenceOf(m, objects, c);
      const hsdf::ReferenceImage& reference = references[key];
      useCellSettings(m);
      registry_ = ecs::Registry();
      for (const Placed& object : objects) drawWith(m, addSdf(registry_, object.asset, m.method, object.model));
      const Frame shaded = renderWith(c.camera, DEBUG_VIEW_NONE);
      const Frame normals = renderWith(c.camera, DEBUG_VIEW_NORMALS);
      expectMatches(m, shaded, normals, reference, c, spacing, objects[0].model, shown);
    }
    return shown;
  }

  // Each shape alone, placed and looked at from HSDF_RANDOM_VIEWS random views (default 4), drawn
  // with `fixedMethods` and `randomMethods` random cell methods per view.
  void expectEveryViewMatches(const std::vector<Method>& fixedMethods, int randomMethods = 0) {
    const unsigned views = envCount("HSDF_RANDOM_VIEWS", 4);
    std::mt19937 rng(envCount("HSDF_RANDOM_SEED", 20261127));
    const std::pair<const char*, int> shapes[] = {{"torus", 16}, {"box", 12}, {"blob", 20}, {"bunny", 32}};
    int shown = 0, drawn = 0;
    for (const auto& [shape, k] : shapes) {
      const auto asset = bakeAsset(shape, k);
      ASSERT_NE(asset, nullptr);
      for (unsigned v = 0; v < views; ++v) {
        glm::vec3 scale;
        const Placed object{asset, placeAbout(*asset, randomLinear(rng, scale), glm::vec3(0.0f))};
        const float cellWorld = float(asset->field.grid.spacing) * std::min({std::abs(scale.x), scale.y, scale.z});
        RandomCamera c = randomCamera(rng, worldSphere(*asset, object.model), cellWorld);
        char label[96];
        std::snprintf(label, sizeof(label), "%s view %u, scale (%.2f %.2f %.2f), ", shape, v, double(scale.x),
                      double(scale.y), double(scale.z));
        c.label = label + c.label;
        std::vector<Method> methods = fixedMethods;
        for (int i = 0; i < randomMethods; ++i) methods.push_back(randomCellMethod(rng));
        shown += expectViewMatches(methods, {object}, c);
        drawn += int(methods.size());
      }
    }
    // Most random views must show some surface, or the test compares empty frames.
    EXPECT_GE(shown, drawn / 2);
  }
};

// Why: each cell method reaches a pixel's root by its own path (a box's own fragment, its back
// face when the near plane cuts it, a tile's list, a run's or a brick's walk), each with its own
// clipping, culling, near-plane, viewport and transform maths, in fp32 and fp16; a mistake in any
// of them shows as a hole or a speck (a ray through the surface) somewhere a chosen camera never
// looked.
TEST_F(RandomViewsTest, EveryCellMethodMatchesTheReferenceFromRandomCameras) {
  expectEveryViewMatches(cellMethods());
}

// Why: the baselines trace from the box entry or the near plane, in the object's own space, with
// their own step rules; the same cameras must draw each tracer's own interpolant, but for the rare
// bump a step passes over.
TEST_F(RandomViewsTest, EachSphereTracerMatchesItsReferenceFromRandomCameras) {
  expectEveryViewMatches({{"trilinear", hsdf::RenderMethod::TrilinearSphereTrace},
                          {"hermite", hsdf::RenderMethod::HermiteSphereTrace},
                          {"hermite fp16", hsdf::RenderMethod::HermiteSphereTrace, Tiles::Auto, ThinBoxes::Auto, false, true}});
}

// Why: the cell feature's settings (tiles, thin boxes, tile size, early depth, front-to-back
// order, cell, brick and occlusion culling, proxy boxes, run length) and the search's (n,
// refinement, certified, fp16) each pick another path or change what a path is given; a user may
// set any combination. Three random combinations per view.
TEST_F(RandomViewsTest, RandomSettingsOfTheCellMethodsMatchTheReference) {
  expectEveryViewMatches({}, 3);
}

// Why: the scene runner's split screen (and any editor's viewports) draws one frame in view
// regions, each with its own method: a region need not start at a multiple of the tiles' size,
// its tiles, boxes and tracers are clipped to it, and each region's features are prepared for it.
// A random column or row splits each view; the left (top) side draws a random cell method, the
// other side a tracer or another cell method, and each side must match its own reference.
TEST_F(RandomViewsTest, SplitScreensAtAnyColumnOrRowMatchEachSidesReference) {
  const unsigned views = envCount("HSDF_RANDOM_VIEWS", 4);
  std::mt19937 rng(envCount("HSDF_RANDOM_SEED", 20261127) + 2);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const auto [torus, bunny] = torusAndBunny();
  ASSERT_TRUE(torus && bunny);
  const std::vector<Method> others = {{"trilinear", hsdf::RenderMethod::TrilinearSphereTrace},
                                      {"hermite", hsdf::RenderMethod::HermiteSphereTrace},
                                      {"cell runs", hsdf::RenderMethod::CellRuns}};
  int shown = 0;
  for (unsigned v = 0; v < 2 * views; ++v) {
    const auto& asset = v % 2 == 0 ? torus : bunny;
    glm::vec3 scale;
    const Placed object{asset, placeAbout(*asset, randomLinear(rng, scale), glm::vec3(0.0f))};
    const float cellWorld = float(asset->field.grid.spacing) * std::min({std::abs(scale.x), scale.y, scale.z});
    RandomCamera c = randomCamera(rng, worldSphere(*asset, object.model), cellWorld);
    const Method first = randomCellMethod(rng);
    const Method second = unit(rng) < 0.5f ? others[std::size_t(v / 2) % others.size()] : randomCellMethod(rng);
    const bool vertical = unit(rng) < 0.5f;
    const std::uint32_t extent = vertical ? c.size.x : c.size.y;
    const std::uint32_t split = 1u + std::uint32_t(unit(rng) * float(extent - 2));
    c.label = std::string(asset->name) + " split view " + std::to_string(v) + " at " + (vertical ? "column " : "row ") +
              std::to_string(split) + ", " + c.label;
    SCOPED_TRACE(c.label + ", " + first.label + " | " + second.label);
    renderer_->resize({c.size.x, c.size.y});
    // One feature setting for the frame (the regions change the object, not the feature).
    useCellSettings(first);
    registry_ = ecs::Registry();
    const ecs::Entity entity = addSdf(registry_, asset, first.method, object.model);
    render::FrameSettings settings;
    const VkExtent2D size{c.size.x, c.size.y};
    const VkRect2D near = vertical ? VkRect2D{{0, 0}, {split, size.height}} : VkRect2D{{0, 0}, {size.width, split}};
    const VkRect2D far = vertical ? VkRect2D{{int(split), 0}, {size.width - split, size.height}}
                                  : VkRect2D{{0, int(split)}, {size.width, size.height - split}};
    settings.regions = {{near, [&] { drawWith(first, entity); }}, {far, [&] { drawWith(second, entity); }}};
    const Frame shaded = renderWith(c.camera, settings);
    settings.debugView = DEBUG_VIEW_NORMALS;
    const Frame normals = renderWith(c.camera, settings);
    // The reference: each pixel from its side's method, so that a pixel drawn by the wrong side or
    // by neither shows on the seam as on any other pixel.
    hsdf::ReferenceImage reference = referenceOf(first, {object}, c);
    const hsdf::ReferenceImage other = referenceOf(second, {object}, c);
    for (std::uint32_t y = 0; y < size.height; ++y)
      for (std::uint32_t x = 0; x < size.width; ++x) {
        if ((vertical ? x : y) >= split) takePixel(reference, other, std::size_t(y) * size.width + x);
      }
    // Checked as strictly as the laxer side allows.
    Method both = first;
    both.label = first.label + " | " + second.label;
    if (isTracer(second.method)) both.method = second.method;
    both.refineSteps = std::min(first.refineSteps, second.refineSteps);
    both.certified = first.certified && second.certified;
    expectMatches(both, shaded, normals, reference, c, asset->field.grid.spacing, object.model, shown);
  }
  EXPECT_GE(shown, int(views));
}

// Why: objects in one draw, in front of and through each other: two instances of the torus (one
// asset, two transforms in one multi-draw) and the bunny (another asset): the depth test between
// their boxes, a tile's list mixing the objects' cells (sorted by box, the ray rebuilt per
// object), the near-plane path for one and not another. Each pixel must show the nearest of the
// references.
TEST_F(RandomViewsTest, ObjectsThroughEachOtherShowTheNearestSurface) {
  const auto [torus, bunny] = torusAndBunny();
  ASSERT_TRUE(torus && bunny);
  const unsigned views = envCount("HSDF_RANDOM_VIEWS", 4);
  std::mt19937 rng(envCount("HSDF_RANDOM_SEED", 20261127) + 1);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int shown = 0;
  for (unsigned v = 0; v < views; ++v) {
    glm::vec3 scale;
    const glm::mat4 linear = randomLinear(rng, scale);  // shared: one depth error scale for all
    const Placed first{torus, placeAbout(*torus, linear, glm::vec3(0.0f))};
    const WorldSphere sphere = worldSphere(*torus, first.model);
    const Placed second{bunny, placeAbout(*bunny, linear, 0.6f * sphere.radius * unit(rng) * unitVector(rng))};
    const Placed third{torus, placeAbout(*torus, linear, 0.6f * sphere.radius * unit(rng) * unitVector(rng))};
    const WorldSphere other = worldSphere(*bunny, second.model);
    // A sphere holding both spheres: the third torus lies within 0.6 radii of the first.
    const WorldSphere all{0.5f * (sphere.center + other.center),
                          0.5f * glm::distance(sphere.center, other.center) + std::max(1.6f * sphere.radius, other.radius)};
    const float cellWorld = float(bunny->field.grid.spacing) * std::min({std::abs(scale.x), scale.y, scale.z});
    RandomCamera c = randomCamera(rng, all, cellWorld);
    c.label = "two tori and a bunny, view " + std::to_string(v) + ", " + c.label;
    shown += expectViewMatches(cellMethods(), {first, second, third}, c);
  }
  EXPECT_GE(shown, int(views * cellMethods().size()) / 2);
}

// Why: a scene mixes render methods (props as cells, runs or bricks, an object traced), and the
// methods share one depth and visibility buffer: each feature's shading pass must shade only the
// pixels its own objects won (the cells' resolve by the winner's feature, a tracer's by its object),
// and the cell feature's frame-wide stages (early depth, thin boxes, tiles, occlusion culling) must
// hold with the other methods' objects in the frame. Five objects in and through each other, each
// drawn by another of the five methods (shuffled) with its own search settings, the cell feature's
// settings random; the nearest of the objects' references (each of the interpolant its method
// draws) per pixel, over two frames (occlusion culling's second one has a history).
TEST_F(RandomViewsTest, MixedMethodsInOneFrameShowTheNearestSurface) {
  int shown = 0;
  std::vector<hsdf::RenderMethod> kinds = {hsdf::RenderMethod::Cells, hsdf::RenderMethod::CellRuns,
                                           hsdf::RenderMethod::CellBricks, hsdf::RenderMethod::TrilinearSphereTrace,
                                           hsdf::RenderMethod::HermiteSphereTrace};
  const auto [torus, bunny] = torusAndBunny();
  ASSERT_TRUE(torus && bunny);
  const unsigned views = envCount("HSDF_RANDOM_VIEWS", 4);
  std::mt19937 rng(envCount("HSDF_RANDOM_SEED", 20261127) + 5);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (unsigned v = 0; v < views; ++v) {
    glm::vec3 scale;
    const glm::mat4 linear = randomLinear(rng, scale);  // shared: one depth error scale for all
    const WorldSphere sphere = worldSphere(*torus, placeAbout(*torus, linear, glm::vec3(0.0f)));
    std::vector<Placed> objects;
    for (std::size_t i = 0; i < kinds.size(); ++i) {
      const auto& asset = i == 2 ? bunny : torus;
      const glm::vec3 offset = i == 0 ? glm::vec3(0.0f) : 0.6f * sphere.radius * unit(rng) * unitVector(rng);
      objects.push_back({asset, placeAbout(*asset, linear, offset)});
    }
    std::shuffle(kinds.begin(), kinds.end(), rng);
    const Method frame = randomCellMethod(rng);  // the cell feature's settings
    std::vector<Method> methods;
    std::string label = frame.label;
    bool traced = false, refined = true;
    for (const hsdf::RenderMethod kind : kinds) {
      Method m = randomCellMethod(rng);
      m.method = kind;
      traced = traced || isTracer(kind);
      refined = refined && (isTracer(kind) || m.refineSteps > 0 || m.certified);
      label += fmt::format(" | {} n={} r={}{}{}", hsdf::renderMethodName(kind), m.subdivisions, m.refineSteps,
                           m.certified ? " certified" : "", m.half ? " fp16" : "");
      methods.push_back(m);
    }
    const WorldSphere all{sphere.center, 1.6f * sphere.radius};
    const float cellWorld = float(torus->field.grid.spacing) * std::min({std::abs(scale.x), scale.y, scale.z});
    RandomCamera c = randomCamera(rng, all, cellWorld);
    c.label = "five objects, five methods, view " + std::to_string(v) + ", " + c.label;
    SCOPED_TRACE(c.label + ", " + label);
    // Each object's own reference, the nearest hit per pixel.
    hsdf::ReferenceImage reference;
    for (std::size_t i = 0; i < objects.size(); ++i) {
      const hsdf::ReferenceImage image = referenceOf(methods[i], {objects[i]}, c);
      if (reference.hit.empty()) reference = image;
      for (std::size_t p = 0; p < image.hit.size(); ++p)
        if (image.hit[p] && (!reference.hit[p] || image.depth[p] > reference.depth[p])) takePixel(reference, image, p);
    }
    renderer_->resize({c.size.x, c.size.y});
    useCellSettings(frame);
    registry_ = ecs::Registry();
    for (std::size_t i = 0; i < objects.size(); ++i)
      drawWith(methods[i], addSdf(registry_, objects[i].asset, methods[i].method, objects[i].model));
    for (int f = 0; f < 2; ++f) {
      SCOPED_TRACE("frame " + std::to_string(f));
      const Frame shaded = renderWith(c.camera, DEBUG_VIEW_NONE);
      const Frame normals = renderWith(c.camera, DEBUG_VIEW_NORMALS);
      // Checked as strictly as the laxest object allows.
      Method strictest = frame;
      strictest.label = label;
      strictest.method = traced ? hsdf::RenderMethod::HermiteSphereTrace : hsdf::RenderMethod::Cells;
      strictest.refineSteps = refined ? 1 : 0;
      strictest.certified = false;
      int drawn = 0;
      expectMatches(strictest, shaded, normals, reference, c, torus->field.grid.spacing, objects[0].model, drawn);
      shown += drawn;
    }
  }
  EXPECT_GE(shown, int(views));
}

// A square of triangles (the fixture's quad) through `center`, facing `normal` (back faces are
// culled: seen from behind it is not drawn), `size` a side, spun about its normal by `spin`.
struct WorldQuad {
  glm::vec3 center;
  glm::quat rotation;  // the quad's +Z onto its normal
  float size;

  glm::mat4 matrix() const {
    return glm::translate(glm::mat4(1.0f), center) * glm::mat4_cast(rotation) * glm::scale(glm::mat4(1.0f), glm::vec3(size, size, 1.0f));
  }

  // Where pixel ray `ray` (from the eye, unit direction) meets the quad's front, as a view distance
  // along `forward`; 0 when it misses, meets the back, or meets it nearer than the near plane.
  double viewDistance(const math::Ray& ray, const glm::dvec3& forward, double znear) const {
    const glm::dvec3 normal = glm::dvec3(rotation * glm::vec3(0.0f, 0.0f, 1.0f));
    const double facing = glm::dot(ray.direction, normal);
    if (!(facing < 0.0)) return 0.0;
    const double t = glm::dot(glm::dvec3(center) - ray.origin, normal) / facing;
    const glm::dvec3 local = glm::inverse(glm::dquat(rotation)) * (ray.origin + t * ray.direction - glm::dvec3(center));
    const double half = 0.5 * double(size);
    if (t <= 0.0 || std::abs(local.x) >= half || std::abs(local.y) >= half) return 0.0;
    const double distance = t * glm::dot(ray.direction, forward);
    return distance > znear ? distance : 0.0;
  }
};

WorldQuad randomQuad(std::mt19937& rng, const WorldSphere& sphere, float offsetRadii, float minSize, float maxSize) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const glm::vec3 normal = unitVector(rng);
  const glm::quat onto(glm::vec3(0.0f, 0.0f, 1.0f), normal);  // the shortest arc from +Z
  const glm::quat spin = glm::angleAxis(6.2832f * unit(rng), glm::vec3(0.0f, 0.0f, 1.0f));
  return {sphere.center + offsetRadii * sphere.radius * unit(rng) * unitVector(rng), onto * spin,
          sphere.radius * glm::mix(minSize, maxSize, unit(rng))};
}

// Which surface each pixel shows where an SDF object and triangle meshes meet in one depth buffer.
struct SurfaceCheck {
  int checked = 0;
  int meshShown = 0;  // pixels whose nearest surface is a mesh
  int sdfShown = 0;   // pixels whose nearest surface is the SDF
  int wrong = 0;      // pixels whose depth is nearer another candidate's than the expected one's
  std::string firstWrong;
};

// Each pixel's expected depth is the nearer of the reference's and the quads'; the GPU's depth must
// lie nearer to it than to every other candidate (the other surface, the background). A GPU snaps
// a triangle's vertices to its sub-pixel grid, and a search places a root within its tolerance, so
// depths are compared by which candidate they are nearest, and pixels where the two surfaces lie
// within `margin` (world units) of each other are left out, as are pixels next to a change of
// what they show (the outline and occlusion edges of the SDF, `edge` world units along the ray
// between neighbours; the edges of a quad; a quad meeting the near plane).
SurfaceCheck checkSurfaces(const Frame& gpu, const hsdf::ReferenceImage& reference, const std::vector<WorldQuad>& quads,
                           const render::CameraView& camera, double margin, double edge) {
  const int width = int(gpu.width), height = int(gpu.height);
  const glm::dvec3 forward = -glm::dvec3(glm::inverse(camera.view)[2]);
  std::vector<double> mesh(std::size_t(width) * std::size_t(height), 0.0), sdf(mesh.size(), 0.0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(width) + std::size_t(x);
      const math::Ray ray = math::pixelRay(camera.view, camera.proj, {float(x) + 0.5f, float(y) + 0.5f}, {width, height});
      for (const WorldQuad& quad : quads) {
        const double d = quad.viewDistance(ray, forward, double(camera.znear));
        if (d > 0.0 && (mesh[i] == 0.0 || d < mesh[i])) mesh[i] = d;
      }
      if (reference.hit[i]) sdf[i] = math::depthToViewDistance(reference.depth[i], camera.znear);
    }
  SurfaceCheck check;
  for (int y = 1; y + 1 < height; ++y)
    for (int x = 1; x + 1 < width; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(width) + std::size_t(x);
      if (mesh[i] == 0.0 && sdf[i] == 0.0) continue;
      bool nearEdge = mesh[i] != 0.0 && mesh[i] < 1.01 * double(camera.znear);
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const std::size_t j = std::size_t(y + dy) * std::size_t(width) + std::size_t(x + dx);
          nearEdge |= (mesh[j] == 0.0) != (mesh[i] == 0.0) || (sdf[j] == 0.0) != (sdf[i] == 0.0) ||
                      std::abs(sdf[j] - sdf[i]) > edge || std::abs(mesh[j] - mesh[i]) > edge;
        }
      if (nearEdge || (mesh[i] != 0.0 && sdf[i] != 0.0 && std::abs(mesh[i] - sdf[i]) < margin)) continue;
      const bool meshInFront = mesh[i] != 0.0 && (sdf[i] == 0.0 || mesh[i] < sdf[i]);
      const auto depthOf = [&](double distance) { return distance == 0.0 ? 0.0 : math::viewDistanceToDepth(distance, camera.znear); };
      const double expected = depthOf(meshInFront ? mesh[i] : sdf[i]);
      const double got = gpu.depth[i];
      bool right = true;
      for (const double other : {depthOf(meshInFront ? sdf[i] : mesh[i]), 0.0})
        if (other != expected) right = right && std::abs(got - expected) < std::abs(got - other);
      ++check.checked;
      (meshInFront ? check.meshShown : check.sdfShown) += 1;
      if (!right && check.wrong++ == 0) {
        char text[160];
        std::snprintf(text, sizeof(text), "first at (%d, %d): mesh %.5g, sdf %.5g, gpu %.5g (view distances, 0: none)", x,
                      y, mesh[i], sdf[i], got > 0.0 ? math::depthToViewDistance(got, camera.znear) : 0.0);
        check.firstWrong = text;
      }
    }
  return check;
}

// Why: SDF objects share the engine's depth prepass with ordinary meshes (a ground, a wall, a
// level's geometry): the boxes' and tiles' conservative depth meets rasterized triangles in one
// depth buffer, a mesh in front must hide the object's cells (culled, rejected early, or searched
// and lost in the depth test) and one behind must not, whatever path draws the object, and the
// tracers write their hits into the same buffer. Random quads through and around the object
// (often cutting it, sometimes seen from behind, where they are culled), from the same random
// cameras; each pixel must show the nearer surface. The random cell method is drawn twice, so
// that occlusion culling also runs with the previous frame's depth, meshes included.
TEST_F(RandomViewsTest, MeshesThroughTheObjectShowTheNearerSurface) {
  const auto [torus, bunny] = torusAndBunny();
  ASSERT_TRUE(torus && bunny);
  const unsigned views = envCount("HSDF_RANDOM_VIEWS", 4);
  std::mt19937 rng(envCount("HSDF_RANDOM_SEED", 20261127) + 3);
  std::vector<Method> fixed = cellMethods();
  fixed.push_back({"trilinear", hsdf::RenderMethod::TrilinearSphereTrace});
  fixed.push_back({"hermite", hsdf::RenderMethod::HermiteSphereTrace});
  SurfaceCheck total;
  for (unsigned v = 0; v < 2 * views; ++v) {
    const auto& asset = v % 2 == 0 ? torus : bunny;
    glm::vec3 scale;
    const Placed object{asset, placeAbout(*asset, randomLinear(rng, scale), glm::vec3(0.0f))};
    const WorldSphere sphere = worldSphere(*asset, object.model);
    const double spacing = asset->field.grid.spacing;
    const float cellWorld = float(spacing) * std::min({std::abs(scale.x), scale.y, scale.z});
    const double cellMax = spacing * double(std::max({std::abs(scale.x), scale.y, scale.z}));
    RandomCamera c = randomCamera(rng, sphere, cellWorld);
    // A large quad through the middle of the object, a smaller one anywhere near it.
    const std::vector<WorldQuad> quads = {randomQuad(rng, sphere, 0.3f, 2.0f, 6.0f), randomQuad(rng, sphere, 1.0f, 0.3f, 1.5f)};
    std::vector<Method> methods = fixed;
    methods.push_back(randomCellMethod(rng));
    c.label = std::string(asset->name) + " and two quads, view " + std::to_string(v) + ", " + c.label;
    renderer_->resize({c.size.x, c.size.y});
    std::map<bool, hsdf::ReferenceImage> references;  // by trilinear
    for (std::size_t k = 0; k < methods.size(); ++k) {
      const Method& m = methods[k];
      SCOPED_TRACE(c.label + ", " + m.label);
      const bool trilinear = m.method == hsdf::RenderMethod::TrilinearSphereTrace;
      if (!references.count(trilinear)) references[trilinear] = referenceOf(m, {object}, c);
      useCellSettings(m);
      registry_ = ecs::Registry();
      drawWith(m, addSdf(registry_, object.asset, m.method, object.model));
      // World transforms set as they are (addSdf's are; resolving the hierarchy would reset them).
      for (const WorldQuad& quad : quads) {
        const ecs::Entity e = addQuad(quad.center, quad.size, {0.3f, 0.5f, 0.8f, 1.0f});
        registry_.emplace<scene::WorldTransform>(e, scene::WorldTransform{quad.matrix()});
      }
      // Without refinement a root lies anywhere in its interval of the ray (up to a cell's
      // diagonal / n); with it, and for the tracers, within a small fraction of a cell.
      const double margin = m.refineSteps == 0 && !m.certified && !isTracer(m.method) ? 2.0 * cellMax : 0.05 * cellMax;
      const int frames = k + 1 == methods.size() ? 2 : 1;
      for (int f = 0; f < frames; ++f) {
        SCOPED_TRACE("frame " + std::to_string(f));
        const Frame frame = renderWith(c.camera, DEBUG_VIEW_NONE);
        const SurfaceCheck check = checkSurfaces(frame, references[trilinear], quads, c.camera, margin, cellMax);
        std::printf("[ %s, %s ] frame %d: checked %d, mesh shown %d, sdf shown %d, wrong %d\n", c.label.c_str(),
                    m.label.c_str(), f, check.checked, check.meshShown, check.sdfShown, check.wrong);
        // The tracers may pass one grazed bump per thousand pixels (expectMatches).
        EXPECT_LE(check.wrong, isTracer(m.method) ? std::max(1, check.sdfShown / 1000) : 0) << check.firstWrong;
        total.checked += check.checked;
        total.meshShown += check.meshShown;
        total.sdfShown += check.sdfShown;
      }
    }
  }
  // The views must put both surfaces in front somewhere, or the test compares little.
  EXPECT_GT(total.meshShown, total.checked / 20);
  EXPECT_GT(total.sdfShown, total.checked / 20);
}


// A camera at `eye` looking at `target` with `up` roughly up, for an image of `size`.
RandomCamera lookingAt(glm::uvec2 size, glm::vec3 eye, glm::vec3 target, float fovY, float znear, glm::vec3 up) {
  const glm::vec3 forward = glm::normalize(target - eye);
  const glm::vec3 right = glm::normalize(glm::cross(forward, up));
  const glm::mat4 world(glm::vec4(right, 0.0f), glm::vec4(glm::cross(right, forward), 0.0f), glm::vec4(-forward, 0.0f),
                        glm::vec4(eye, 1.0f));
  RandomCamera c;
  c.size = size;
  c.camera = render::CameraView::fromWorld(world, fovY, znear, float(size.x) / float(size.y)).value();
  return c;
}

// An object placement and a camera at a limit no random view reaches; `ci`: drawn in CI.
struct LimitCase {
  glm::mat4 model;
  RandomCamera camera;
  bool ci;
};

// The limits (the torus at K = 16): a scale of 1e-3 and 1e3 on one axis (mirrored too), seen from
// outside and from a fiftieth to two cells before the surface inside the grid; shears whose
// columns keep their length but are nearly parallel (the smallest column is no bound on the
// smallest scale); eyes on a cell corner inside the grid and on a cell edge outside it, looking
// straight along a grid axis (rays parallel to cell faces, the centre ray of an odd image along a
// cell edge), perspective and orthographic; fields of view of 150-178 degrees from the torus's hole
// and of 0.1 and 1 degree from afar; images of 3x1000 and 1000x3; a chain of 64 nodes.
std::vector<LimitCase> limitCases(const hsdf::SdfAsset& torus) {
  const glm::mat4 id(1.0f);
  const glm::mat4 turn = glm::rotate(id, 0.5f, glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f)));
  const glm::vec3 centre(torus.surfaceBounds.center());
  const float h = float(torus.field.grid.spacing);
  const float radius = 0.5f * float(glm::length(torus.surfaceBounds.size()));
  const glm::vec3 tilted(0.1f, 0.2f, 1.0f);  // an up vector no view here looks along
  std::vector<LimitCase> cases;
  auto add = [&](const std::string& label, const glm::mat4& model, RandomCamera c, bool ci) {
    c.label = label;
    cases.push_back({model, std::move(c), ci});
  };
  const glm::vec3 sides[3] = {glm::normalize(glm::vec3(0.3f, 0.5f, 1.0f)), glm::normalize(glm::vec3(1.0f, 0.4f, 0.2f)),
                              glm::normalize(glm::vec3(-0.2f, 1.0f, 0.3f))};
  for (const float sx : {1e-3f, -1e-3f, 1e3f, 20.0f, 0.05f})
    for (int rotated = 0; rotated < 2; ++rotated) {
      const glm::mat4 model = placeAbout(torus, (rotated ? turn : id) * glm::scale(id, glm::vec3(sx, 1.0f, 1.0f)), glm::vec3(0.0f));
      const WorldSphere s = worldSphere(torus, model);
      const float distance = std::abs(sx) > 1.0f ? 2.5f * radius : 2.5f * s.radius;  // close to a long object
      for (int v = 0; v < 3; ++v)
        add(fmt::format("scale ({}, 1, 1){}, view {}", sx, rotated ? " turned" : "", v), model,
            lookingAt({97, 83}, s.center + distance * sides[v], s.center, 1.0f, 1e-3f * radius, tilted),
            rotated && v == 1 && (sx == -1e-3f || sx == 1e3f));
    }
  for (const float sx : {1e-3f, 1e3f, 1e-2f, 30.0f})
    for (int axis = 0; axis < 2; ++axis) {
      const glm::mat4 model = placeAbout(torus, glm::scale(id, glm::vec3(sx, 1.0f, 1.0f)), glm::vec3(0.0f));
      glm::dvec3 along(0.0);
      along[axis == 0 ? 0 : 2] = 1.0;
      const auto hit = hsdf::castRay(torus.field, {glm::dvec3(centre) + glm::dvec3(0.0, 0.05, 0.0), along});
      EXPECT_TRUE(hit.ok() && hit->has_value());
      if (!hit.ok() || !hit->has_value()) continue;
      for (const double back : {0.3, 0.02, 2.0}) {
        const glm::dvec3 eye = (*hit)->position - back * double(h) * along;
        const glm::dvec3 target = (*hit)->position + double(h) * glm::dvec3(0.2 * along.z, 0.3, 0.2 * along.x);
        const float cellWorld = h * std::min(std::abs(sx), 1.0f);
        add(fmt::format("scale ({}, 1, 1), {} cells before the surface along {}", sx, back, axis == 0 ? "x" : "z"), model,
            lookingAt({81, 81}, glm::vec3(model * glm::vec4(glm::vec3(eye), 1.0f)),
                      glm::vec3(model * glm::vec4(glm::vec3(target), 1.0f)), 1.2f, 0.05f * cellWorld, tilted),
            back == 0.02 && axis == 0 && (sx == 1e-3f || sx == 1e3f));
      }
    }
  // Column b leans towards column a until their cosine is c: x towards y, then (the strongest
  // shear, in larger images: more cell edges near pixel centres) y towards z and z towards x.
  const char* pairs[3] = {"", " yz", " zx"};
  for (const float c : {0.9f, 0.995f, 0.9995f, 0.99999f})
    for (int a = 0; a < (c > 0.9999f ? 3 : 1); ++a) {
      const int b = (a + 1) % 3;
      glm::mat4 shear(1.0f);
      shear[b] = glm::vec4(0.0f);
      shear[b][a] = c;
      shear[b][b] = std::sqrt(1.0f - c * c);
      const glm::uvec2 size = c > 0.9999f ? glm::uvec2{301, 257} : glm::uvec2{97, 83};
      for (int rotated = 0; rotated < 2; ++rotated) {
        const glm::mat4 model = placeAbout(torus, (rotated ? turn : id) * shear, glm::vec3(0.0f));
        const WorldSphere s = worldSphere(torus, model);
        for (int v = 0; v < 4; ++v) {
          const glm::vec3 eye = s.center + (v == 3 ? 0.3f * s.radius * glm::normalize(glm::vec3(0.0f, 0.1f, 1.0f)) : 2.0f * s.radius * sides[v]);
          add(fmt::format("shear {}{}{}, view {}", c, pairs[a], rotated ? " turned" : "", v), model,
              lookingAt(size, eye, s.center + glm::vec3(0.01f, 0.02f, 0.0f), 1.0f, 1e-4f * radius, tilted),
              c == 0.9995f && rotated && v == 3);
        }
      }
    }
  const glm::vec3 corner = glm::vec3(torus.field.grid.origin) + 7.0f * h;  // a cell corner inside the grid
  for (int a = 0; a < 3; ++a) {
    glm::vec3 axis(0.0f);
    axis[a] = 1.0f;
    const glm::vec3 up = a == 1 ? glm::vec3(0.0f, 0.0f, 1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
    glm::vec3 outside = corner;  // on a cell edge's line, outside the grid
    outside[a] = float(torus.field.grid.origin[a]) + 20.0f * h;
    const std::string name = fmt::format("along {}", "xyz"[a]);
    add(name + " from a cell edge outside the grid", id, lookingAt({65, 65}, outside, outside - axis, 1.2f, 1e-3f * radius, up), false);
    add(name + " from a cell corner", id, lookingAt({65, 65}, corner, corner - axis, 1.2f, 1e-3f * radius, up), a == 0);
    add(name + " from a cell corner, backwards", id, lookingAt({65, 65}, corner, corner + axis, 1.2f, 1e-3f * radius, up), false);
    RandomCamera ortho = lookingAt({64, 64}, outside, outside - axis, 1.2f, 1e-3f * radius, up);
    ortho.camera = orthographicLike(ortho.camera, 1.1f * radius, 0.01f * radius, 6.0f * radius);
    add(name + ", orthographic", id, ortho, false);
    RandomCamera inside = lookingAt({64, 64}, corner, corner - axis, 1.2f, 1e-3f * radius, up);
    inside.camera = orthographicLike(inside.camera, 1.1f * radius, 1e-4f * radius, 6.0f * radius);
    add(name + ", orthographic from a cell corner", id, inside, a == 1);
  }
  // Along a grid diagonal from a cell corner: the centre ray meets only cell corners (the bricks'
  // walk steps through ties on all three axes).
  for (const float sign : {1.0f, -1.0f}) {
    const glm::vec3 diagonal = sign * glm::vec3(1.0f) / std::sqrt(3.0f);
    const glm::vec3 from = sign > 0.0f ? corner : glm::vec3(torus.field.grid.origin) + 12.0f * h;
    add(fmt::format("along the diagonal {} from a cell corner", sign > 0.0f ? "+" : "-"), id,
        lookingAt({65, 65}, from, from + diagonal, 1.2f, 1e-3f * radius, glm::vec3(0.0f, 1.0f, 0.0f)), false);
    RandomCamera ortho = lookingAt({64, 64}, from, from + diagonal, 1.2f, 1e-3f * radius, glm::vec3(0.0f, 1.0f, 0.0f));
    ortho.camera = orthographicLike(ortho.camera, 0.5f * radius, 1e-4f * radius, 6.0f * radius);
    add(fmt::format("along the diagonal {} from a cell corner, orthographic", sign > 0.0f ? "+" : "-"), id, ortho, false);
  }
  for (const float fov : {150.0f, 170.0f, 178.0f})
    add(fmt::format("fov {} deg from the hole", fov), turn,
        lookingAt({91, 67}, centre + glm::vec3(0.0f, 0.01f, 0.0f), centre + glm::vec3(1.0f, 0.2f, 0.1f), glm::radians(fov),
                  1e-3f * radius, glm::vec3(0.0f, 1.0f, 0.0f)),
        fov == 178.0f);
  struct Shot {
    glm::uvec2 size;
    float fovDegrees, distance;
  };
  for (const Shot& shot : {Shot{{3, 1000}, 40.0f, 2.0f}, Shot{{1000, 3}, 2.0f, 2.0f}, Shot{{90, 70}, 1.0f, 120.0f},
                           Shot{{90, 70}, 0.1f, 1000.0f}})
    add(fmt::format("{}x{}, fov {} deg", shot.size.x, shot.size.y, shot.fovDegrees), turn,
        lookingAt(shot.size, centre + shot.distance * radius * glm::normalize(glm::vec3(0.4f, 0.6f, 1.0f)), centre,
                  glm::radians(shot.fovDegrees), 1e-3f * radius, glm::vec3(0.0f, 1.0f, 0.0f)),
        false);
  glm::mat4 chain(1.0f);
  for (int i = 0; i < 64; ++i)
    chain = chain * glm::rotate(id, 0.05f, glm::normalize(glm::vec3(1.0f, float(i % 3), 0.5f))) *
            glm::scale(id, glm::vec3(1.01f, 0.995f, 1.0f));
  const glm::mat4 model = placeAbout(torus, chain, glm::vec3(0.0f));
  const WorldSphere s = worldSphere(torus, model);
  add("a chain of 64 nodes", model,
      lookingAt({80, 80}, s.center + 2.0f * s.radius * glm::normalize(glm::vec3(1.0f)), s.center, 1.0f, 1e-3f * radius, tilted), false);
  return cases;
}

// Why: the random views keep scales within 0.5-2, fields of view within 15-120 degrees, images
// within 24-140 pixels a side, and never put an eye exactly on a grid plane or a ray exactly
// along an axis. At the limits the same maths meets its ends: a cell 1e3 times longer than wide
// (the proxies' dilation and the near plane's reach measured along the most shrunk axis), a shear
// whose columns keep their length, divisions by a zero ray component in the slab tests and the
// bricks' walk, a wide field of view's pixel footprint. Every cell method and both tracers against
// their references. CI draws the 8 cases marked `ci`; HSDF_LIMIT_VIEWS=all draws all 129, HSDF_LIMIT_VIEWS=TEXT those whose label holds TEXT.
TEST_F(RandomViewsTest, TransformsAndViewsAtTheirLimitsMatchTheReference) {
  const auto torus = bakeAsset("torus", 16);
  ASSERT_NE(torus, nullptr);
  // HSDF_LIMIT_VIEWS=all: every case; any other value: the cases whose label holds it.
  const char* chosen = std::getenv("HSDF_LIMIT_VIEWS");
  const std::string pick = chosen != nullptr ? chosen : "";
  std::vector<Method> methods = cellMethods();
  methods.push_back({"trilinear", hsdf::RenderMethod::TrilinearSphereTrace});
  methods.push_back({"hermite", hsdf::RenderMethod::HermiteSphereTrace});
  int drawn = 0, shown = 0;
  for (const LimitCase& limit : limitCases(*torus)) {
    const bool picked = pick.empty() ? limit.ci : pick == "all" || limit.camera.label.find(pick) != std::string::npos;
    if (!picked) continue;
    shown += expectViewMatches(methods, {{torus, limit.model}}, limit.camera);
    drawn += int(methods.size());
  }
  EXPECT_GE(shown, drawn * 9 / 10) << "most cases must show some surface";
}

}  // namespace
}  // namespace gputest
