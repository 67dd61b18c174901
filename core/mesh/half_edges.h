// SPDX-License-Identifier: MIT
// The half-edges of a triangle surface, sorted so that the uses of one edge stand side by side:
// what the manifold and orientation checks read (two uses per edge on a closed 2-manifold,
// running opposite ways when the two triangles agree in orientation). Also the triangles'
// sorted vertex triples, side by side where two triangles use the same three vertices.
//
// Both sorts order first by a vertex number, so they are made as a counting sort by that
// vertex and then a sort of each vertex's few items: two passes over the items instead of the
// twenty-odd of a comparison sort, which on millions of triangles was a second a sort. The
// order is total, so the result is the one std::sort gives.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace dthex {

//! make(0), ..., make(n - 1) sorted by `less`, a strict total order whose first criterion is
//! lead(item), a vertex number compared as a number. A counting sort by the vertex, then
//! std::sort within each vertex's items; std::sort over all of them where the vertex numbers
//! are few items apart no longer (more than 4 per item, or negative), where it is as fast.
template <class Item, class Make, class Lead, class Less>
std::vector<Item> sorted_by_lead_vertex(size_t n, Make make, Lead lead, Less less) {
  int64_t largest = -1;
  bool negative = false;
  for (size_t i = 0; i < n; ++i) {
    const int64_t v = lead(make(i));
    largest = std::max(largest, v);
    negative |= v < 0;
  }
  std::vector<Item> items;
  if (negative || largest >= int64_t(4 * n + 16)) {
    items.reserve(n);
    for (size_t i = 0; i < n; ++i) items.push_back(make(i));
    std::sort(items.begin(), items.end(), less);
    return items;
  }
  const size_t vertices = size_t(largest + 1);
  std::vector<size_t> start(vertices + 1, 0);
  for (size_t i = 0; i < n; ++i) ++start[size_t(lead(make(i))) + 1];
  for (size_t v = 0; v < vertices; ++v) start[v + 1] += start[v];
  std::vector<size_t> next(start.begin(), start.end() - 1);
  items.resize(n);
  for (size_t i = 0; i < n; ++i) {
    Item item = make(i);
    items[next[size_t(lead(item))]++] = std::move(item);
  }
  for (size_t v = 0; v < vertices; ++v)
    if (start[v + 1] - start[v] > 1)
      std::sort(items.begin() + long(start[v]), items.begin() + long(start[v + 1]), less);
  return items;
}

struct HalfEdge {
  uint64_t key;  //!< the edge, min << 32 | max of its two vertices
  int triangle;  //!< the triangle it belongs to
  int from;      //!< the vertex it leaves in that triangle's winding
  //! By edge, then triangle, then the vertex it leaves (twice in one triangle only where the
  //! triangle repeats a vertex).
  bool operator<(const HalfEdge& o) const {
    return key != o.key ? key < o.key : triangle != o.triangle ? triangle < o.triangle : from < o.from;
  }
};

//! Every triangle's three half-edges, sorted by edge, then by triangle. Preconditions: vertex
//! indices are non-negative and fit 32 bits.
inline std::vector<HalfEdge> sorted_half_edges(const std::vector<std::array<int, 3>>& triangles) {
  const auto half_edge = [&triangles](size_t i) {
    const size_t t = i / 3, k = i % 3;
    const int a = triangles[t][k], b = triangles[t][(k + 1) % 3];
    return HalfEdge{uint64_t(std::min(a, b)) << 32 | uint64_t(std::max(a, b)), int(t), a};
  };
  return sorted_by_lead_vertex<HalfEdge>(
      3 * triangles.size(), half_edge, [](const HalfEdge& h) { return int64_t(h.key >> 32); }, std::less<HalfEdge>());
}

//! A triangle's vertices in ascending order, and its index.
using TriangleKey = std::pair<std::array<int, 3>, int>;

//! The given triangles' keys, sorted (by vertices, then index): triangles that use the same
//! three vertices stand side by side, the lower index first.
inline std::vector<TriangleKey> sorted_triangle_keys(const std::vector<std::array<int, 3>>& triangles,
                                                     const std::vector<int>& which) {
  const auto key_of = [&](size_t i) {
    std::array<int, 3> key = triangles[size_t(which[i])];
    std::sort(key.begin(), key.end());
    return TriangleKey{key, which[i]};
  };
  return sorted_by_lead_vertex<TriangleKey>(
      which.size(), key_of, [](const TriangleKey& k) { return int64_t(k.first[0]); }, std::less<TriangleKey>());
}

}  // namespace dthex
