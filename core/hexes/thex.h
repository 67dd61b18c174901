// SPDX-License-Identifier: MIT
// THex: the classic tet-to-hex split, the hex mesh DTHex starts from.
#pragma once

#include <dthex/mesh/types.h>

namespace dthex {

//! Splits every tet into 4 hexes (a corner, its 3 edge midpoints, 3 face centroids
//! and the cell centroid), so the result is conforming wherever the tet mesh is.
//!
//! Node numbering (relied upon by dice() and by callers): the tet points first with
//! their indices unchanged, then one node per unique tet edge, one per unique triangle
//! face, one per tet. Sharing goes through sorted integer vertex ids, never through
//! coordinates, so coincident but distinct points stay distinct.
//!
//! boundary_facet: nodes on boundary faces of the tet mesh get the
//! TetMesh::boundary_face_source of a boundary face they lie on (the boundary face
//! index when there are no sources), other nodes -1. It
//! is left empty when the tet mesh carries no boundary faces. The faces between two regions
//! (TetMesh::tet_region) are among the boundary faces, so interface nodes get one too.
//!
//! region: hexes 4t .. 4t+3 come from tet t and get its tet_region (empty when it is).
//! Negatively oriented tets are split with a mirrored corner order, so every hex of a
//! non-degenerate tet is positively oriented.
//! \throw InputError on a tet with an out-of-range or repeated vertex, or
//!        boundary_face_source of a size other than boundary_faces.
HexMesh thex(const TetMesh& tets);

}  // namespace dthex
