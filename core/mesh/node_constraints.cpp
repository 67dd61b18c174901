// SPDX-License-Identifier: MIT
#include <dthex/mesh/node_constraints.h>

#include <dthex/hexes/conformity.h>
#include <dthex/surface/features.h>

namespace dthex {

NodeConstraints node_constraints(const HexMesh& mesh, const TriSurface& coarse) {
  NodeConstraints c;
  c.boundary_quads = boundary_quads(mesh);
  c.on_boundary = boundary_nodes_of_quads(mesh, c.boundary_quads);
  c.on_feature = nodes_on_feature_edges(mesh, coarse);
  return c;
}

}  // namespace dthex
