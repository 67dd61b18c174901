// SPDX-License-Identifier: MIT
// Fewer tets before THex: every interior edge with exactly three tets around it is taken out
// by the 3-2 flip (edge_removal.h) when the two new tets are no worse, in Verdict shape, than
// the worst of the three. One tet fewer is about 32 fewer nodes after THex and dice 2 (an
// edge, two faces and a tet less), and the flip is taken only where it does not lower the
// local worst shape. TetGen's own flips judge dihedral angles, not this shape, and leave
// many such edges. The flips keep the rule of
// split_surface_tets: the new face is never one of three boundary vertices.
#pragma once

#include <dthex/mesh/types.h>

namespace dthex {

struct FlipThreeTetEdgesOptions {
  //! A flip is taken when its worse new tet has at least this fraction of the shape of the
  //! worst tet it replaces (1: the local worst shape never falls).
  double min_shape_ratio = 1.0;
  //! Passes over all edges (a flip can leave another edge with three tets); stops early
  //! when a pass flips nothing.
  int max_passes = 5;
};

struct FlipThreeTetEdgesReport {
  size_t flips = 0;
  size_t tets_before = 0, tets_after = 0;
};

//! Flips, in place, the three-tet interior edges whose 3-2 flip is allowed. Points, boundary
//! faces and their sources stay as they are; the mesh stays conforming and positive.
FlipThreeTetEdgesReport flip_three_tet_edges(TetMesh& mesh, const FlipThreeTetEdgesOptions& options = {});

}  // namespace dthex
