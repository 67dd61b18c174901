// SPDX-License-Identifier: MIT
#include <dthex/mesh/node_constraints.h>

#include <dthex/hexes/conformity.h>
#include <dthex/surface/features.h>

namespace dthex {

NodeConstraints node_constraints(const HexMesh& mesh, const TriSurface& coarse) {
  NodeConstraints c;
  c.boundary_quads = boundary_quads(mesh);
  // An interface between regions is held on the input's inner surface as the boundary is.
  const std::vector<std::array<int, 4>> interface = interface_quads(mesh);
  c.boundary_quads.insert(c.boundary_quads.end(), interface.begin(), interface.end());
  c.on_boundary = boundary_nodes_of_quads(mesh, c.boundary_quads);
  c.on_feature = nodes_on_feature_edges(mesh, coarse);
  return c;
}

}  // namespace dthex
