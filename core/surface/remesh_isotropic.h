// SPDX-License-Identifier: MIT
// Before coarsening: an input made of needle triangles (a CAD export of a rod or a plate,
// whose flat faces are long strips between feature lines) gives the coarsening nothing to
// work with. Its collapses move vertices along the existing edges, so the strips stay
// strips, every needle of the coarse surface becomes a sliver tet, and its hexes cannot be
// made valid.
// Such an input is remeshed first with even triangles of one edge length: Botsch and Kobbelt,
// "A remeshing approach to multiresolution modeling" (SGP 2004): split long edges, collapse
// short ones, flip towards valence 6, relax each vertex in its tangent plane, and put it
// back on the input surface; feature lines keep their vertices on them, corners stay.
// No edit may leave a triangle of zero area, turned over, or through the other side of a thin
// wall (an input triangle facing away from it): on a thin wall a chord can dip through the
// other side where the wall curves (the steep cone of an ear drum's umbo), and two vertices put
// back on the input can land on one point (at the tip of a pit).
#pragma once

#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/types.h>

#include <functional>

namespace dthex {

struct RemeshIsotropicOptions {
  //! Edge length aimed at; 0 = automatic (remesh_edge_length).
  double edge_length = 0;
  //! Split-collapse-flip-relax rounds.
  int rounds = 8;
  //! Feature angle (degrees between triangle normals), as features.h.
  double feature_angle_deg = 60.0;
  //! Called with the fraction of rounds done.
  std::function<void(double)> progress;
};

struct RemeshIsotropicReport {
  size_t triangles_before = 0, triangles_after = 0;
  double edge_length = 0;
  double min_angle_before_deg = 0, min_angle_after_deg = 0;  //!< smallest triangle angle
  //! Edits (splits onto the input, collapses, flips, moves) not made because a triangle would
  //! have passed through the other side of a thin wall.
  size_t refused_crossings = 0;
  //! Vertices left on a chord of the input, off it: putting them on it would have turned a
  //! triangle over or through the other side of the wall.
  size_t off_input_vertices = 0;
  //! The mesh grew past 16 times the triangles the length asks for, plus twice the input's
  //! (well above the peak of a needle input's early rounds): the remeshing stopped and
  //! returned the input unchanged.
  bool gave_up = false;
};

//! Share of the triangles that are needles: longest edge squared over twice the area above
//! 10 (an equilateral triangle has 1.15; a right triangle of legs 1 and 0.1, 10).
double needle_share(const TriSurface& surface);

//! Needles of at least this share (one triangle in 200) call for remeshing at --remesh auto:
//! each needle left in the coarse surface is the face of a sliver tet. CAD exports of rods
//! and plates are mostly needles, scans have none or nearly none unless fans closed their
//! holes (docs/METHOD.md section 2, Reading and verifying the input).
constexpr double kRemeshNeedleShare = 0.005;

//! The automatic edge length: that of an equilateral triangle of the input's mean area (the
//! remeshed surface has about as many triangles as the input), but no more than the inner-ball
//! radius (half the wall thickness) at the thinner 5% of the vertices, so that the coarsening,
//! which cannot refine, can still size thin walls by their thickness; and no less than keeps
//! the result within `max_triangles`. 0 = automatic: 100 times the input's triangles, at
//! least 1,000 and at most 400,000, so that a spike, whose tip
//! has no thickness, does not turn a few triangles into hundreds of thousands.
//! `surface_bvh`, when given, is a tree over `surface` the caller already has.
double remesh_edge_length(const TriSurface& surface, size_t max_triangles = 0,
                          const TriangleBvh* surface_bvh = nullptr);

//! The remeshed surface of a verified (closed, manifold, consistently oriented) surface.
//! Every vertex lies on the input surface (but RemeshIsotropicReport::off_input_vertices, on a
//! chord of it), a vertex on a feature line on that line; the result keeps the orientation. The caller verifies it (a fold is possible in principle) and
//! judges it: where feature lines meet at a hair's angle (a spike's tip), even triangles are
//! impossible and the smallest angle can get worse.
//! `surface_bvh`, when given, is a tree over `surface` the caller already has (else one is built).
TriSurface remesh_isotropic(const TriSurface& surface, const RemeshIsotropicOptions& options = {},
                            RemeshIsotropicReport* report = nullptr, const TriangleBvh* surface_bvh = nullptr);

}  // namespace dthex
