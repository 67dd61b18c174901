// SPDX-License-Identifier: MIT
// Wall thickness of a closed surface at its vertices, for sizing. Curvature alone sizes a
// thin wall (a skull vault, a pelvis wing) by its large radius, so its coarse triangles
// grow many times wider than the wall is thick; the tets then span the wall with every
// vertex on the boundary, and their hexes cannot all stay valid once projected.
//
// The measure: the radius of the largest ball inside the surface that touches it at the
// vertex and holds no point of the opposite wall, found by shrinking the ball along the
// inward normal (Ma et al., "3D medial axis point approximation using nearest neighbors
// and the normal field", 2012). Only triangles facing back towards the vertex count as the
// opposite wall: the faces next to a convex edge would otherwise shrink the ball to nothing
// along every feature line of a CAD part.
#pragma once

#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/types.h>

#include <vector>

namespace dthex {

struct WallThicknessOptions {
  //! A triangle belongs to the opposite wall when its normal turns more than this from the
  //! vertex normal (degrees).
  double opposite_angle_deg = 120.0;
  //! Shrinking steps per vertex; each is one closest-point query.
  int max_steps = 30;
};

//! Per vertex of `surface` (closed; oriented outward or inward, the enclosed volume's sign
//! tells): the radius of the inner ball described above, at most `start_radius[v]`. Starting
//! at the radius that matters, a ball that already holds no opposite wall ends the search
//! after one query, so "is the wall thinner than this?" is cheap. Vertices whose start
//! radius is not a positive finite number are returned unchanged without a query.
std::vector<double> inner_wall_radii(const TriSurface& surface, const TriangleBvh& bvh,
                                     const std::vector<double>& start_radius,
                                     const WallThicknessOptions& options = {});

//! The wall thickness of a membrane (a surface that is mostly two close sheets): the median
//! of twice inner_wall_radii over the vertices whose ball, started at `start_radius`, met the
//! opposite wall; 0 when none did. Walls thicker than 2 x start_radius are not seen.
double median_wall_thickness(const TriSurface& surface, const TriangleBvh& bvh, double start_radius,
                             const WallThicknessOptions& options = {});

}  // namespace dthex
