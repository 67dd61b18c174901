// SPDX-License-Identifier: MIT
// docs/METHOD.md section 6 (Fitting the boundary), step 1: put the boundary nodes of the
// diced hex mesh back on the input (fine) surface, and carry the interior nodes along so
// that they do not stay behind.
#pragma once

#include <dthex/mesh/node_constraints.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/types.h>

#include <array>
#include <vector>

namespace dthex {

struct ProjectOptions {
  //! A fine triangle is a candidate for a node only if its normal is within this angle
  //! of the normal of the node's coarse facet. 90 degrees keeps every node on the side of
  //! the surface its facet faces: across a thin wall the other side faces the opposite way.
  double max_normal_angle_deg = 90.0;
  //! A node may not travel further than this many times the longest edge of its coarse
  //! facet (guards against a closest point on an unrelated part of a folded surface).
  //! When nothing acceptable is that close, the node takes the nearest point among the
  //! normal-compatible triangles anyway and is counted in ProjectReport::far_nodes.
  double max_distance_factor = 1.0;
  //! Re-place the interior nodes by harmonic interpolation of the boundary displacement
  //! (a linear solve on the hex-edge graph). Without it the boundary moves alone and
  //! concave parts invert.
  bool move_interior = true;
  int interior_max_iterations = 2000;   //!< conjugate-gradient iterations
  //! Relative residual of the solve. Looser is faster but can hand the untangler more
  //! inverted hexes; tighter changes the nodes by a negligible fraction of an edge.
  double interior_tolerance = 1e-5;
  //! Before the interior moves: rounds of boundary relaxation on the fine surface (see
  //! relax_boundary_nodes(); 0 = none). The feature nodes of `constraints` (the coarse
  //! surface's feature lines) stay where projection put them. More rounds raise the worst
  //! hexes where projection bunched nodes, at the cost of a slightly larger distance to
  //! sharp CAD edges.
  int relax_rounds = 3;
  //! Optional: the mesh's node_constraints() (before projection), if the caller has them: its
  //! feature nodes are held and its boundary quads used by the relaxation. Without them no
  //! node is held and the quads are found here.
  const NodeConstraints* constraints = nullptr;
};

struct ProjectReport {
  size_t projected_nodes = 0;
  size_t far_nodes = 0;          //!< nodes that had to travel further than the bound
  size_t unconstrained_nodes = 0;  //!< no normal-compatible triangle existed: plain closest point
  double max_displacement = 0;
  size_t relaxed_moves = 0;  //!< node moves of the boundary relaxation, over its rounds
};

//! Moves every boundary node (mesh.boundary_facet[n] >= 0, a triangle of `coarse`) to the
//! closest point of `fine` among the triangles that face the same way as its coarse facet,
//! relaxes them on `fine` (options.relax_rounds), then (options.move_interior) moves interior
//! nodes by the harmonic extension of the boundary displacement.
//! \throw InputError if mesh.boundary_facet is missing or names a triangle `coarse` lacks.
ProjectReport project_boundary(HexMesh& mesh, const TriSurface& coarse, const TriSurface& fine,
                               const TriangleBvh& fine_bvh, const ProjectOptions& options = {});

//! The harmonic (uniform graph Laplacian) extension into the interior of the displacement
//! `boundary_displacement` given at boundary nodes; interior entries of the input are ignored.
//! Adds the result to the interior nodes. Exposed for the untangler and tests.
void move_interior_harmonically(HexMesh& mesh, const std::vector<Vec3>& boundary_displacement,
                                int max_iterations = 2000, double tolerance = 1e-5);

}  // namespace dthex
