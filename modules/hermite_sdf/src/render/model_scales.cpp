#include "render/model_scales.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace hsdf {

namespace {

// Turns columns p and q of `a` in their plane until they are orthogonal (one Jacobi rotation of
// the Gram matrix's (p, q) entry to 0); false when they are orthogonal to double's rounding.
bool orthogonalize(glm::dmat3& a, int p, int q) {
  const double alpha = glm::dot(a[p], a[p]), beta = glm::dot(a[q], a[q]), gamma = glm::dot(a[p], a[q]);
  if (!(std::abs(gamma) > 1e-15 * std::sqrt(alpha * beta))) return false;
  const double zeta = (beta - alpha) / (2.0 * gamma);
  const double t = std::copysign(1.0, zeta) / (std::abs(zeta) + std::sqrt(1.0 + zeta * zeta));
  const double c = 1.0 / std::sqrt(1.0 + t * t), s = c * t;
  const glm::dvec3 ap = a[p];
  a[p] = c * ap - s * a[q];
  a[q] = s * ap + c * a[q];
  return true;
}

}  // namespace

ModelScales modelScales(const glm::mat4& model) {
  glm::dmat3 a{glm::mat3(model)};
  // Converges quadratically: a handful of sweeps reach double's rounding; 32 bounds the loop.
  for (int sweep = 0; sweep < 32; ++sweep) {
    bool turned = false;
    for (const auto& [p, q] : {std::pair{0, 1}, std::pair{0, 2}, std::pair{1, 2}}) turned |= orthogonalize(a, p, q);
    if (!turned) break;
  }
  const double x = glm::length(a[0]), y = glm::length(a[1]), z = glm::length(a[2]);
  return {std::min({x, y, z}), std::max({x, y, z})};
}

}  // namespace hsdf
