// SPDX-License-Identifier: MIT
// The safe repairs of an input surface, in the order they need (the pipeline's --repair
// safe, run before verify_surface()): each fixes a defect of real files that cannot change
// the shape, and what cannot be repaired this way is left for verification to refuse.
#pragma once

#include <dthex/mesh/types.h>
#include <dthex/repair/flip_zero_area_slivers.h>
#include <dthex/repair/merge_coincident_vertices.h>
#include <dthex/repair/remove_redundant_triangles.h>
#include <dthex/repair/remove_small_islands.h>
#include <dthex/repair/repair_orientation.h>

namespace dthex {

struct SurfaceRepairOptions {
  MergeCoincidentVerticesOptions merge;
  RemoveSmallIslandsOptions islands;  //!< off by default (min_triangles 0): it removes geometry
  RemoveRedundantTrianglesOptions redundant;
  RepairOrientationOptions orientation;
  FlipZeroAreaSliversOptions slivers;
};

struct SurfaceRepairReport {
  bool ran = false;  //!< false with --repair none
  MergeCoincidentVerticesReport merge;
  RemoveSmallIslandsReport islands;
  RemoveRedundantTrianglesReport redundant;
  RepairOrientationReport orientation;
  FlipZeroAreaSliversReport slivers;
  //! Did any repair change the surface?
  bool changed() const {
    return merge.vertices_merged + islands.triangles_dropped + redundant.collapsed_removed + redundant.duplicates_removed +
               orientation.triangles_turned + slivers.slivers_flipped >
           0;
  }
};

//! Merges coincident vertices (merge_coincident_vertices.h), drops the islands below
//! options.islands.min_triangles or min_volume_fraction if set (remove_small_islands.h: after the merge, so that a
//! soup's triangles are one island, and before the next step, whose closed-surface test a
//! noise island must not fail), then removes the collapsed and duplicate triangles where the
//! surface stays closed and manifold
//! (remove_redundant_triangles.h), then makes each component's orientation consistent
//! (repair_orientation.h), then flips the zero-area slivers away (flip_zero_area_slivers.h:
//! it needs the consistent orientation). Vertex ids are kept (merged vertices are left
//! unused); triangle ids shift only when triangles were removed.
SurfaceRepairReport repair_surface(TriSurface& surface, const SurfaceRepairOptions& options = {});

}  // namespace dthex
