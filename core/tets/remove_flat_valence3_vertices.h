// SPDX-License-Identifier: MIT
// Before TetGen, when the boundary will be projected: a coarse surface vertex with exactly
// three triangles around it, nearly in their neighbours' plane, is removed and its three
// triangles become one. TetGen (Y keeps the surface) must mesh such a vertex with one tet
// that has the three triangles as faces, a sliver when the cap is flat; after the split the
// hexes at that vertex have three faces on a surface that is nearly a plane there, and no
// untangler makes them good. A sharp three-triangle corner is kept.
#pragma once

#include <dthex/mesh/types.h>

namespace dthex {

struct RemoveFlatValence3Options {
  //! A vertex goes when the Verdict shape of the tet it makes with its three neighbours
  //! (its cap) is below this: 0 flat, 1 the corner of a regular tet.
  double max_cap_shape = 0.1;
};

//! Removes, in place, the flat three-triangle vertices (not two neighbouring ones at once,
//! and none whose removal would leave a neighbour with fewer than three triangles or
//! duplicate a triangle) and renumbers the points. Returns the vertices removed.
size_t remove_flat_valence3_vertices(TriSurface& surface, const RemoveFlatValence3Options& options = {});

}  // namespace dthex
