// SPDX-License-Identifier: MIT
// Before TetGen: a flat region of the coarse surface whose vertices all lie on its outline
// keeps needle triangles that no collapse can remove, because there is no inner vertex to
// move. Cut planes closed by a fan of triangles are common in segmented scans: the bone or
// skull leaves the field of view, and hole filling closes it without inner points, with
// needles down to a fraction of a degree. TetGen keeps the surface (Y), so every needle
// becomes the face of a sliver tet, and THex and dicing turn it into hexes that no
// untangler makes good. Such needles are
// refined here, within their plane: the longest edge of a needle is split at its midpoint
// (the midpoint lies in the plane, so the surface does not change), flips within the plane
// restore the Delaunay property, and each new vertex moves to the mean of its neighbours in
// the plane. Edges on the region's outline are never split, and a needle whose smallest
// angle touches the outline is left alone (a thin strip between feature lines stays thin).
#pragma once

#include <dthex/mesh/types.h>

namespace dthex {

struct RefineFlatNeedlesOptions {
  //! A triangle with an angle below this is a needle.
  double min_angle_deg = 15;
  //! Two triangles that share an edge are one flat region when their normals differ by less.
  double coplanar_deg = 0.5;
  //! Split-flip-relax rounds, and the most vertices added in all, as a fraction of the
  //! surface's vertices (at least 64): a bound for outlines whose spacing would call for
  //! ever finer triangles.
  int max_rounds = 12;
  double max_added_fraction = 0.5;
};

struct RefineFlatNeedlesReport {
  size_t needles_before = 0;  //!< flat-region needles the step could work on
  size_t needles_after = 0;
  size_t vertices_added = 0;
  size_t flips = 0;
  //! The last rounds, taken back because they left more needles than an earlier round (or
  //! than there were, when every round is taken back and the surface stays as it was).
  size_t rounds_taken_back = 0;
};

//! Refines, in place, the needles of the flat regions of a closed, consistently oriented
//! surface (see above), keeping the last round that left the fewest needles: on an outline
//! whose spacing calls for ever finer triangles, later rounds can leave more than they
//! found (a coarse surface of a finer skull scan: 73 needles, 29 after two rounds, 217 after
//! twelve). Every point of the result lies on the input surface, and the
//! surface keeps its orientation, closedness and manifoldness.
RefineFlatNeedlesReport refine_flat_needles(TriSurface& surface, const RefineFlatNeedlesOptions& options = {});

}  // namespace dthex
