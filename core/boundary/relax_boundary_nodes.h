// SPDX-License-Identifier: MIT
// Between projection and the interior placement: boundary nodes slide on the input surface
// toward the mean of their boundary neighbours. Projection takes each node to its own
// closest point, and where the input bends away from a coarse facet (a pit, a fold) the
// nodes of that facet bunch up on one side; the hexes there are flat before the untangler
// starts, and no later one-node move lifts them. The nodes on the coarse surface's feature
// lines and on convex creases of the input stay, so sharp edges keep their nodes; where the
// coarse surface has no feature line along an input crease, the nodes beside it still move,
// so its quads may cut such an edge a little deeper.
#pragma once

#include <dthex/mesh/node_constraints.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/types.h>
#include <dthex/surface/features.h>

#include <array>
#include <vector>

namespace dthex {

struct RelaxBoundaryOptions {
  //! Jacobi rounds over all boundary nodes; each moves a node `step` of the way to the
  //! mean of its boundary-quad neighbours, in the tangent plane, then back onto the surface.
  int rounds = 3;
  double step = 0.5;
  //! A move is refused where the surface normal at the landing point turns by more than
  //! this from the normal where the node stands: a node does not cross a feature line.
  double max_normal_turn_deg = kDefaultFeatureAngleDeg;
  //! Optional: the mesh's node_constraints(), if the caller has them, for its boundary quads
  //! (used as given, even empty); found here otherwise.
  const NodeConstraints* constraints = nullptr;
};

struct RelaxBoundaryReport {
  size_t moves = 0;   //!< accepted node moves, over all rounds
  size_t held = 0;    //!< nodes that never move (on the coarse surface's feature lines)
};

//! Moves the boundary nodes of `mesh` (boundary_facet >= 0) on `surface`, each kept on
//! triangles that face the same side as its coarse facet (as projection keeps it), and
//! adds every move to `displacement`. Nodes with held[v] != 0 stay.
RelaxBoundaryReport relax_boundary_nodes(HexMesh& mesh, const TriSurface& coarse, const TriangleBvh& surface,
                                         const std::vector<char>& held, std::vector<Vec3>& displacement,
                                         const RelaxBoundaryOptions& options = {});

}  // namespace dthex
