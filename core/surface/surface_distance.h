// SPDX-License-Identifier: MIT
// How far the hex mesh boundary is from the input surface: the two-sided Hausdorff
// distance the user's geometry error is judged by, and the enclosed volumes.
#pragma once

#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/types.h>

namespace dthex {

struct SurfaceDistance {
  double hausdorff = 0;        //!< max of both one-sided distances
  double to_input_max = 0;     //!< boundary -> input
  double from_input_max = 0;   //!< input -> boundary
  double mean = 0;             //!< mean of boundary -> input over the samples
};

//! Boundary quads split into two triangles each (outward as the quads are).
TriSurface quads_to_triangles(const std::vector<Vec3>& nodes, const std::vector<std::array<int, 4>>& quads);

//! Two-sided distance between surfaces a and b, sampled at vertices, edge midpoints
//! and triangle centroids, measured exactly to the other surface's triangles. b must be
//! closed and consistently oriented (the verified input): its edges are sampled once each.
SurfaceDistance surface_distance(const TriSurface& a, const TriangleBvh& a_bvh, const TriSurface& b,
                                 const TriangleBvh& b_bvh);

//! Signed enclosed volume of a closed, outward-oriented triangle surface.
double enclosed_volume(const TriSurface& surface);

}  // namespace dthex
