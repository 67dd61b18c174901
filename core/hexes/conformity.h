// SPDX-License-Identifier: MIT
// Conformity checks for hex meshes: what a finite-element solver silently assumes.
#pragma once

#include <dthex/mesh/types.h>

#include <array>
#include <vector>

namespace dthex {

//! What check_conformity() found. A conforming mesh has every count below at zero
//! (boundary_faces excepted): faces shared by at most two hexes, no repeated hex or
//! node, every node used, and a boundary quad surface that is closed, 2-manifold and
//! consistently oriented, with no node hanging on another boundary edge.
struct ConformityReport {
  size_t hexes = 0, nodes = 0;
  size_t boundary_faces = 0;             //!< faces used by exactly one hex
  size_t overshared_faces = 0;           //!< faces used by more than two hexes
  size_t duplicate_hexes = 0;            //!< hexes with the same 8 nodes as an earlier one
  size_t unreferenced_nodes = 0;         //!< nodes no hex uses
  size_t duplicate_nodes = 0;            //!< nodes coinciding with an earlier node (1e-10 of the diagonal)
  size_t open_boundary_edges = 0;        //!< boundary-surface edges not used by exactly two boundary quads
  size_t misoriented_boundary_edges = 0; //!< edges two boundary quads traverse in the same direction
  size_t non_manifold_boundary_nodes = 0;//!< boundary nodes whose boundary quads form several fans
  size_t hanging_nodes = 0;              //!< boundary nodes lying inside another boundary edge
  //! Boundary faces lying inside the mesh: just outside each, a point that some hex covers
  //! (the boundary folded into the volume; see boundary_overlap.h). The referee's probe.
  size_t boundary_faces_inside = 0;
  int first_boundary_face_inside = -1;   //!< index into the boundary quads, -1 when none
  Vec3 first_inside_point = Vec3::Zero();//!< the probe point of that face

  bool conforming() const {
    return overshared_faces == 0 && duplicate_hexes == 0 && unreferenced_nodes == 0 && duplicate_nodes == 0 &&
           open_boundary_edges == 0 && misoriented_boundary_edges == 0 && non_manifold_boundary_nodes == 0 &&
           hanging_nodes == 0 && boundary_faces_inside == 0;
  }
};

//! Checks a hex mesh for the defects listed in ConformityReport, the combinatorial ones and
//! one geometric one (boundary faces inside the mesh). A hanging node (one
//! side of a face refined, the other not) shows up as non-manifold boundary nodes and
//! hanging nodes: the refined and unrefined sides each get their own boundary face.
//! O(n log n); meant for tests and verification, not for inner loops. The boundary quads
//! it finds on the way are stored in `boundary` when given (as boundary_quads() returns
//! them), which saves a caller that needs both a second pass over every face; the hex of
//! each goes to `boundary_owners` when given.
ConformityReport check_conformity(const HexMesh& mesh, std::vector<std::array<int, 4>>* boundary = nullptr,
                                  std::vector<int>* boundary_owners = nullptr);

//! The faces used by exactly one hex, as node rings oriented outward (counter-clockwise
//! seen from outside) for positively oriented hexes, in hex order; the hex of each goes to
//! `owners` when given.
std::vector<std::array<int, 4>> boundary_quads(const HexMesh& mesh, std::vector<int>* owners = nullptr);

//! The faces between two hexes of different regions (HexMesh::region: a closed surface inside
//! another meshed as a second material), each once, as node rings oriented outward of the hex
//! of the lower-numbered region (into the higher one, the way the input's inner surface faces),
//! in hex order; that hex goes to `owners` when given, and the hex on the other side to
//! `others`. Empty when region is.
std::vector<std::array<int, 4>> interface_quads(const HexMesh& mesh, std::vector<int>* owners = nullptr,
                                                std::vector<int>* others = nullptr);

//! The hexes of one region (all of them when mesh.region is empty) as a mesh of their own, with
//! the nodes they use in the mesh's order and their boundary_facet; region is left empty. The
//! mesh node of each of its nodes goes to `node_of` when given. Lets the checks that judge a
//! closed body (check_conformity) judge each region of a mesh alone.
HexMesh region_submesh(const HexMesh& mesh, int region, std::vector<int>* node_of = nullptr);

//! Per node: 1 if it lies on a boundary quad or carries a boundary facet, the nodes that the
//! untangler and the smoothers keep on the surface. They depend on the topology only, so a
//! pipeline computes them once and hands them to each (finding them on a big mesh is costly).
//! With `known` (such a vector computed earlier for the same topology): a copy of it, unless
//! its size is not the mesh's node count, in which case they are found again.
std::vector<char> boundary_nodes(const HexMesh& mesh, const std::vector<char>* known = nullptr);
//! The same from the mesh's boundary_quads(), when the caller has them.
std::vector<char> boundary_nodes_of_quads(const HexMesh& mesh, const std::vector<std::array<int, 4>>& quads);

}  // namespace dthex
