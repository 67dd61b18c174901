// SPDX-License-Identifier: MIT
// Fewer tets before THex: an interior vertex is merged into one of its neighbours (edge
// contraction) when the tets around it, with it replaced by that neighbour, are all positive
// and no worse in Verdict shape than the worst tet around it now. The tets around the
// contracted edge vanish: about 32 nodes per tet after THex and dice 2, plus the vertex. It
// keeps the rule of split_surface_tets: no new edge between two boundary vertices, no new
// interior face of three; and it crowds no vertex: the neighbour kept may not end in more tets
// than THex's hex corners there can share well. Boundary vertices never move, so the boundary
// stays as it was.
#pragma once

#include <dthex/mesh/types.h>

namespace dthex {

struct CollapseInteriorVerticesOptions {
  //! A contraction is taken when the worst new tet has at least this fraction of the shape
  //! of the worst tet around the vertex (1: the local worst never falls).
  double min_shape_ratio = 1.0;
  //! Nor when the neighbour would then be in more tets than this (half as many for a boundary
  //! neighbour, whose tets fill half the sphere around it): every tet at a vertex gives THex
  //! a hex corner there, and the more share it, the narrower they are (split_crowded_vertices.h).
  int max_tets_at_kept_vertex = 40;
  int max_passes = 5;
};

struct CollapseInteriorVerticesReport {
  size_t collapsed = 0;
  size_t tets_before = 0, tets_after = 0;
};

//! Contracts, in place, the interior vertices that can go; the points left unused are removed
//! and the indices of tets and boundary faces renumbered.
CollapseInteriorVerticesReport collapse_interior_vertices(TetMesh& mesh,
                                                          const CollapseInteriorVerticesOptions& options = {});

}  // namespace dthex
