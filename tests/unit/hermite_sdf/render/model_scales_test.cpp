// The model matrix's least and most stretch (src/render/model_scales.cpp), which the cells'
// proxies are dilated by: against the closed-form eigenvalues of M^T M, on random sheared matrices.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "render/model_scales.h"

namespace {

// The eigenvalues of the symmetric G = M^T M in closed form (the trigonometric solution of its
// characteristic cubic, in long double), smallest first: an answer found without rotations.
std::array<long double, 3> gramEigenvalues(const glm::mat3& m) {
  long double g[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      g[i][j] = 0.0L;
      for (int r = 0; r < 3; ++r) g[i][j] += (long double)m[i][r] * (long double)m[j][r];
    }
  const long double q = (g[0][0] + g[1][1] + g[2][2]) / 3.0L;
  const long double off = g[0][1] * g[0][1] + g[0][2] * g[0][2] + g[1][2] * g[1][2];
  const long double p = std::sqrt(((g[0][0] - q) * (g[0][0] - q) + (g[1][1] - q) * (g[1][1] - q) +
                                   (g[2][2] - q) * (g[2][2] - q) + 2.0L * off) / 6.0L);
  if (p == 0.0L) return {q, q, q};
  long double b[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) b[i][j] = (g[i][j] - (i == j ? q : 0.0L)) / p;
  const long double det = b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1]) -
                          b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0]) +
                          b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0]);
  const long double phi = std::acos(std::clamp(det / 2.0L, -1.0L, 1.0L)) / 3.0L;
  const long double largest = q + 2.0L * p * std::cos(phi);
  const long double smallest = q + 2.0L * p * std::cos(phi + 2.0L * std::numbers::pi_v<long double> / 3.0L);
  return {smallest, 3.0L * q - largest - smallest, largest};
}

// A rotation times axis scales times a shear that leans column `b` towards column `a` until their
// cosine is `c`, then a random rotation.
glm::mat4 randomSheared(std::mt19937& rng, double c) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), scale(0.01f, 100.0f);
  std::uniform_int_distribution<int> axis(0, 2);
  const int a = axis(rng), b = (a + 1 + axis(rng) % 2) % 3;
  glm::mat4 shear(1.0f);
  shear[b] = glm::vec4(0.0f);
  shear[b][a] = float(c);
  shear[b][b] = float(std::sqrt(1.0 - c * c));
  const glm::vec3 around = glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)) + glm::vec3(1e-3f));
  return glm::rotate(glm::mat4(1.0f), 3.0f * unit(rng), around) * shear *
         glm::scale(glm::mat4(1.0f), glm::vec3(scale(rng), scale(rng), scale(rng)));
}

float shortestColumn(const glm::mat4& m) {
  return std::min({glm::length(glm::vec3(m[0])), glm::length(glm::vec3(m[1])), glm::length(glm::vec3(m[2]))});
}

}  // namespace

// Why: the proxies' dilation divides by the model's smallest scale. A sheared matrix's shortest
// column overstates it (by 45x at cos 0.9995, 316x at 0.99999): the dilation then falls below the
// rasterizer's snapping along the thin direction. The singular values must match an independent
// solution to near double's precision on sheared, scaled and turned matrices.
TEST(ModelScales, AreTheSingularValuesOfShearedMatrices) {
  std::mt19937 rng(20261207);
  for (const double c : {0.0, 0.5, 0.9, 0.9995, 0.99999})
    for (int i = 0; i < 200; ++i) {
      const glm::mat4 m = randomSheared(rng, c);
      const auto lambda = gramEigenvalues(glm::mat3(m));
      const hsdf::ModelScales s = hsdf::modelScales(m);
      SCOPED_TRACE(testing::Message() << "cos " << c << ", matrix " << i);
      // Within float's rounding (the GPU gets a float): the closed form itself loses digits of the
      // smallest eigenvalue where M^T M's condition reaches 1e13 (scales 0.01-100 times the shear).
      EXPECT_NEAR(s.smallest, double(std::sqrt(lambda[0])), 1e-7 * double(std::sqrt(lambda[0])));
      EXPECT_NEAR(s.largest, double(std::sqrt(lambda[2])), 1e-12 * double(std::sqrt(lambda[2])));
    }
}

// Why: the limit views' shear (columns of length 1 at cosine c) shrinks the direction between the
// two columns to sqrt(1 - c), 1/45 at c = 0.9995, while every column keeps length 1.
TEST(ModelScales, AShearOfUnitColumnsShrinksToTheSquareRootOfOneLessTheCosine) {
  for (const double c : {0.9, 0.9995, 0.99999}) {
    glm::mat4 shear(1.0f);
    shear[1] = glm::vec4(float(c), float(std::sqrt(1.0 - c * c)), 0.0f, 0.0f);
    const hsdf::ModelScales s = hsdf::modelScales(shear);
    // The float column's length and cosine (1e-8 off unit length moves sqrt(1 - c) by 1e-3 at
    // c = 0.99999): the 2x2 Gram matrix [[1, c], [c, l^2]]'s eigenvalues.
    const long double cf = shear[1][0], l2 = (long double)cf * cf + (long double)shear[1][1] * shear[1][1];
    const long double mid = 0.5L * (1.0L + l2), half = std::sqrt(0.25L * (1.0L - l2) * (1.0L - l2) + cf * cf);
    EXPECT_NEAR(s.smallest, double(std::sqrt(mid - half)), 1e-7 * double(std::sqrt(mid - half))) << "cos " << c;
    EXPECT_NEAR(s.largest, double(std::sqrt(mid + half)), 1e-12) << "cos " << c;
    EXPECT_NEAR(s.smallest, std::sqrt(1.0 - c), 2e-3 * std::sqrt(1.0 - c)) << "cos " << c;
  }
}

// Why: unsheared objects (axis scales, turned or not) must keep the dilation their shortest column
// gave them: the same float, so that their images and counts do not change.
TEST(ModelScales, UnshearedMatricesKeepTheirShortestColumn) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), scale(1e-3f, 1e3f);
  for (int i = 0; i < 500; ++i) {
    const glm::vec3 axes(scale(rng), scale(rng), scale(rng));
    const glm::mat4 scaled = glm::scale(glm::mat4(1.0f), axes * (i % 2 ? -1.0f : 1.0f));
    const hsdf::ModelScales s = hsdf::modelScales(scaled);
    EXPECT_EQ(s.smallest, double(std::min({axes.x, axes.y, axes.z})));
    EXPECT_EQ(s.largest, double(std::max({axes.x, axes.y, axes.z})));
    const glm::vec3 around = glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)) + glm::vec3(1e-3f));
    const glm::mat4 turned = glm::rotate(glm::mat4(1.0f), 3.0f * unit(rng), around) * scaled;
    const hsdf::ModelScales t = hsdf::modelScales(turned);  // float's rotation: columns orthogonal to ~1e-7
    EXPECT_NEAR(t.smallest, double(shortestColumn(turned)), 1e-6 * t.smallest) << i;
  }
}
