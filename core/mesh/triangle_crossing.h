// SPDX-License-Identifier: MIT
// Whether a segment or a triangle passes through a triangle, by orientation tests alone: the
// coarsening's self-intersection check and the remeshing's thin-wall guard ask the same
// question. The check counts ends within rounding of a plane as on it; the guard, stricter,
// does not, so what the guard lets through the check passes too. And whether two triangles on
// one edge fold onto each other: the input's verification and the coarsening's check ask that
// alike, so that an input the verification accepts is not one no coarsening can pass. And
// whether a triangle has zero area: the verification refuses such a triangle, the repair flips
// it away and the remeshing makes none, by this one test.
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

//! Two triangles on one edge fold onto each other when the cosine of the angle between their
//! normals is below -(1 - kFoldedCosineMargin): their sides are less than 1.4e-5 radians
//! (0.0008 degrees) apart. Such a fin is far thinner than the tet mesher tells apart across it
//! (its tolerance is 1e-8 of the diagonal, and a fin's width shrinks to zero at its edge).
constexpr double kFoldedCosineMargin = 1e-10;

//! Do triangles A and B, which share an edge and are oriented alike (they traverse it in
//! opposite directions), fold onto each other (kFoldedCosineMargin)? A flat fold, one lying on
//! the other, is the limit; the test needs no exact arithmetic, as no sign decides it.
bool triangles_fold_onto_each_other(const std::array<Vec3, 3>& A, const std::array<Vec3, 3>& B);

//! Has the triangle with these corners zero area: a repeated corner, or a cross product of two
//! edges at most 1e-12 of the longest edge squared (corners within rounding of one line)?
//! verify_surface() refuses such a triangle, flip_zero_area_slivers() flips it away, and
//! remesh_isotropic() makes none.
bool has_zero_area(const Vec3& a, const Vec3& b, const Vec3& c);

//! The angle between the sides of two such triangles, in degrees (0: folded flat; 180: flat).
double angle_between_sides_deg(const std::array<Vec3, 3>& A, const std::array<Vec3, 3>& B);

}  // namespace dthex
