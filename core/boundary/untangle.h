// SPDX-License-Identifier: MIT
// docs/METHOD.md section 6 (Fitting the boundary), step 4: after projection, remove every
// inverted hex corner and improve shape.
// Energy: Garanzha et al. 2021, "Foldover-free maps in 50 lines of code", over the 8 corner
// Jacobians and the centre Jacobian of each hex (the nine places Verdict's scaled Jacobian
// looks at), each normalized by the hex's own edge length. Its regularized determinant
// makes the energy finite on inverted corners, and the continuation on epsilon turns it
// into a barrier once everything is valid, so the shape pass that follows never re-inverts.
#pragma once

#include <dthex/mesh/node_constraints.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/types.h>

#include <functional>
#include <vector>

namespace dthex {

struct UntangleOptions {
  //! Weight of the size term against the shape term of the energy (Garanzha's theta).
  double theta = 0.5;
  //! Hexes whose scaled Jacobian is below this are repaired locally: the nodes within
  //! `region_rings` hex rings of them move, the rest of the mesh stays put.
  double target_scaled_jacobian = 0.2;
  int region_rings = 2;
  //! Epsilon-continuation rounds per local repair, and L-BFGS iterations per round.
  int max_rounds = 20;
  int max_lbfgs_iterations = 100;
  //! The shape pass: rounds and L-BFGS iterations per round (0 iterations skips it). Once
  //! nothing is inverted it is a barrier: it never re-inverts. It sets the average shape the
  //! local smoother then works from: 20 iterations over the hexes below shape 0.5 end about
  //! 0.01-0.02 higher on average than 10 below 0.4 (the smoother's lift of the worst hexes
  //! costs about that much); 30 below 0.6 gained little more for three times the time on
  //! thin walls.
  int smoothing_rounds = 1;
  int smoothing_iterations = 20;
  //! It moves the interior nodes of hexes whose shape is below this and of the hexes within
  //! `smoothing_rings` rings of them (threshold 1 or more: every interior node), in pieces of
  //! at most `smoothing_part_nodes` nodes grown breadth-first; pieces that share no hex are
  //! solved at the same time on all cores, neighbours one after the other. Over the whole
  //! mesh at once one near-flat frame limits every step; small pieces converge further in
  //! less time.
  double smoothing_shape_threshold = 0.5;
  int smoothing_rings = 1;
  int smoothing_part_nodes = 500;
  //! Where moving interior nodes is not enough, let the boundary nodes of the repair
  //! region slide on the surface (tangent-plane moves, then back onto the surface), in up
  //! to this many passes.
  bool slide_boundary = true;
  int max_boundary_phases = 3;
  //! Optional: boundary nodes that must not move where they stand, asked before each round
  //! (e.g. on a crease of the surface, which a slide in the tangent plane would round off;
  //! a node that slid onto one stops there). Called concurrently: must not write.
  std::function<bool(size_t node, const Vec3& at)> held;
  //! Optional: whether a sliding node that stood at `from` when the round began may land at
  //! `to`; refused, it goes back. Called concurrently: must not write.
  std::function<bool(size_t node, const Vec3& from, const Vec3& to)> may_land;
  //! Rounds of the first, interior-only repair when the boundary may slide afterwards.
  //! Fewer rounds save time where the fixed boundary cannot undo an inversion but leave more
  //! to the sliding repair, which lowers the final minimum scaled Jacobian.
  int fixed_boundary_rounds = 20;
  //! Optional: the mesh's node_constraints(), if the caller has them; its on_boundary is
  //! used (found here without it, or if it is not of the mesh's node count).
  const NodeConstraints* constraints = nullptr;
  //! The run stops (and reports what it reached) after this much wall time.
  double time_limit_seconds = 120.0;
  //! The repair of inverted hexes gives up (UntangleReport::stalled) when their count has not
  //! fallen over this much work (hexes evaluated by the energy, summed over its evaluations),
  //! or over a whole pass with the boundary sliding: a fold the energy cannot undo is left to
  //! the stages after it, not worked on until the time limit. Work, not wall time, so that a
  //! run stops at the same point every time; 50 million is about 20 s on 2 cores of the
  //! machine of docs/BENCHMARKS.md (the shared pelvis's whole untangling is 9 million).
  //! 0 = no such bound (only time_limit_seconds).
  long stall_work = 50'000'000;
  //! Length of worst_hexes in the report.
  size_t report_worst = 10;
};

struct UntangleReport {
  size_t inverted_before = 0, inverted_after = 0;  //!< hexes with scaled Jacobian <= 0
  double min_scaled_jacobian = 0;                   //!< after
  double avg_shape = 0, min_shape = 0;              //!< after
  std::vector<size_t> worst_hexes;                  //!< lowest scaled Jacobian first
  size_t sliding_boundary_nodes = 0;  //!< boundary nodes that were allowed to move
  int rounds = 0;                     //!< epsilon-continuation rounds run in all
  double seconds = 0;
  bool time_limit_reached = false;
  //! The repair of inverted hexes stopped because their count had stopped falling
  //! (UntangleOptions::stall_work); stalled_after_seconds is when.
  bool stalled = false;
  double stalled_after_seconds = 0;
  bool undone = false;  //!< it ended with more inverted hexes than it began with: nodes put back
};

//! Moves interior nodes (and, where needed, boundary nodes along the surface of
//! `fine_bvh`) until no hex has a non-positive scaled Jacobian, then improves shape.
//! Boundary nodes are those with boundary_facet >= 0 and every node of a boundary quad.
//! Never throws on failure to untangle: the report says what is left.
UntangleReport untangle_and_smooth(HexMesh& mesh, const TriangleBvh& fine_bvh, const UntangleOptions& options = {});

}  // namespace dthex
