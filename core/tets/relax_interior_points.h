// SPDX-License-Identifier: MIT
// Before THex: move each interior tet point to where the worst tet around it is best (a
// max-min relocation; the connectivity stays). THex copies a tet's shape into its four hexes,
// so a flat tet gives flat hexes that no hex smoother repairs. On thin walls the worst tets
// are a boundary face with an interior point just above it: the midpoint of an interior edge
// between two boundary vertices (remove_boundary_edges, split_surface_tets) lies close to the
// surface when the wall is thin or the edge runs nearly along it, and TetGen's Steiner
// points are placed for radius-edge ratio, not for this shape. Only interior points move, so
// the boundary faces stay as they are; a move is taken only when every tet around the point
// stays positive, and then the moved star fills the same polyhedron as before (its outer
// faces do not change), so the mesh stays conforming.
#pragma once

#include <dthex/mesh/types.h>

namespace dthex {

struct RelaxInteriorPointsOptions {
  //! Passes over the interior points, worst star first; stops early when a pass moves none.
  int max_passes = 4;
  //! First trial step, as a fraction of the mean length of the edges at the point.
  double initial_step = 0.25;
  //! The search around one point stops when its step falls below this fraction of that
  //! mean edge length (about 1e-3: far below what changes a hex's shape).
  double min_step = 1e-3;
  //! Trial steps per point and pass.
  int max_trials = 60;
  //! The first relaxation moves the interior points whose worst tet is below this shape. A
  //! point whose tets are all better is left as it is: its hexes are fine, and moving it
  //! gains the average a little but changes what the hex smoother meets, which can lower the
  //! final minimum scaled Jacobian.
  double relax_below = 0.1;
  //! After the first relaxation (which lowers the sum of the inverse tet shapes around each
  //! point, its worst tet never falling), the points whose worst tet is still below this are
  //! moved again to raise that worst tet alone. The first keeps the average shape (a pure
  //! max-min over all points trades it away); the second gets the worst further. 0: no
  //! second relaxation.
  double max_min_below = 0.1;
};

struct RelaxInteriorPointsReport {
  size_t moved = 0;                 //!< interior points moved (counted once)
  double worst_before = 0, worst_after = 0;  //!< worst Verdict tet shape of the mesh
};

//! Moves, in place, interior points (not on a boundary face) to raise the worst Verdict
//! shape of the tets around each. Tets, boundary faces and boundary points stay as they are;
//! a positively oriented conforming mesh stays so. A move never lowers the worst tet around the
//! moved point, so the worst tet of the mesh never falls.
RelaxInteriorPointsReport relax_interior_points(TetMesh& mesh, const RelaxInteriorPointsOptions& options = {});

}  // namespace dthex
