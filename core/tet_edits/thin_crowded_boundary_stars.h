// SPDX-License-Identifier: MIT
// Before THex: fewer tets at the boundary vertices that too many share for the solid angle the
// surface leaves them. THex gives every tet at a vertex one hex corner there, spanned by the
// tet's own three edges, so the k corners at a boundary vertex share the solid angle W inside
// the surface there (2 pi on a flat wall, 2 theta on a crease of dihedral angle theta, less at
// a knife edge or the tip of a ridge); the narrowest gets at most W / k, and a corner of solid
// angle w has at most the scaled Jacobian of the equilateral corner of that solid angle
// (corner_scaled_jacobian_bound). The smoothing of the hexes moves nodes, not k, so such a
// vertex bounds the worst hex around it whatever the smoother does.
//
// k falls by two with each interior edge v u taken out, in one of two ways: an edge removal
// (edge_removal.h: the tets around v u are replaced by those joining v and u to a
// triangulation of the ring around the edge, k - 2 of them at v), or a merge of the interior
// neighbour u into another interior neighbour w of v (an edge contraction, as
// collapse_interior_vertices does: the tets with both u and w go, w replaces u in the rest).
// A change is taken when every new tet is positive, no new edge joins two boundary vertices
// (the rule of split_surface_tets), its worst tet keeps min_shape_ratio of the worst it
// replaces, and the lowest bound among the boundary vertices whose tet count it changes rises
// (a removal hands tets to the ring's boundary vertices; a merge only takes tets away). The
// boundary faces and the boundary points stay as they are, so the mesh stays conforming with
// the same boundary; merged interior points are dropped.
#pragma once

#include <dthex/mesh/types.h>

namespace dthex {

struct ThinCrowdedBoundaryStarsOptions {
  //! Boundary vertices whose corner bound (the equilateral corner of W / k) is below this
  //! scaled Jacobian are thinned, the lowest first. Higher thins more stars, each removal
  //! reshaping a few tets around them: at 0.35 the worst hex of the shared fandisk rose from
  //! 0.275 to 0.301, of skull_hollow from 0.278 to 0.284, of the peer fertility from 0.392 to
  //! 0.400, and no other mesh changed; with edge removals alone, at 0.4 the fandisk reached
  //! 0.299 and at 0.45 the pelvis fell from 0.374 to 0.363 (the bound is reckoned on the coarse
  //! surface, whose solid angles the projection changes).
  double target_bound = 0.35;
  //! A change (removal or merge) is taken when its worst tet's Verdict shape is at least this
  //! fraction of the worst shape among the tets it replaces (THex hands a tet's shape on to its
  //! hexes); at 0.8 skull_hollow's worst hex fell from 0.284 to 0.254.
  double min_shape_ratio = 0.9;
  //! ... and at least this (absolute floor).
  double min_shape = 0.1;
  //! Edge removals are tried for edges with at most this many tets around them (the
  //! triangulations of the ring to search grow fast with it).
  int max_ring = 7;
  //! Also merge an interior neighbour u of the vertex into another interior vertex w (an edge
  //! contraction): the vertex loses two tets when it has both u and w as neighbours, and a
  //! boundary vertex beside it that has u but not w gains none, where an edge removal hands
  //! tets to the ring's boundary vertices (a row of crowded vertices along a knife edge).
  bool merge_interior_neighbours = true;
  //! A merge is not taken when w would end in more tets than this (as in
  //! collapse_interior_vertices).
  int max_tets_at_merged_vertex = 40;
};

struct ThinCrowdedBoundaryStarsReport {
  size_t crowded_before = 0, crowded_after = 0;  //!< boundary vertices with a bound below the target
  double lowest_bound_before = 1, lowest_bound_after = 1;  //!< over all boundary vertices
  size_t edges_removed = 0;  //!< by edge removals
  size_t merged = 0;         //!< interior points merged into a neighbour
  size_t tets_before = 0, tets_after = 0;
};

//! The scaled Jacobian of the corner whose three edges meet at equal angles and span the
//! solid angle w (steradians): the best any corner of that solid angle reaches. 1 from
//! w = pi / 2 (the cube's corner) on, 0 at w = 0.
double corner_scaled_jacobian_bound(double w);

//! Removes, in place, interior edges at the boundary vertices whose corner bound is below
//! options.target_bound, as the header says. Tets stay positively oriented; the points of
//! merged vertices are removed and the indices of tets and boundary faces renumbered. For a
//! mesh of one material (tet_region empty), as the pipeline hands each region on.
ThinCrowdedBoundaryStarsReport thin_crowded_boundary_stars(TetMesh& mesh, const ThinCrowdedBoundaryStarsOptions& options = {});

}  // namespace dthex
