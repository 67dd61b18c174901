// SPDX-License-Identifier: MIT
// Dicing: the uniform refinement that turns THex's few good-sized hexes into many.
#pragma once

#include <dthex/mesh/types.h>

namespace dthex {

//! Splits every hex into n^3 by trilinear subdivision of its parameter cube.
//!
//! Nodes on a hex edge or face shared by several hexes are created once: edges are
//! matched by their sorted node pair, faces by their sorted 4 node ids, and a face's
//! (n-1)^2 interior nodes are laid out in a canonical frame (from its smallest node id
//! towards its smaller neighbour) so both sides index them alike. Matching buckets the
//! edges and faces by their smallest node, so time and memory are linear in the output.
//!
//! Numbering: the input nodes first with their indices unchanged, then (n-1) nodes per
//! unique edge, (n-1)^2 per unique face (edges and faces in order of first use by the
//! hexes), (n-1)^3 per hex. The n^3 sub-hexes of hex h are h*n^3 ... (h+1)*n^3-1 and
//! keep the parent's orientation and VTK node order.
//!
//! boundary_facet (when the input has it): a face used by exactly one hex is a boundary
//! face; its new nodes, and the new nodes of its edges, get the face's facet, which is
//! the facet of its highest-numbered boundary corner. That corner is the most recently
//! created one, which for meshes from thex() and dice() lies inside the face's coarse
//! triangle, not on an edge shared with a neighbouring triangle. Other new nodes get -1.
//! region (when the input has it): each sub-hex has its parent's, and a face between two
//! regions counts as a boundary face for boundary_facet (its nodes lie on the interface).
//! \throw InputError when region is neither empty nor one entry per hex.
//! \throw std::invalid_argument when n < 1.
//! \throw InputError on a hex with an out-of-range node.
HexMesh dice(const HexMesh& mesh, int n);

}  // namespace dthex
