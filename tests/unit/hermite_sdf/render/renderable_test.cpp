// The methods' one name table (hermite_sdf/render/renderable.h): every method in kRenderMethods once,
// each name parsing back to its method, the names the command lines and settings files use; and
// the module's one rule of when its features warm (hasSdfObjects).
#include "hermite_sdf/render/renderable.h"

#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <string>

#include "engine/ecs/registry.h"
#include "engine/scene/transform.h"

namespace hsdf {
namespace {

TEST(RenderMethodNames, EveryMethodParsesBackFromItsName) {
  std::set<std::string> names;
  for (const RenderMethod method : kRenderMethods) {
    EXPECT_EQ(parseRenderMethod(renderMethodName(method)), method) << renderMethodName(method);
    names.insert(renderMethodName(method));
  }
  EXPECT_EQ(names.size(), std::size(kRenderMethods)) << "two methods share a name";
  EXPECT_FALSE(names.contains("?")) << "a method without a name";
}

TEST(RenderMethodNames, TheNamesOfTheCommandLine) {
  EXPECT_EQ(parseRenderMethod("cells"), RenderMethod::Cells);
  EXPECT_EQ(parseRenderMethod("trilinear"), RenderMethod::TrilinearSphereTrace);
  EXPECT_EQ(parseRenderMethod("hermite"), RenderMethod::HermiteSphereTrace);
  EXPECT_EQ(parseRenderMethod("cells-runs"), RenderMethod::CellRuns);
  EXPECT_EQ(parseRenderMethod("cell-bricks"), RenderMethod::CellBricks);
}

TEST(RenderMethodNames, UnknownNamesAreRefused) {
  EXPECT_FALSE(parseRenderMethod("Cells").has_value()) << "case-sensitive, as the command line";
  EXPECT_FALSE(parseRenderMethod("mesh").has_value()) << "the triangles are no SDF method";
  EXPECT_FALSE(parseRenderMethod("").has_value());
  EXPECT_FALSE(parseRenderMethod("?").has_value());
}

// Why: the cells and the tracers warm the pipelines a switch of method binds from the second frame
// with any object of the module, whichever feature draws it (the cells did not while only a tracer
// drew). An entity without an asset or without a WorldTransform is drawn by neither; one of any
// method, in view or not, counts.
TEST(HasSdfObjects, AnyPlacedRenderableWithAnAssetOfAnyMethod) {
  engine::ecs::Registry registry;
  EXPECT_FALSE(hasSdfObjects(registry)) << "an empty registry";
  const engine::ecs::Entity entity = registry.create();
  registry.emplace<HermiteSdfRenderable>(entity);
  registry.emplace<engine::scene::WorldTransform>(entity);
  EXPECT_FALSE(hasSdfObjects(registry)) << "no asset: nothing to draw";
  const engine::ecs::Entity unplaced = registry.create();
  registry.emplace<HermiteSdfRenderable>(unplaced).asset = std::make_shared<const SdfAsset>();
  EXPECT_FALSE(hasSdfObjects(registry)) << "no WorldTransform: not drawn";
  for (const RenderMethod method : kRenderMethods) {
    HermiteSdfRenderable& renderable = registry.get<HermiteSdfRenderable>(entity);
    renderable.asset = std::make_shared<const SdfAsset>();
    renderable.method = method;
    EXPECT_TRUE(hasSdfObjects(registry)) << renderMethodName(method);
  }
}

}  // namespace
}  // namespace hsdf
