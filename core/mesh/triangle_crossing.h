// SPDX-License-Identifier: MIT
// Whether a segment or a triangle passes through a triangle, by orientation tests alone: the
// coarsening's self-intersection check and the remeshing's thin-wall guard ask the same
// question and must agree on it.
#pragma once

#include <dthex/mesh/types.h>

#include <array>

namespace dthex {

//! Does segment pq cross triangle abc? Touching counts (an end on the triangle, the segment
//! through its edge or corner); a segment in the triangle's plane does not.
bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c);

//! Do triangles A and B cross: an edge of one crosses the other (segment_crosses_triangle)?
//! Closed triangles that meet do so along a segment with an end on the boundary of one of
//! them, so this misses only coplanar overlaps.
bool triangles_cross(const std::array<Vec3, 3>& A, const std::array<Vec3, 3>& B);

}  // namespace dthex
