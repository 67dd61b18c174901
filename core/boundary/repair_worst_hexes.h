// SPDX-License-Identifier: MIT
// After smoothing: where hexes stay below a scaled Jacobian the local smoother cannot lift
// (it moves one node at a time, and in a pit or at a sharp detail every single-node move that
// raises one corner lowers another), re-place the region around them as a whole, then
// raise again. The untangler's local repair (untangle.h, phase 3) minimizes its energy
// over the nodes within a few hex rings of those hexes, the boundary nodes among them
// sliding on the input surface (creases and corners hold); its result has a lower minimum
// (the energy evens out the region, it does not maximize the worst corner) but lies in a
// different basin, from which the smoother's scaled-Jacobian pass then reaches further.
// A round that ends worse (a lower minimum, more inverted hexes) is undone.
#pragma once

#include <dthex/boundary/local_smooth.h>
#include <dthex/mesh/node_constraints.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/types.h>
#include <dthex/surface/features.h>

#include <vector>

namespace dthex {

struct RepairWorstHexesOptions {
  //! Hexes whose scaled Jacobian is below this are repaired; a mesh without any is not touched.
  double threshold = 0.2;
  //! Nor is a mesh with more than this fraction of its hexes below it, and more than
  //! `always_repaired` (a small mesh has a large fraction): the regions around them then
  //! cover the mesh, and a global solve is what the untangler already ran; the repair
  //! would spend long minutes for little gain.
  double max_below_fraction = 0.01;
  size_t always_repaired = 500;
  //! Hex rings around them whose nodes the region solve moves.
  int region_rings = 2;
  //! Passes of the region solve with the boundary nodes sliding on the surface (after one
  //! with the boundary fixed). Sliding frees hexes the fixed boundary pins; further passes
  //! tend to end where the first did.
  int sliding_passes = 1;
  //! Rounds of region solve and smoothing, while each gains (fewer hexes below the
  //! threshold, or a higher minimum) without lowering the minimum; a round that does not
  //! gain is undone and ends the repair.
  int rounds = 3;
  //! The scaled Jacobian the smoother then raises hexes towards (LocalSmoothOptions).
  double target_scaled_jacobian = 0.3;
  //! Shape sweeps of that smoother run; they also raise the minimum a little.
  int shape_sweeps = 0;
  //! As LocalSmoothOptions::constraints: the boundary nodes (found here without them), and
  //! the nodes of the coarse feature lines, held on concave creases too. A crease is where
  //! the surface turns by more than `max_normal_turn_deg` (the smoother's feature angle).
  const NodeConstraints* constraints = nullptr;
  double max_normal_turn_deg = kDefaultFeatureAngleDeg;
  //! As LocalSmoothOptions::knife_edge_slide, for the region solve's slides too (the nodes
  //! of a knife edge's line are not held).
  double knife_edge_slide = LocalSmoothOptions().knife_edge_slide;
  double time_limit_seconds = 120.0;
};

struct RepairWorstHexesReport {
  size_t below_before = 0, below_after = 0;          //!< hexes below the threshold
  double min_scaled_jacobian_before = 0, min_scaled_jacobian_after = 0;
  double min_after_region_solve = 0;                 //!< before the smoother ran again
  int rounds = 0;       //!< rounds kept
  bool undone = false;  //!< the first round ended worse than the input, which was put back
  bool too_many = false;  //!< too many hexes were below (max_below_fraction): not run
  bool time_limit_reached = false;
};

//! Repairs the hexes below options.threshold as above; never leaves the mesh worse (its
//! minimum scaled Jacobian and inverted count) than it found it.
RepairWorstHexesReport repair_worst_hexes(HexMesh& mesh, const TriangleBvh& surface,
                                          const RepairWorstHexesOptions& options = {});

}  // namespace dthex
