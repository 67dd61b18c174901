// SPDX-License-Identifier: MIT
#include <dthex/tets/remove_flat_valence3_vertices.h>

#include <dthex/mesh/incidence.h>
#include <dthex/mesh/quality.h>

#include <algorithm>
#include <set>

namespace dthex {

size_t remove_flat_valence3_vertices(TriSurface& surface, const RemoveFlatValence3Options& options) {
  const size_t n = surface.points.size();
  const NodeCellIncidence vertex_triangles(n, surface.triangles);
  std::set<std::array<int, 3>> triangle_keys;
  for (const auto& tri : surface.triangles) {
    std::array<int, 3> key = tri;
    std::sort(key.begin(), key.end());
    triangle_keys.insert(key);
  }
  std::vector<char> removed_vertex(n, 0), touched(n, 0), removed_triangle(surface.triangles.size(), 0);
  std::vector<std::array<int, 3>> added;
  size_t removed = 0;
  for (size_t v = 0; v < n; ++v) {
    if (vertex_triangles[v].size() != 3 || touched[v]) continue;
    // The outer edge x -> y of each triangle (v, x, y), in the triangle's own orientation.
    std::vector<std::pair<int, int>> outer;
    for (int t : vertex_triangles[v]) {
      const auto& tri = surface.triangles[size_t(t)];
      const int at = int(std::find(tri.begin(), tri.end(), int(v)) - tri.begin());
      outer.emplace_back(tri[size_t((at + 1) % 3)], tri[size_t((at + 2) % 3)]);
    }
    // They close one cycle a -> b -> c -> a: the replacing triangle, same orientation.
    const int a = outer[0].first, b = outer[0].second;
    int c = -1;
    for (const auto& [x, y] : outer)
      if (x == b) c = y;
    if (c < 0 || a == c || b == c) continue;
    bool closes = false;
    for (const auto& [x, y] : outer) closes |= (x == c && y == a);
    if (!closes) continue;
    std::array<int, 3> key{a, b, c};
    std::sort(key.begin(), key.end());
    if (triangle_keys.count(key)) continue;
    if (vertex_triangles[size_t(a)].size() < 4 || vertex_triangles[size_t(b)].size() < 4 ||
        vertex_triangles[size_t(c)].size() < 4 || touched[size_t(a)] || touched[size_t(b)] || touched[size_t(c)])
      continue;
    const auto& p = surface.points;
    // The shape of a tet is independent of its orientation here: take the positive one.
    const double cap = std::max(tet_shape(p[v], p[size_t(a)], p[size_t(b)], p[size_t(c)]),
                                tet_shape(p[v], p[size_t(a)], p[size_t(c)], p[size_t(b)]));
    if (cap >= options.max_cap_shape) continue;
    for (int t : vertex_triangles[v]) removed_triangle[size_t(t)] = 1;
    added.push_back({a, b, c});
    triangle_keys.insert(key);
    removed_vertex[v] = 1;
    touched[v] = touched[size_t(a)] = touched[size_t(b)] = touched[size_t(c)] = 1;
    ++removed;
  }
  if (!removed) return 0;
  std::vector<int> new_index(n, -1);
  std::vector<Vec3> points;
  for (size_t v = 0; v < n; ++v)
    if (!removed_vertex[v]) {
      new_index[v] = int(points.size());
      points.push_back(surface.points[v]);
    }
  std::vector<std::array<int, 3>> triangles;
  for (size_t t = 0; t < surface.triangles.size(); ++t)
    if (!removed_triangle[t]) triangles.push_back(surface.triangles[t]);
  triangles.insert(triangles.end(), added.begin(), added.end());
  for (auto& tri : triangles)
    for (int& v : tri) v = new_index[size_t(v)];
  surface.points = std::move(points);
  surface.triangles = std::move(triangles);
  return removed;
}

}  // namespace dthex
