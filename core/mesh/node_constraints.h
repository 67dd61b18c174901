// SPDX-License-Identifier: MIT
// What the boundary stages (projection, untangling, smoothing, repair) must know about a
// hex mesh's nodes: which lie on its boundary, which on a feature line or corner of the
// coarse surface (held there), and the boundary quads. Found once when the hex topology is
// final, so that no stage sorts every hex face again to find them.
#pragma once

#include <dthex/mesh/types.h>

#include <array>
#include <vector>

namespace dthex {

struct NodeConstraints {
  //! The mesh's boundary faces as outward quads (conformity.h's boundary_quads()), then the
  //! faces between its regions (interface_quads()), whose nodes are held on the surface too.
  std::vector<std::array<int, 4>> boundary_quads;
  //! Per node: on the boundary (a node of a boundary quad, or one with a boundary facet).
  //! Empty, or not of the mesh's node count, means not known: a stage then finds them.
  std::vector<char> on_boundary;
  //! Per node: on a feature edge of the coarse surface (nodes_on_feature_edges()). These
  //! nodes are held: projection's relaxation leaves them where projection put them, and
  //! the smoothers keep them on any crease they sit on. Empty means not known: the local
  //! smoother then holds every node on a crease, the repair's slides none on a concave one.
  std::vector<char> on_feature;

  //! Whether node v is marked in on_feature (false when on_feature is not known).
  bool is_feature(size_t v) const { return v < on_feature.size() && on_feature[v]; }
};

//! The constraints of `mesh`, whose boundary nodes must still lie on the coarse surface they
//! were made from (after THex and dicing, before projection moves them; boundary_facet names
//! each one's coarse triangle). Changes nothing. Call again if the topology changes.
NodeConstraints node_constraints(const HexMesh& mesh, const TriSurface& coarse);

}  // namespace dthex
