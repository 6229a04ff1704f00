// The capture's PNG charts: a chart is an image of the asked size with each series drawn in its
// colour, and points a log axis cannot show are skipped rather than drawn at infinity.
#include "charts.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "engine/core/image_io.h"

namespace capture {
namespace {

int countColor(const engine::LoadedImage& image, glm::u8vec3 c) {
  int n = 0;
  for (std::size_t i = 0; i < image.rgba.size(); i += 4)
    n += image.rgba[i] == c.r && image.rgba[i + 1] == c.g && image.rgba[i + 2] == c.b;
  return n;
}

// Tricky: the second series has a zero and a NaN on log axes; they must be skipped (no crash,
// nothing drawn for them) while its valid points still show.
TEST(Charts, SeriesAreDrawnInTheirColours) {
  const auto path = std::filesystem::path(testing::TempDir()) / "chart_test.png";
  Chart chart;
  chart.series.push_back({"a", seriesColor(0), {{16, 1.0}, {32, 2.0}, {64, 4.0}}});
  chart.series.push_back({"b", seriesColor(1), {{16, 0.0}, {32, std::nan("")}, {64, 3.0}, {128, 9.0}}});
  ASSERT_TRUE(writeChart(path, chart, 300, 200).ok());
  auto image = engine::readPng(path);
  ASSERT_TRUE(image.ok()) << image.error().message;
  EXPECT_EQ(image->width, 300u);
  EXPECT_EQ(image->height, 200u);
  EXPECT_GT(countColor(*image, seriesColor(0)), 100);
  EXPECT_GT(countColor(*image, seriesColor(1)), 100);
  EXPECT_EQ(countColor(*image, seriesColor(2)), 0);
  EXPECT_NE(seriesColor(0), seriesColor(1));
  EXPECT_EQ(colorHex({255, 0, 16}), "#ff0010");
}

}  // namespace
}  // namespace capture
