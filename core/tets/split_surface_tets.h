// SPDX-License-Identifier: MIT
// Before THex: split the tets whose THex hexes would get a flat corner on the boundary.
// Once the boundary is projected onto a smooth surface, every hex edge along the boundary
// lies in the surface's tangent plane at its boundary end. A hex corner there is then flat
// or inverted, whatever the untangler does, when two of its edges run along the surface
// but the hex face between them does not: the hex on the other side of that face has the
// same two edges and its third edge also going inside. THex makes such a corner from
// every interior tet edge joining two boundary vertices and every interior tet face with
// three boundary vertices. The rule kept here: after the splits no interior edge joins two
// boundary vertices and no interior face has three, so every tet has at most three
// boundary vertices, and when three, the face through them is a boundary face.
#pragma once

#include <dthex/mesh/types.h>

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
  //! Split at its centroid every interior face whose three vertices are boundary vertices
  //! (after the edge splits: a triangle of boundary edges that is not a boundary face). At
  //! each of its corners the hexes on both sides have two edges along the surface and their
  //! third inside, which a smooth surface makes impossible for both at once.
  bool split_interior_faces = true;
  //! Split tets with at least this many faces on the boundary.
  int min_boundary_faces = 2;
  //! Also split tets whose four vertices all lie on the boundary (edges through the
  //! interior joining boundary vertices: their THex hexes are thin after projection).
  bool split_all_boundary_vertex_tets = false;
};

struct SplitSurfaceTetsReport {
  size_t split_tets = 0;   //!< 1-to-4 centroid splits
  size_t split_edges = 0;  //!< interior edges split at their midpoint
  size_t split_faces = 0;  //!< interior faces between boundary vertices split at their centroid
  size_t coned_clusters = 0;  //!< clusters of such edges re-meshed as a cone from one point
};

//! Only the cone step of split_surface_tets (cone_edge_clusters): returns the clusters coned.
size_t cone_edge_clusters(TetMesh& mesh);

//! Splits, in place, the selected edges at their midpoint, faces at their centroid and tets
//! at their centroid (or re-meshes edge clusters as cones). Every new point is inside the
//! volume and every split goes through all tets on the split entity, so the mesh stays
//! conforming, its boundary faces and their sources stay as they were, and positively
//! oriented tets stay positive.
SplitSurfaceTetsReport split_surface_tets(TetMesh& mesh, const SplitSurfaceTetsOptions& options = {});

}  // namespace dthex
