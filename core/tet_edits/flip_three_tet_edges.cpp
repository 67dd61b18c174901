// SPDX-License-Identifier: MIT
#include <dthex/tet_edits/flip_three_tet_edges.h>

#include <dthex/tet_edits/edge_removal.h>

#include <algorithm>

namespace dthex {

FlipThreeTetEdgesReport flip_three_tet_edges(TetMesh& mesh, const FlipThreeTetEdgesOptions& options) {
  FlipThreeTetEdgesReport report;
  report.tets_before = mesh.tets.size();
  std::vector<char> on_boundary(mesh.points.size(), 0);
  for (const auto& f : mesh.boundary_faces)
    for (int v : f) on_boundary[size_t(v)] = 1;
  EditableTets tets(mesh);
  for (int pass = 0; pass < options.max_passes; ++pass) {
    const size_t flips_before = report.flips;
    std::vector<std::pair<int, int>> edges;
    for (size_t t = 0; t < tets.tet_slots(); ++t) {
      if (!tets.alive(int(t))) continue;
      const auto& x = tets.tet(int(t));
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) edges.emplace_back(std::minmax(x[size_t(i)], x[size_t(j)]));
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    for (const auto& [p, q] : edges) {
      const std::vector<int> around = tets.tets_with(p, q);
      if (around.size() != 3) continue;
      const auto flip = best_edge_removal(tets, p, q, around, 3, on_boundary);
      if (!flip || flip->worst < options.min_shape_ratio * worst_shape(tets, around)) continue;
      tets.replace(around, flip->new_tets);
      ++report.flips;
    }
    if (report.flips == flips_before) break;
  }
  tets.compact();
  report.tets_after = mesh.tets.size();
  return report;
}

}  // namespace dthex
