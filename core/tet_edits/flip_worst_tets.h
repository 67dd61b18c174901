// SPDX-License-Identifier: MIT
// Before THex: flips around the worst tets (those below a shape), taken only where they raise
// the worst tet they touch. THex hands a tet's shape on to its four hexes, and on a thin wall
// the worst tets are often a boundary face with an interior point close above it, or a
// sliver between two boundary faces, that moving the interior point (relax_interior_points)
// cannot open because its other tets have no room either. A different connectivity can: an
// edge removal (edge_removal.h) of one of the bad tet's edges, or a 2-3 flip of one of its
// faces (the two tets on an interior face a b c, (a b c d) and (c b a e), become the three
// around the new edge d e). Both keep the rule of split_surface_tets: no new edge joins two
// boundary vertices, no new face has three. Every new tet is positive and the flipped tets'
// union is unchanged, so the mesh stays conforming with the same boundary faces; no point is
// added or moved.
#pragma once

#include <dthex/mesh/types.h>

namespace dthex {

struct FlipWorstTetsOptions {
  //! Tets below this Verdict shape are the ones whose edges and faces are flipped.
  double below = 0.1;
  //! Edge removals are tried for edges with at most this many tets around them.
  int max_ring = 7;
  //! Passes over the bad tets; stops early when a pass flips nothing.
  int max_passes = 4;
};

struct FlipWorstTetsReport {
  size_t edge_removals = 0, face_flips = 0;
  double worst_before = 0, worst_after = 0;  //!< worst Verdict tet shape of the mesh
};

//! Flips, in place, around the tets below options.below where a flip raises the worst of
//! the tets it replaces. The worst tet of the mesh never falls.
FlipWorstTetsReport flip_worst_tets(TetMesh& mesh, const FlipWorstTetsOptions& options = {});

}  // namespace dthex
