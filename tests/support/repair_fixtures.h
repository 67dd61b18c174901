// SPDX-License-Identifier: MIT
// Small surfaces for the repair tests.
#pragma once

#include <dthex/mesh/types.h>

namespace dthex::testing {

//! The unit cube [0,1]^3 as 8 vertices (vertex i at (i&1, i>>1&1, i>>2&1)) and 12 outward
//! triangles, two per face.
inline TriSurface unit_cube() {
  TriSurface s;
  for (int i = 0; i < 8; ++i) s.points.push_back(Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    s.triangles.push_back({q[0], q[1], q[2]});
    s.triangles.push_back({q[0], q[2], q[3]});
  }
  return s;
}

}  // namespace dthex::testing
