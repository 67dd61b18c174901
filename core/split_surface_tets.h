// SPDX-License-Identifier: MIT
// Before THex: split the tets whose THex hexes would get a flat corner on the boundary.
// A tet with two boundary faces gives, at the vertices of their shared edge, hexes with
// two faces on those two facets; once the boundary is projected onto a smooth surface the
// two facets become nearly coplanar and the hex corner between them flattens (scaled
// Jacobian near 0), which no node placement can repair. Splitting such a tet at its
// centroid (1-to-4) leaves every boundary facet in a tet of its own.
#pragma once

#include "core/types.h"

namespace dthex {

struct SplitSurfaceTetsOptions {
  //! Split at its midpoint every edge that joins two boundary vertices through the interior
  //! (not a boundary edge). A tet on such an edge has two boundary edges meeting at a vertex
  //! with the face between them inside: its THex hex there gets two faces along the surface
  //! at a narrow angle. The split runs through every tet on the edge, so it stays conforming.
  bool split_interior_edges = true;
  //! Before those splits, re-mesh each cluster of tets around two or more such edges as one
  //! cone from its centroid (one new point instead of one per edge) when that is valid and
  //! no worse in tet shape.
  bool cone_edge_clusters = true;
  //! Split tets with at least this many faces on the boundary.
  int min_boundary_faces = 2;
  //! Also split tets whose four vertices all lie on the boundary (edges through the
  //! interior joining boundary vertices: their THex hexes are thin after projection).
  bool split_all_boundary_vertex_tets = false;
};

struct SplitSurfaceTetsReport {
  size_t split_tets = 0;   //!< 1-to-4 centroid splits
  size_t split_edges = 0;  //!< interior edges split at their midpoint
  size_t coned_clusters = 0;  //!< clusters of such edges re-meshed as a cone from one point
};

//! Splits the selected tets 1-to-4 at their centroid, in place. Faces of the tet mesh are
//! unchanged (the new point is inside the tet), so the mesh stays conforming, its boundary
//! faces and their sources stay as they were, and positively oriented tets stay positive.
SplitSurfaceTetsReport split_surface_tets(TetMesh& mesh, const SplitSurfaceTetsOptions& options = {});

}  // namespace dthex
