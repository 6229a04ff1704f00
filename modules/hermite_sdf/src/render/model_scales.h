#pragma once
// How much a model matrix stretches lengths: the least and the most, its linear part's singular
// values. The cells' proxies are dilated by a screen-space margin measured in the object's cells
// along its most shrunk direction (proxy_dilation.glsl, the tiles, the near cells' reach in
// cell_draws.cpp): a sheared matrix's shortest column is no bound on that (two columns of length 1
// at cos 0.9995 shrink some direction to 1/45).
#include <glm/glm.hpp>

namespace hsdf {

struct ModelScales {
  double smallest = 0.0;  // sigma_min: no world length is less than this times its object length
  double largest = 0.0;   // sigma_max: none is more than this times it
};

// The singular values of mat3(model), in double: one-sided Jacobi rotations (Hestenes) turn the
// columns until they are orthogonal; their lengths are then the singular values. Columns that are
// orthogonal already (axis scales, a rotation times axis scales) are the lengths of the matrix's
// own columns, so unsheared objects keep the dilation their shortest column gave them.
ModelScales modelScales(const glm::mat4& model);

}  // namespace hsdf
