// The methods' one name table (hermite_sdf/render/renderable.h): every method in kRenderMethods once,
// each name parsing back to its method, the names the command lines and settings files use.
#include "hermite_sdf/render/renderable.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

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

}  // namespace
}  // namespace hsdf
