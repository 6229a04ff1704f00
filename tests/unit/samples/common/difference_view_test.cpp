// The difference view's numbers and heat map (samples/common/difference_view.h) from synthetic
// normals frames: known angles in, known degrees out. No GPU (the Viewer tests draw real ones).
#include <gtest/gtest.h>

#include <cmath>

#include "difference_view.h"

namespace samples {
namespace {

// The shader's DEBUG_VIEW_NORMALS colour (0.5 n + 0.5) stored in an sRGB target.
void putNormal(NormalsFrame& frame, std::size_t i, glm::vec3 n) {
  for (int c = 0; c < 3; ++c) {
    const double v = 0.5 * double(n[c]) + 0.5;
    const double s = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
    frame.rgba[4 * i + std::size_t(c)] = std::uint8_t(std::lround(s * 255.0));
  }
  frame.rgba[4 * i + 3] = 255;
  frame.visibility[i] = {1u, 0u};
}

NormalsFrame emptyFrame(std::size_t pixels) {
  NormalsFrame frame;
  frame.rgba.assign(pixels * 4, 0);
  frame.visibility.assign(pixels, glm::uvec2(0));
  return frame;
}

glm::vec3 tilted(float degrees) {
  const float r = glm::radians(degrees);
  return {0.0f, std::sin(r), std::cos(r)};
}

// Tricky: the angles must come from decoded normals (sRGB undone, not the bytes compared as if
// linear: that would make 10 degrees read as ~7), with 8-bit quantization kept under a degree;
// identical bytes are exactly 0; a pixel covered by one method only is counted apart, not as an
// angle; background is neither.
TEST(DifferenceView, AnglesAndCoverageOfKnownNormals) {
  NormalsFrame a = emptyFrame(6), b = emptyFrame(6);
  putNormal(a, 0, {0.0f, 0.0f, 1.0f});
  putNormal(b, 0, {0.0f, 0.0f, 1.0f});
  putNormal(a, 1, {0.0f, 0.0f, 1.0f});
  putNormal(b, 1, {1.0f, 0.0f, 0.0f});
  putNormal(a, 2, {0.0f, 0.0f, 1.0f});
  putNormal(b, 2, tilted(10.0f));
  putNormal(a, 3, glm::normalize(glm::vec3(-1.0f, 2.0f, 0.5f)));
  putNormal(b, 3, glm::normalize(glm::vec3(-1.0f, 2.0f, 0.5f)));
  putNormal(a, 4, {0.0f, 1.0f, 0.0f});  // only a
  const auto d = compareNormals(a, b, 3, 2);
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_EQ(d->degrees[0], 0.0f);
  EXPECT_NEAR(d->degrees[1], 90.0, 1.0);
  EXPECT_NEAR(d->degrees[2], 10.0, 1.0);
  EXPECT_EQ(d->degrees[3], 0.0f);
  EXPECT_EQ(d->degrees[4], -1.0f);
  EXPECT_EQ(d->degrees[5], -2.0f);
  EXPECT_EQ(d->coveredBoth, 4u);
  EXPECT_EQ(d->coveredEither, 5u);
  EXPECT_EQ(d->coverageDiffers, 1u);
  EXPECT_DOUBLE_EQ(d->coverageDiffersShare(), 0.2);
  EXPECT_NEAR(d->meanDegrees, (double(d->degrees[1]) + double(d->degrees[2])) / 4.0, 1e-9);
  EXPECT_EQ(d->maxDegrees, double(d->degrees[1]));
}

// Tricky: frames of another size than the one given (a resize between the two read-backs) must be
// refused with the sizes named, not read out of bounds.
TEST(DifferenceView, SizeMismatchIsAnError) {
  const auto d = compareNormals(emptyFrame(6), emptyFrame(5), 3, 2);
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("is not 3x2"), std::string::npos) << d.error().message;
}

// Tricky: the heat map's colours must follow the legend: 0 blue, half the range green, the range
// and beyond red (clamped, not wrapped), coverage differences white, background dark.
TEST(DifferenceView, HeatMapFollowsTheLegend) {
  NormalDifference d;
  d.width = 6;
  d.height = 1;
  d.degrees = {0.0f, 5.0f, 10.0f, 80.0f, -1.0f, -2.0f};
  const std::vector<std::uint8_t> rgba = heatMapImage(d, 10.0f);
  ASSERT_EQ(rgba.size(), 24u);
  auto pixel = [&](int i) { return glm::ivec3(rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]); };
  EXPECT_GT(pixel(0).b, 200);
  EXPECT_LT(pixel(0).r, 10);
  EXPECT_GT(pixel(1).g, 200);
  EXPECT_GT(pixel(2).r, 200);
  EXPECT_LT(pixel(2).b, 10);
  EXPECT_EQ(pixel(3), pixel(2));
  EXPECT_EQ(pixel(4), glm::ivec3(255));
  EXPECT_LT(pixel(5).r, 50);
  EXPECT_EQ(pixel(5), glm::ivec3(pixel(5).r));
}

}  // namespace
}  // namespace samples
