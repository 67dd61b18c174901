// SPDX-License-Identifier: MIT
// The 26 unit directions from a cell of a cubic grid to its neighbours (faces, edges, corners),
// in a fixed order: the trial steps of the derivative-free pattern searches that place a tet
// point where the worst tet around it is best (relax_interior_points, split_crowded_vertices),
// with the step halved when none helps.
#pragma once

#include <dthex/mesh/types.h>

#include <vector>

namespace dthex {

inline const std::vector<Vec3>& grid_directions() {
  static const std::vector<Vec3> directions = [] {
    std::vector<Vec3> out;
    for (int i = -1; i <= 1; ++i)
      for (int j = -1; j <= 1; ++j)
        for (int k = -1; k <= 1; ++k)
          if (i || j || k) out.push_back(Vec3(i, j, k).normalized());
    return out;
  }();
  return directions;
}

}  // namespace dthex
