// SPDX-License-Identifier: MIT
// The half-edges of a triangle surface, sorted so that the uses of one edge stand side by side:
// what the manifold and orientation checks read (two uses per edge on a closed 2-manifold,
// running opposite ways when the two triangles agree in orientation).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace dthex {

struct HalfEdge {
  uint64_t key;  //!< the edge, min << 32 | max of its two vertices
  int triangle;  //!< the triangle it belongs to
  int from;      //!< the vertex it leaves in that triangle's winding
  bool operator<(const HalfEdge& o) const { return key < o.key || (key == o.key && triangle < o.triangle); }
};

//! Every triangle's three half-edges, sorted by edge, then by triangle. Preconditions: vertex
//! indices are non-negative and fit 32 bits.
inline std::vector<HalfEdge> sorted_half_edges(const std::vector<std::array<int, 3>>& triangles) {
  std::vector<HalfEdge> half_edges;
  half_edges.reserve(triangles.size() * 3);
  for (size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = triangles[t][size_t(k)], b = triangles[t][size_t((k + 1) % 3)];
      half_edges.push_back({uint64_t(std::min(a, b)) << 32 | uint64_t(std::max(a, b)), int(t), a});
    }
  std::sort(half_edges.begin(), half_edges.end());
  return half_edges;
}

}  // namespace dthex
