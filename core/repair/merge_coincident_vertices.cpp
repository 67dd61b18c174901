// SPDX-License-Identifier: MIT
#include <dthex/repair/merge_coincident_vertices.h>

#include <algorithm>
#include <numeric>

namespace dthex {

MergeCoincidentVerticesReport merge_coincident_vertices(TriSurface& surface,
                                                        const MergeCoincidentVerticesOptions& options) {
  MergeCoincidentVerticesReport report;
  const auto& P = surface.points;
  // Finite points sorted by position, then id: equal positions form runs, the lowest id first.
  // (On finite values < is a strict weak order in which -0 and +0 are equivalent.)
  std::vector<int> order;
  order.reserve(P.size());
  for (size_t v = 0; v < P.size(); ++v)
    if (P[v].allFinite()) order.push_back(int(v));
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const Vec3 &p = P[size_t(a)], &q = P[size_t(b)];
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    if (p.z() != q.z()) return p.z() < q.z();
    return a < b;
  });
  std::vector<int> target(P.size());
  std::iota(target.begin(), target.end(), 0);
  std::vector<int> merged;
  for (size_t k = 1; k < order.size(); ++k) {
    const int previous = order[k - 1], v = order[k];
    if (P[size_t(v)] == P[size_t(previous)]) {
      target[size_t(v)] = target[size_t(previous)];
      merged.push_back(v);
    }
  }
  if (merged.empty()) return report;
  std::sort(merged.begin(), merged.end());
  report.vertices_merged = merged.size();
  for (size_t k = 0; k < merged.size() && k < options.examples; ++k) {
    report.first_merged.push_back(merged[k]);
    report.first_kept.push_back(target[size_t(merged[k])]);
    report.first_places.push_back(P[size_t(merged[k])]);
  }
  for (auto& tri : surface.triangles)
    for (int& v : tri)
      if (v >= 0 && size_t(v) < P.size()) v = target[size_t(v)];
  return report;
}

}  // namespace dthex
