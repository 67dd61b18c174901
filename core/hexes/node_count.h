// SPDX-License-Identifier: MIT
// How many nodes THex and dicing will make from a tet mesh, without making them:
// what --target-nodes searches over.
#pragma once

#include <dthex/mesh/types.h>

namespace dthex {

struct TetCounts {
  size_t vertices = 0, edges = 0, faces = 0, tets = 0;
};

//! Vertices used by tets, unique edges, unique triangles, tets.
TetCounts count_tet_entities(const TetMesh& mesh);

//! Nodes of THex (corner, edge midpoints, face centres, cell centre: V+E+F+T) followed by
//! dicing by n. The THex mesh has V+E+F+T nodes, 2E+3F+4T edges, 3F+6T quads and 4T
//! hexes; dicing adds (n-1) nodes per edge, (n-1)^2 per quad and (n-1)^3 per hex.
size_t diced_thex_nodes(const TetCounts& counts, int dice);

}  // namespace dthex
