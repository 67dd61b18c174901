// SPDX-License-Identifier: MIT
#include <dthex/repair/flip_zero_area_slivers.h>

#include <dthex/mesh/hex_topology.h>
#include <dthex/mesh/triangle_crossing.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <unordered_map>

namespace dthex {

FlipZeroAreaSliversReport flip_zero_area_slivers(TriSurface& surface, const FlipZeroAreaSliversOptions& options) {
  FlipZeroAreaSliversReport report;
  auto& T = surface.triangles;
  const auto& P = surface.points;
  const int nv = int(P.size());
  for (const auto& tri : T) {
    for (int v : tri)
      if (v < 0 || v >= nv || !P[size_t(v)].allFinite()) return report;
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) return report;
  }
  auto zero_area = [&](const std::array<int, 3>& t) { return has_zero_area(P[size_t(t[0])], P[size_t(t[1])], P[size_t(t[2])]); };
  std::vector<int> slivers;
  for (size_t t = 0; t < T.size(); ++t)
    if (zero_area(T[t])) slivers.push_back(int(t));
  if (slivers.empty()) return report;
  // The two triangles on each edge (a manifold, consistently oriented surface is required).
  std::unordered_map<uint64_t, std::array<int, 2>> on_edge;
  on_edge.reserve(T.size() * 2);
  for (size_t t = 0; t < T.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      auto [it, added] = on_edge.try_emplace(undirected_edge_key(T[t][size_t(k)], T[t][size_t((k + 1) % 3)]), std::array<int, 2>{int(t), -1});
      if (added) continue;
      if (it->second[1] >= 0) return report;
      it->second[1] = int(t);
    }
  for (const auto& [key, pair] : on_edge)
    if (pair[1] < 0) return report;
  auto other = [&](int a, int b, int t) {
    const auto& pair = on_edge.at(undirected_edge_key(a, b));
    return pair[0] == t ? pair[1] : pair[0];
  };
  auto replace = [&](int a, int b, int from, int to) {
    auto& pair = on_edge.at(undirected_edge_key(a, b));
    (pair[0] == from ? pair[0] : pair[1]) = to;
  };
  std::vector<char> flipped(T.size(), 0);
  std::vector<int> pending = slivers;
  for (bool progress = true; progress && !pending.empty();) {
    progress = false;
    std::vector<int> left;
    for (int s : pending) {
      const auto tri = T[size_t(s)];
      if (!zero_area(tri)) {
        progress = true;  // a neighbour's flip already mended it
        continue;
      }
      // The longest edge ab, c the corner opposite it.
      int k = 0;
      double longest = -1;
      for (int i = 0; i < 3; ++i) {
        const double length = (P[size_t(tri[size_t((i + 1) % 3)])] - P[size_t(tri[size_t(i)])]).squaredNorm();
        if (length > longest) {
          longest = length;
          k = i;
        }
      }
      const int a = tri[size_t(k)], b = tri[size_t((k + 1) % 3)], c = tri[size_t((k + 2) % 3)];
      const int n = other(a, b, s);
      const auto& across = T[size_t(n)];
      int d = -1;
      bool opposite = false;  // n traverses the edge from b to a
      for (int i = 0; i < 3; ++i) {
        if (across[size_t(i)] != a && across[size_t(i)] != b) d = across[size_t(i)];
        if (across[size_t(i)] == b && across[size_t((i + 1) % 3)] == a) opposite = true;
      }
      const std::array<int, 3> first{c, a, d}, second{d, b, c};
      if (!opposite || d == c || on_edge.count(undirected_edge_key(c, d)) || zero_area(first) || zero_area(second)) {
        left.push_back(s);
        continue;
      }
      // Edges: ab goes, cd comes; ca stays on s, bc moves from s to n, ad moves from n to s.
      on_edge.erase(undirected_edge_key(a, b));
      on_edge[undirected_edge_key(c, d)] = {s, n};
      replace(b, c, s, n);
      replace(a, d, n, s);
      T[size_t(s)] = first;
      T[size_t(n)] = second;
      progress = true;
      if (!flipped[size_t(s)]) {
        flipped[size_t(s)] = 1;
        ++report.slivers_flipped;
        if (report.first_flipped.size() < options.examples) {
          report.first_flipped.push_back(s);
          report.first_places.push_back(P[size_t(c)]);
        }
      }
    }
    pending = std::move(left);
  }
  report.left_in_place = pending.size();
  return report;
}

}  // namespace dthex
