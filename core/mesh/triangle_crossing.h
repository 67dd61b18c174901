// SPDX-License-Identifier: MIT
// Whether a segment or a triangle passes through a triangle, by orientation tests alone: the
// coarsening's self-intersection check and the remeshing's thin-wall guard ask the same
// question. The check counts ends within rounding of a plane as on it; the guard, stricter,
// does not, so what the guard lets through the check passes too.
#pragma once

#include <dthex/mesh/types.h>

#include <array>

namespace dthex {

//! A point this close to a plane, as a fraction of the largest coordinate in the test, is on it
//! (the `on_plane` of the tests below): about 450 times double precision's unit roundoff, far
//! above the rounding of coordinates and of the cross product, far below any distance a
//! mesher resolves. On a flat face off the axes the points lie on its plane only to within
//! their coordinates' last bits; two triangles side by side on it must not cross by that noise.
constexpr double kWithinRoundingOfPlane = 1e-13;

//! Does segment pq cross triangle abc? Touching counts (an end on the triangle, the segment
//! through its edge or corner); a segment in the triangle's plane does not, nor one whose ends
//! are both within `on_plane` x the largest coordinate of it (0: only exactly in it).
bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c,
                              double on_plane = 0);

//! Do triangles A and B cross: an edge of one crosses the other (segment_crosses_triangle)?
//! Closed triangles that meet do so along a segment with an end on the boundary of one of
//! them, so this misses only coplanar overlaps.
bool triangles_cross(const std::array<Vec3, 3>& A, const std::array<Vec3, 3>& B, double on_plane = 0);

}  // namespace dthex
