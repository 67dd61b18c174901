// SPDX-License-Identifier: MIT
// Before THex: split the interior tet vertices that too many tets share. THex gives every tet
// at a vertex one hex corner there, and those corners share the sphere around the vertex: with
// k of them, an even split leaves each a spherical triangle of area 4 pi / k, whose scaled
// Jacobian is at most 0.62 at k = 28, 0.48 at k = 40, 0.42 at k = 48 and 0.35 at k = 60
// (docs/METHOD.md section 4). No smoothing of the hexes changes k, so such a vertex bounds the worst hex. It
// arises where a cone point replaces a cluster of edges between boundary vertices and where
// interior points are merged (remove_boundary_edges, collapse_interior_vertices), and among
// TetGen's own points.
//
// A crowded vertex v is split in two, the inverse of an edge collapse: the faces opposite v in
// its tets (its link, a triangulated sphere) are cut by a plane through v into two caps, each
// a disk; v keeps one cap, a new vertex w takes the other, and a tet (v, w, a, b) fills each
// link edge (a, b) on the cut. Each of the two then has about half the tets plus the cut's
// length. The star's outer faces do not change, so the mesh stays conforming and its boundary
// as it was. Several cutting planes are tried (the principal axes of the link and the
// coordinate axes, each through the median of the link faces), the two points placed by a
// pattern search where the worst tet of the new star is best, and a split is taken only when
// that worst tet is nearly as good as the old star's (min_quality_ratio).
#pragma once

#include <dthex/mesh/types.h>

namespace dthex {

struct SplitCrowdedVerticesOptions {
  //! Interior vertices in more tets than this are split, most crowded first. At 44 an even
  //! split of the sphere bounds the scaled Jacobian at 0.45, above what the smoother reaches
  //! elsewhere; a lower value lifts that bound but splits more vertices, each split adding a
  //! point and the cut's tets (about 8, some 250 hexes after dicing), and at 40 the cut tets'
  //! outer corners, on the boundary of thin walls, lowered the worst hexes there.
  int max_tets = 44;
  //! A split is taken when the worst tet scaled Jacobian of the new star is at least this
  //! fraction of the old star's worst. Below 1 a split may start the hexes a little worse where
  //! the smoothing can still widen them (at the cut's outer corners), to free the crowded
  //! vertex, which no smoothing can: a crowded star of even tets cannot be split without it.
  double min_quality_ratio = 0.9;
  //! Vertices in more than `very_crowded_tets` tets take a split down to this ratio instead.
  //! Their even split of the sphere bounds the hex corners below the smoother's lift (0.4 at
  //! about 51 tets, 0.35 at 60), so no smoothing brings the worst hex there to 0.4, while the
  //! worse tets a split starts with sit at the cut's outer corners, which the smoothing can
  //! widen (the shared pelvis: a vertex of 52 tets whose best split kept 0.62 of its star's
  //! worst tet held the worst hex at 0.342; split, 0.373). For less crowded vertices a low
  //! ratio costs more than it frees (skull_hollow's worst 0.245 -> 0.237 with 0.6 for all).
  int very_crowded_tets = 51;
  double very_crowded_quality_ratio = 0.6;
  //! Rounds over the crowded vertices (a vertex split once may still be crowded).
  int max_passes = 3;
  //! Trial steps of the pattern search per point and placement round (two rounds, each
  //! placing both points); more place them slightly better for more time.
  int placement_trials = 30;
};

struct SplitCrowdedVerticesReport {
  size_t split = 0;                              //!< splits made (one new point each)
  size_t crowded_before = 0, crowded_after = 0;  //!< interior vertices in more than max_tets tets
  int most_tets_before = 0, most_tets_after = 0;  //!< the largest tet count of an interior vertex
  size_t tets_before = 0, tets_after = 0;
};

//! Splits, in place, the interior vertices (on no boundary face) of `mesh` that more than
//! options.max_tets tets share, where the worst tet scaled Jacobian around them keeps
//! options.min_quality_ratio of its value (very_crowded_quality_ratio for the most crowded). Boundary faces and boundary points stay; tets stay positively oriented; new points
//! are appended; tet_region, when present, is carried to the new tets.
SplitCrowdedVerticesReport split_crowded_vertices(TetMesh& mesh, const SplitCrowdedVerticesOptions& options = {});

}  // namespace dthex
