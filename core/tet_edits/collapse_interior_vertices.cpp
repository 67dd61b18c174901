// SPDX-License-Identifier: MIT
#include <dthex/tet_edits/collapse_interior_vertices.h>

#include <dthex/mesh/quality.h>
#include <dthex/tet_edits/edge_removal.h>

#include <algorithm>

namespace dthex {

CollapseInteriorVerticesReport collapse_interior_vertices(TetMesh& mesh, const CollapseInteriorVerticesOptions& options) {
  CollapseInteriorVerticesReport report;
  report.tets_before = mesh.tets.size();
  std::vector<char> on_boundary(mesh.points.size(), 0);
  std::vector<std::array<int, 3>> boundary_faces;
  for (const auto& f : mesh.boundary_faces) {
    for (int v : f) on_boundary[size_t(v)] = 1;
    std::array<int, 3> key = f;
    std::sort(key.begin(), key.end());
    boundary_faces.push_back(key);
  }
  std::sort(boundary_faces.begin(), boundary_faces.end());
  EditableTets tets(mesh);
  std::vector<char> gone(mesh.points.size(), 0);
  for (int pass = 0; pass < options.max_passes; ++pass) {
    const size_t before = report.collapsed;
    for (size_t v = 0; v < mesh.points.size(); ++v) {
      if (on_boundary[v] || gone[v]) continue;
      const std::vector<int> star = tets.tets_of(int(v));
      if (star.empty()) continue;
      const double old_worst = worst_shape(tets, star);
      std::vector<int> neighbours;
      for (int t : star)
        for (int x : tets.tet(t))
          if (x != int(v)) neighbours.push_back(x);
      std::sort(neighbours.begin(), neighbours.end());
      neighbours.erase(std::unique(neighbours.begin(), neighbours.end()), neighbours.end());
      double best = -1;
      int best_w = -1;
      std::vector<std::array<int, 4>> best_tets;
      for (int w : neighbours) {
        EdgeContraction merge = contract_edge(tets, int(v), w, star);
        if (merge.dropped == 0) continue;
        if (!(merge.worst > 0) || merge.worst < options.min_shape_ratio * old_worst || merge.worst <= best) continue;
        // New edges from w and faces through w must not join only boundary vertices.
        bool ok = true;
        if (on_boundary[size_t(w)])
          for (const auto& x : merge.new_tets) {
            std::array<int, 3> others{};
            int k = 0;
            for (int y : x)
              if (y != w) others[size_t(k++)] = y;
            for (int i = 0; i < 3 && ok; ++i) {
              const int a = others[size_t(i)];
              if (on_boundary[size_t(a)] && !tets.has_edge(w, a)) ok = false;
              const int b = others[size_t((i + 1) % 3)];
              if (on_boundary[size_t(a)] && on_boundary[size_t(b)]) {
                std::array<int, 3> key{w, a, b};
                std::sort(key.begin(), key.end());
                if (!std::binary_search(boundary_faces.begin(), boundary_faces.end(), key)) ok = false;
              }
            }
            if (!ok) break;
          }
        if (!ok) continue;
        const int cap = on_boundary[size_t(w)] ? options.max_tets_at_kept_vertex / 2 : options.max_tets_at_kept_vertex;
        if (merge.tets_at_kept > size_t(cap)) continue;
        best = merge.worst;
        best_w = w;
        best_tets = std::move(merge.new_tets);
      }
      if (best_w < 0) continue;
      tets.replace(star, best_tets);
      gone[v] = 1;
      ++report.collapsed;
    }
    if (report.collapsed == before) break;
  }
  tets.compact();
  drop_points(mesh, gone);
  report.tets_after = mesh.tets.size();
  return report;
}

}  // namespace dthex
