// SPDX-License-Identifier: MIT
// The closest pair of triangles that belong to different parts of a surface (two bodies, a
// body and its cavity, or two places of one body that share no corner). A tet mesher tells
// two facets apart only down to its tolerance: closer than that, TetGen reports a
// self-intersection where there is none, without saying where. verify_surface() uses this to
// refuse such surfaces first, naming the place; tetrahedralize() to say where it failed.
#pragma once

#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/types.h>

#include <functional>
#include <limits>

namespace dthex {

struct TrianglePairDistance {
  int a = -1, b = -1;  //!< the triangles, a < b; -1 when no pair was found
  double distance = std::numeric_limits<double>::infinity();
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero();  //!< the closest points, on a and on b
};

//! Distance and closest points of two triangles, from the six corner-to-triangle and nine
//! edge-to-edge distances: exact for triangles that do not cross (for crossing ones it is an
//! upper bound on the true distance, 0).
TrianglePairDistance triangle_distance(const std::array<Vec3, 3>& A, const std::array<Vec3, 3>& B);

//! The closest pair a < b of the tree's triangles with separate(a, b) true that lie at most
//! max_distance apart (ties: the lower ids), found by box queries inflated by max_distance;
//! triangle -1 when there is none. The result does not depend on the thread count.
TrianglePairDistance closest_separate_pair(const TriangleBvh& tree, double max_distance,
                                           const std::function<bool(int, int)>& separate);

}  // namespace dthex
