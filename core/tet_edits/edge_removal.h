// SPDX-License-Identifier: MIT
// Edge removal, the flip that takes an edge out of a tet mesh without adding a point: the k
// tets around an interior edge pq (its ring r0 .. r(k-1)) are replaced by the 2(k - 2) tets
// joining p and q to a triangulation of the ring polygon. When every new tet is positive the
// new tets fill exactly the old ones' union (the boundary of that union is unchanged, and
// positive tets over the same boundary cover each point once), so the mesh stays conforming.
// For k = 3 it is the 3-2 flip (one tet fewer). Here it is shared by two stages:
// remove_boundary_edges and flip_three_tet_edges. Its rule for where the boundary vertices
// may go: no new edge joins two boundary vertices and no new face has three (split_surface_tets
// says why such edges and faces must not be inside).
#pragma once

#include <dthex/mesh/types.h>

#include <optional>
#include <utility>
#include <vector>

namespace dthex {

//! The tets of a mesh being edited: dead tets stay in place until compact() (indices stay
//! valid) and each vertex lists the tets that use it, dead ones dropped when met.
class EditableTets {
 public:
  explicit EditableTets(TetMesh& mesh);

  const Vec3& point(int v) const { return mesh_.points[size_t(v)]; }
  const std::array<int, 4>& tet(int t) const { return mesh_.tets[size_t(t)]; }
  bool alive(int t) const { return alive_[size_t(t)] != 0; }
  size_t tet_slots() const { return mesh_.tets.size(); }

  //! The live tets that have vertex v.
  std::vector<int> tets_of(int v);
  //! The live tets that have both a and b.
  std::vector<int> tets_with(int a, int b);
  bool has_edge(int a, int b) const;
  int add_point(const Vec3& x);
  //! Kills old_tets and appends new_tets.
  void replace(const std::vector<int>& old_tets, const std::vector<std::array<int, 4>>& new_tets);
  //! Drops the dead tets from the mesh.
  void compact();

 private:
  TetMesh& mesh_;
  std::vector<char> alive_;
  std::vector<std::vector<int>> vertex_tets_;
};

//! The ring of vertices around edge pq, ordered so that every tet around it is
//! (p, q, r[i], r[i+1]) up to an even permutation; nothing when the tets do not close one
//! simple ring (pq is a boundary edge).
std::optional<std::vector<int>> ring_around(const EditableTets& mesh, int p, int q, const std::vector<int>& tets);

//! The triangulation of the ring polygon whose tets (joined to p and to q) have the best
//! worst Verdict shape, among those with no diagonal between two boundary vertices (or
//! already an edge) and no triangle of three boundary vertices. worst is -1 when none is
//! allowed, 0 when every allowed one has a flat or inverted tet.
struct RingTriangulation {
  double worst = -1;
  std::vector<std::array<int, 3>> triangles;  //!< ring positions, each in ring order
};
RingTriangulation best_ring_triangulation(EditableTets& mesh, int p, int q, const std::vector<int>& ring,
                                          const std::vector<char>& on_boundary);

//! The 2(k - 2) positive tets that replace the ring's tets for this triangulation.
std::vector<std::array<int, 4>> tets_of_ring_triangulation(int p, int q, const std::vector<int>& ring,
                                                             const RingTriangulation& triangulation);

//! An edge removal ready to be made: the ring around the edge and the tets that replace the
//! ones around it, whose worst Verdict shape is `worst` (above 0).
struct EdgeRemoval {
  std::vector<int> ring;
  std::vector<std::array<int, 4>> new_tets;
  double worst = 0;
};

//! The best edge removal of the edge pq, `around` being its tets: nothing when more than
//! max_ring tets are around it, pq is a boundary edge, or no allowed triangulation of its ring
//! (best_ring_triangulation) makes only positive tets.
std::optional<EdgeRemoval> best_edge_removal(EditableTets& mesh, int p, int q, const std::vector<int>& around,
                                             int max_ring, const std::vector<char>& on_boundary);

//! The edge contraction of vertex u into its neighbour w: u's tets (`star`) with u replaced by
//! w, those that have both u and w dropped. worst is the worst Verdict shape of the new tets (0
//! when one is flat, inverted or not a number; 1 when there are none), tets_at_kept the number
//! of tets w then has. Nothing is changed: the caller decides and calls replace(star, new_tets).
struct EdgeContraction {
  std::vector<std::array<int, 4>> new_tets;
  size_t dropped = 0;
  double worst = 1;
  size_t tets_at_kept = 0;
};
EdgeContraction contract_edge(EditableTets& mesh, int u, int w, const std::vector<int>& star);

//! Removes the points marked in `gone` (used by no tet and no boundary face) and renumbers
//! the tets and boundary faces to the points kept, in their order.
void drop_points(TetMesh& mesh, const std::vector<char>& gone);

//! Worst Verdict shape among the tets given.
double worst_shape(const EditableTets& mesh, const std::vector<int>& tets);

}  // namespace dthex
