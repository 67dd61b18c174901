// SPDX-License-Identifier: MIT
// After smoothing: take out the folds of the boundary into the mesh's own volume
// (boundary_overlap.h). Projection puts each boundary node on the input surface by itself,
// and where that surface turns much faster than the coarse facet over it, the quads of one
// facet no longer lie side by side there: where a facet lands on a crease facing well away
// from it, the boundary quads of two face-neighbour hexes fold over each other at their
// shared edge; at a coarse vertex where two facets meet at a wide angle a tiny quad ends up
// turned over, its probe inside its own hex; on a flap thinner than a hex, the quads of two
// coarse facets land on the same side of it, which the boundary then covers twice. Every
// hex stays valid, so neither the untangler nor the smoother, which see one hex at a time,
// can notice. Here the nodes around each fold move (boundary nodes sliding on the input
// surface, and where that is not enough leaving it by a bounded distance; interior nodes
// freely) to push each folded quad's probe point out of the hex that holds it and to turn
// turned-over quads back, never letting a hex fall below a scaled-Jacobian floor. Meshes
// without folds are not touched (docs/METHOD.md section 6, Fitting the boundary, step 7).
#pragma once

#include <dthex/hexes/boundary_overlap.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/types.h>

#include <array>
#include <vector>

namespace dthex {

struct RepairBoundaryFoldsOptions {
  //! Rings of hexes (through shared nodes) around the folded quads' hexes and the hexes
  //! that hold their probes whose nodes may move; grown one at a time up to `max_rings`
  //! while folds remain and the last ring count removed one (else the next phase starts).
  int rings = 1;
  int max_rings = 4;
  //! Sweeps over a region's nodes per ring count; fewer once no probe of its quads lies in a
  //! hex and none of them is turned over, or when a sweep moves nothing.
  int sweeps = 12;
  //! No moved node may leave a hex around it below min(this, the hex's scaled Jacobian
  //! before the move): the repair makes no hex poor that was not, and no poor hex worse.
  double min_scaled_jacobian = 0.2;
  //! Compass-search steps, as fractions of the node's mean edge length.
  double initial_step = 0.5;
  double min_step = 0.01;
  //! Where sliding on the surface leaves folds (a slit narrower than a hex, whose two sides
  //! one hex face spans), boundary nodes may then leave the surface by up to this fraction
  //! of their mean edge length; 0: never.
  double max_off_surface = 0.5;
  BoundaryOverlapOptions probe;  //!< the probe that decides which quads are folded
  //! Wall-clock bound: past it no further node is tried (what was done so far stands).
  double time_limit_seconds = 120;
};

struct RepairBoundaryFoldsReport {
  size_t faces_inside_before = 0, faces_inside_after = 0;
  int first_face_after = -1;            //!< as BoundaryOverlapReport::first_face, after the repair
  Vec3 first_point_after = Vec3::Zero();
  size_t regions = 0;                   //!< connected groups of folds worked on
  size_t moved_nodes = 0;               //!< nodes that ended away from where they started
  //! The lowest scaled Jacobian of the hexes around the moved nodes, before and after.
  double region_min_scaled_jacobian_before = 1, region_min_scaled_jacobian_after = 1;
  bool undone = false;                  //!< the repair did not lower the count and was put back
  bool time_limit_reached = false;
  //! Phases (on the surface, then off it) that ended early: a ring count removed no fold.
  size_t phases_ended_without_gain = 0;
};

//! Finds the boundary quads of `mesh` (outward rings `quads`, hex `owners[i]` of quad i, as
//! boundary_quads() gives them) whose probe point lies inside a hex, and moves nodes around
//! them until none does or nothing more helps. A move is kept only if it lowers the folds
//! of the quads near it (their count, then how deep their probes lie) and keeps every hex
//! around the node at or above min(floor, its value); boundary nodes move in the tangent plane of
//! `surface` and land back on it. When the count over the whole mesh has not fallen in the
//! end, every node goes back. Without folds the mesh is untouched and the cost is one
//! probe pass (faces_inside_after then equals what check_conformity would count).
RepairBoundaryFoldsReport repair_boundary_folds(HexMesh& mesh, const TriangleBvh& surface,
                                                const std::vector<std::array<int, 4>>& quads,
                                                const std::vector<int>& owners,
                                                const RepairBoundaryFoldsOptions& options = {});

}  // namespace dthex
