// SPDX-License-Identifier: MIT
#include <dthex/repair/remove_small_islands.h>

#include <algorithm>
#include <numeric>

namespace dthex {

RemoveSmallIslandsReport remove_small_islands(TriSurface& surface, const RemoveSmallIslandsOptions& options) {
  RemoveSmallIslandsReport report;
  auto& T = surface.triangles;
  const int nv = int(surface.points.size());
  if (options.min_triangles == 0 || T.empty()) return report;
  for (const auto& tri : T)
    for (int v : tri)
      if (v < 0 || v >= nv) return report;
  // Union-find over vertices: an island is a class of vertices joined by triangles.
  std::vector<int> parent(static_cast<size_t>(nv));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[size_t(x)] != x) {
      parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
      x = parent[size_t(x)];
    }
    return x;
  };
  for (const auto& tri : T)
    for (int k = 1; k < 3; ++k) {
      const int a = find(tri[0]), b = find(tri[size_t(k)]);
      if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);
    }
  std::vector<size_t> size(size_t(nv), 0);
  for (const auto& tri : T) ++size[size_t(find(tri[0]))];
  const int largest = int(std::max_element(size.begin(), size.end()) - size.begin());
  std::vector<char> dropped_island(size_t(nv), 0);
  std::vector<std::array<int, 3>> kept;
  kept.reserve(T.size());
  for (size_t t = 0; t < T.size(); ++t) {
    const int root = find(T[t][0]);
    if (root == largest || size[size_t(root)] >= options.min_triangles) {
      kept.push_back(T[t]);
      continue;
    }
    ++report.triangles_dropped;
    if (!dropped_island[size_t(root)]) {
      dropped_island[size_t(root)] = 1;
      ++report.islands_dropped;
      if (report.first_triangles.size() < options.examples) {
        report.first_triangles.push_back(int(t));
        const auto& P = surface.points;
        report.first_places.push_back((P[size_t(T[t][0])] + P[size_t(T[t][1])] + P[size_t(T[t][2])]) / 3.0);
      }
    }
  }
  if (report.triangles_dropped) T = std::move(kept);
  return report;
}

}  // namespace dthex
