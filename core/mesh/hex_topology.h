// SPDX-License-Identifier: MIT
// The corner numbering of a hexahedron (VTK's and every writer's: corners 0-3 one quad,
// 4-7 the opposite quad, i above i-4), its edges, sides and Jacobian frames as corner lists,
// and the key of an undirected edge between two nodes. Written once: dicing, conformity, projection, the
// fold repair, the sets and the writers all walk hexes by these tables.
#pragma once

#include <array>
#include <cstdint>
#include <utility>

namespace dthex {

//! The twelve edges as corner pairs: the bottom ring, the top ring, then the four verticals.
constexpr std::array<std::array<int, 2>, 12> kHexEdges = {{
    {0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}}};

//! The corners of each side, ordered so that the face's normal (right-hand rule) points out of a
//! positively oriented hex.
constexpr std::array<std::array<int, 4>, 6> kHexFaces = {{
    {0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}};

//! Verdict's corner frames: corner k, then its three edge neighbours, in the order of the
//! columns of the corner's Jacobian (scaled Jacobian, shape, the untangler's energy).
inline constexpr int kHexCornerFrames[8][4] = {{0, 1, 3, 4}, {1, 2, 0, 5}, {2, 3, 1, 6}, {3, 0, 2, 7},
                                               {4, 7, 5, 0}, {5, 4, 6, 1}, {6, 5, 7, 2}, {7, 6, 4, 3}};

//! The centre frame's three axes as sums of the eight corners with these signs.
inline constexpr double kHexCentreAxes[3][8] = {{-1, 1, 1, -1, -1, 1, 1, -1},
                                                {-1, -1, 1, 1, -1, -1, 1, 1},
                                                {-1, -1, -1, -1, 1, 1, 1, 1}};

//! One 64-bit key per undirected edge: the smaller node index in the high half.
inline uint64_t undirected_edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (uint64_t(uint32_t(a)) << 32) | uint32_t(b);
}

}  // namespace dthex
