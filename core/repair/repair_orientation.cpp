// SPDX-License-Identifier: MIT
#include <dthex/repair/repair_orientation.h>

#include <dthex/mesh/half_edges.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>

namespace dthex {

RepairOrientationReport repair_orientation(TriSurface& surface, const RepairOrientationOptions& options) {
  RepairOrientationReport report;
  auto& T = surface.triangles;
  const auto& P = surface.points;
  const int nv = int(P.size()), nt = int(T.size());
  for (const auto& tri : T) {
    for (int v : tri)
      if (v < 0 || v >= nv) {
        report.skipped_not_manifold = true;
        return report;
      }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) {
      report.skipped_not_manifold = true;
      return report;
    }
  }
  const std::vector<HalfEdge> half_edges = sorted_half_edges(T);
  for (size_t k = 0; k < half_edges.size(); k += 2)
    if (k + 1 >= half_edges.size() || half_edges[k + 1].key != half_edges[k].key ||
        (k + 2 < half_edges.size() && half_edges[k + 2].key == half_edges[k].key)) {
      report.skipped_not_manifold = true;
      return report;
    }
  // Each triangle's three neighbours, and whether it disagrees with each (both traverse the
  // shared edge the same way).
  struct Neighbour {
    int triangle;
    bool disagrees;
  };
  std::vector<std::array<Neighbour, 3>> neighbours(static_cast<size_t>(nt));
  std::vector<int> filled(size_t(nt), 0);
  for (size_t k = 0; k < half_edges.size(); k += 2) {
    const HalfEdge &a = half_edges[k], &b = half_edges[k + 1];
    const bool disagrees = a.from == b.from;
    neighbours[size_t(a.triangle)][size_t(filled[size_t(a.triangle)]++)] = {b.triangle, disagrees};
    neighbours[size_t(b.triangle)][size_t(filled[size_t(b.triangle)]++)] = {a.triangle, disagrees};
  }
  auto area = [&](int t) {
    const auto& tri = T[size_t(t)];
    return 0.5 * (P[size_t(tri[1])] - P[size_t(tri[0])]).cross(P[size_t(tri[2])] - P[size_t(tri[0])]).norm();
  };
  // Class 0 or 1 per triangle (-1 unvisited), found component by component from its lowest id.
  std::vector<int> side(size_t(nt), -1);
  std::vector<int> turned, component, stack;
  for (int seed = 0; seed < nt; ++seed) {
    if (side[size_t(seed)] >= 0) continue;
    component.clear();
    stack.assign(1, seed);
    side[size_t(seed)] = 0;
    bool orientable = true;
    while (!stack.empty()) {
      const int t = stack.back();
      stack.pop_back();
      component.push_back(t);
      for (const Neighbour& n : neighbours[size_t(t)]) {
        const int expected = side[size_t(t)] ^ int(n.disagrees);
        if (side[size_t(n.triangle)] < 0) {
          side[size_t(n.triangle)] = expected;
          stack.push_back(n.triangle);
        } else if (side[size_t(n.triangle)] != expected) {
          orientable = false;
        }
      }
    }
    if (!orientable) {
      ++report.non_orientable_components;
      continue;
    }
    size_t count[2] = {0, 0};
    double class_area[2] = {0, 0};
    for (int t : component) {
      ++count[side[size_t(t)]];
      class_area[side[size_t(t)]] += area(t);
    }
    if (count[1] == 0) continue;
    const int turn = count[0] != count[1] ? (count[0] < count[1] ? 0 : 1) : (class_area[0] < class_area[1] ? 0 : 1);
    ++report.components_repaired;
    for (int t : component)
      if (side[size_t(t)] == turn) turned.push_back(t);
  }
  std::sort(turned.begin(), turned.end());
  for (int t : turned) std::swap(T[size_t(t)][1], T[size_t(t)][2]);
  report.triangles_turned = turned.size();
  report.first_turned.assign(turned.begin(), turned.begin() + long(std::min(turned.size(), options.examples)));
  return report;
}

}  // namespace dthex
