// SPDX-License-Identifier: MIT
#include <dthex/repair/remove_small_islands.h>

#include <dthex/repair/remove_redundant_triangles.h>
#include <dthex/repair/repair_orientation.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>

namespace dthex {

namespace {

//! Per island root (the vertex find() gives), the volume it encloses, or -1 when it has none:
//! it is not closed and manifold, not orientable, or not finite.
template <class Find>
std::vector<double> island_volumes(const TriSurface& surface, Find& find) {
  const auto& T = surface.triangles;
  const size_t nv = surface.points.size();
  std::vector<std::vector<int>> triangles_of(nv);
  for (size_t t = 0; t < T.size(); ++t) triangles_of[size_t(find(T[t][0]))].push_back(int(t));
  std::vector<double> volume(nv, -1.0);
  std::vector<int> local(nv, -1);
  for (size_t root = 0; root < nv; ++root) {
    if (triangles_of[root].empty()) continue;
    TriSurface island;  // the island alone, its vertices renumbered
    for (int t : triangles_of[root]) {
      std::array<int, 3> tri = T[size_t(t)];
      for (int& v : tri) {
        if (local[size_t(v)] < 0) {
          local[size_t(v)] = int(island.points.size());
          island.points.push_back(surface.points[size_t(v)]);
        }
        v = local[size_t(v)];
      }
      island.triangles.push_back(tri);
    }
    for (int t : triangles_of[root])
      for (int v : T[size_t(t)]) local[size_t(v)] = -1;
    bool collapsed = false;
    for (const auto& tri : island.triangles) collapsed |= tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0];
    if (collapsed || !is_closed_manifold(island.triangles, island.points.size())) continue;
    const RepairOrientationReport turned = repair_orientation(island);
    if (turned.skipped_not_manifold || turned.non_orientable_components) continue;
    const Vec3 origin = island.points[0];
    double sum = 0;
    for (const auto& tri : island.triangles) {
      const Vec3 a = island.points[size_t(tri[0])] - origin, b = island.points[size_t(tri[1])] - origin,
                 c = island.points[size_t(tri[2])] - origin;
      sum += a.dot(b.cross(c)) / 6.0;
    }
    if (std::isfinite(sum)) volume[root] = std::abs(sum);
  }
  return volume;
}

}  // namespace

RemoveSmallIslandsReport remove_small_islands(TriSurface& surface, const RemoveSmallIslandsOptions& options) {
  RemoveSmallIslandsReport report;
  auto& T = surface.triangles;
  const int nv = int(surface.points.size());
  if ((options.min_triangles == 0 && !(options.min_volume_fraction > 0)) || T.empty()) return report;
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
  std::vector<char> too_small(size_t(nv), 0);
  for (int root = 0; root < nv; ++root)
    too_small[size_t(root)] = size[size_t(root)] > 0 && root != largest && size[size_t(root)] < options.min_triangles;
  if (options.min_volume_fraction > 0) {
    const std::vector<double> volume = island_volumes(surface, find);
    int largest_volume = -1;
    for (int root = 0; root < nv; ++root)
      if (volume[size_t(root)] > 0 && (largest_volume < 0 || volume[size_t(root)] > volume[size_t(largest_volume)]))
        largest_volume = root;
    for (int root = 0; root < nv && largest_volume >= 0; ++root)
      if (root != largest_volume && volume[size_t(root)] >= 0 && !too_small[size_t(root)] &&
          volume[size_t(root)] < options.min_volume_fraction * volume[size_t(largest_volume)]) {
        too_small[size_t(root)] = 1;
        ++report.dropped_by_volume;
      }
  }
  std::vector<char> dropped_island(size_t(nv), 0);
  std::vector<std::array<int, 3>> kept;
  kept.reserve(T.size());
  for (size_t t = 0; t < T.size(); ++t) {
    const int root = find(T[t][0]);
    if (!too_small[size_t(root)]) {
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
