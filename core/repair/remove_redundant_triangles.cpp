// SPDX-License-Identifier: MIT
#include <dthex/repair/remove_redundant_triangles.h>

#include <dthex/mesh/half_edges.h>

#include <algorithm>
#include <cstdint>
#include <numeric>

namespace dthex {

namespace {

int find_root(std::vector<int>& parent, int x) {
  while (parent[size_t(x)] != x) {
    parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
    x = parent[size_t(x)];
  }
  return x;
}

}  // namespace

bool is_closed_manifold(const std::vector<std::array<int, 3>>& T, size_t vertex_count) {
  const std::vector<HalfEdge> half_edges = sorted_half_edges(T);
  for (size_t k = 0; k < half_edges.size(); k += 2)
    if (k + 1 >= half_edges.size() || half_edges[k + 1].key != half_edges[k].key ||
        (k + 2 < half_edges.size() && half_edges[k + 2].key == half_edges[k].key))
      return false;
  // Corners (3 t + k) around a vertex joined across the shared edges must form one fan.
  std::vector<int> parent(T.size() * 3);
  std::iota(parent.begin(), parent.end(), 0);
  auto corner = [&](int t, int v) {
    const auto& tri = T[size_t(t)];
    return 3 * t + (tri[0] == v ? 0 : tri[1] == v ? 1 : 2);
  };
  for (size_t k = 0; k < half_edges.size(); k += 2) {
    const int t1 = half_edges[k].triangle, t2 = half_edges[k + 1].triangle;
    for (int v : {int(half_edges[k].key >> 32), int(half_edges[k].key & 0xffffffffu)}) {
      const int a = find_root(parent, corner(t1, v)), b = find_root(parent, corner(t2, v));
      if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);
    }
  }
  std::vector<int> fan(vertex_count, -1);
  for (int c = 0; c < int(parent.size()); ++c) {
    const int v = T[size_t(c / 3)][size_t(c % 3)];
    const int root = find_root(parent, c);
    if (fan[size_t(v)] < 0)
      fan[size_t(v)] = root;
    else if (fan[size_t(v)] != root)
      return false;
  }
  return true;
}

RemoveRedundantTrianglesReport remove_redundant_triangles(TriSurface& surface,
                                                          const RemoveRedundantTrianglesOptions& options) {
  RemoveRedundantTrianglesReport report;
  auto& T = surface.triangles;
  const int nv = int(surface.points.size());
  for (const auto& tri : T)
    for (int v : tri)
      if (v < 0 || v >= nv) return report;
  std::vector<char> removed(T.size(), 0);
  std::vector<int> kept;
  kept.reserve(T.size());
  for (size_t t = 0; t < T.size(); ++t) {
    const auto& tri = T[t];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) {
      removed[t] = 1;
      ++report.collapsed_removed;
      continue;
    }
    kept.push_back(int(t));
  }
  const std::vector<TriangleKey> keys = sorted_triangle_keys(T, kept);
  for (size_t k = 1; k < keys.size(); ++k)
    if (keys[k].first == keys[k - 1].first) {
      removed[size_t(keys[k].second)] = 1;  // a lower id with the same vertices comes first
      ++report.duplicates_removed;
    }
  const size_t count = report.collapsed_removed + report.duplicates_removed;
  if (count == 0) return report;
  std::vector<std::array<int, 3>> remaining;
  remaining.reserve(T.size() - count);
  for (size_t t = 0; t < T.size(); ++t)
    if (!removed[t]) remaining.push_back(T[t]);
  if (remaining.empty() || !is_closed_manifold(remaining, size_t(nv))) {
    report.collapsed_removed = report.duplicates_removed = 0;
    report.left_in_place = count;
    return report;
  }
  for (size_t t = 0; t < T.size() && report.first_removed.size() < options.examples; ++t)
    if (removed[t]) report.first_removed.push_back(int(t));
  T = std::move(remaining);
  return report;
}

}  // namespace dthex
