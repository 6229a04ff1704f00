#pragma once
// The integer boxes of the bakes' coarse-to-fine descents (the dense field's narrow band over
// samples, the sparse bake over cells): a box far from the surface is skipped whole, one near it is
// halved until its parts are leaves.
#include <glm/glm.hpp>

#include "engine/core/expected.h"

namespace hsdf::detail {

struct IndexBox {
  glm::ivec3 lo;  // inclusive
  glm::ivec3 hi;  // exclusive
};

// visit(part) for each part of `box` with every axis longer than `leaf` halved: 8 parts at most,
// fewer where an axis is not split (it gives one part, not an empty second). Stops at the first
// error.
template <class Visit>
engine::Status forEachHalf(const IndexBox& box, int leaf, Visit&& visit) {
  glm::ivec3 mid = box.hi;
  for (int a = 0; a < 3; ++a)
    if (box.hi[a] - box.lo[a] > leaf) mid[a] = box.lo[a] + (box.hi[a] - box.lo[a]) / 2;
  for (int child = 0; child < 8; ++child) {
    IndexBox part = box;
    bool empty = false;
    for (int a = 0; a < 3; ++a) {
      const bool upper = (child >> a) & 1;
      if (upper && mid[a] == box.hi[a]) empty = true;  // this axis was not split
      part.lo[a] = upper ? mid[a] : box.lo[a];
      part.hi[a] = upper ? box.hi[a] : mid[a];
    }
    if (!empty) ENGINE_TRY(visit(part));
  }
  return {};
}

}  // namespace hsdf::detail
