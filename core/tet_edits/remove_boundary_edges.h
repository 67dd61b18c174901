// SPDX-License-Identifier: MIT
// Before split_surface_tets: remove interior edges between two boundary vertices by edge
// removal (a flip) instead of a midpoint split. split_surface_tets explains why such an edge
// must go (its THex hexes get a corner that cannot be valid once the boundary is projected).
// A midpoint split of an edge with k tets around it adds one point and k tets (about 32k + 4
// nodes after THex and dice 2); removing the edge replaces its k tets by the 2(k - 2) tets
// joining its two ends to a triangulation of the ring around it (32(k - 4) nodes: fewer for
// k = 3, none for k = 4). It is done only where no new edge joins two boundary vertices,
// no new face has three, every new tet is positive and no new tet is worse than the worst
// tet the split would have made, so the rule split_surface_tets keeps still holds.
#pragma once

#include <dthex/mesh/types.h>

namespace dthex {

struct RemoveBoundaryEdgesOptions {
  //! Rings with more tets than this are left to the split (the removal would add 2k - 4
  //! tets, as many as the split from k = 4 on, and the triangulations to search grow fast).
  int max_ring = 7;
  //! A removal is taken when its worst tet's shape is at least this fraction of the worst
  //! shape among the tets the midpoint split would give.
  double min_shape_ratio = 1.0;
  //! ... and at least this (absolute floor: THex of a sliver is a poor hex whatever).
  double min_shape = 0.05;
  //! When no flip is left, split a remaining edge at its midpoint (as split_surface_tets
  //! does) and try the flips again: the new interior point joins the rings of the edges
  //! around it, and often lets them go by flips instead of their own splits.
  bool split_when_stuck = true;
};

struct RemoveBoundaryEdgesReport {
  size_t candidates = 0;  //!< interior edges between boundary vertices at the start
  size_t removed = 0;     //!< of those, removed by a flip
  size_t split = 0;       //!< of those, split at their midpoint
  size_t tets_before = 0, tets_after = 0;
};

//! Removes, in place, what it can of the interior edges whose two ends are boundary vertices
//! by flips. The boundary faces, their sources and the points stay as they are; the mesh
//! stays conforming and positively oriented.
RemoveBoundaryEdgesReport remove_boundary_edges(TetMesh& mesh, const RemoveBoundaryEdgesOptions& options = {});

}  // namespace dthex
