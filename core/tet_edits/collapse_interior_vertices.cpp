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
      std::vector<int> best_removed;
      for (int w : neighbours) {
        std::vector<std::array<int, 4>> moved;
        std::vector<int> removed;
        double worst = 1;
        bool ok = true;
        for (int t : star) {
          std::array<int, 4> x = tets.tet(t);
          if (std::find(x.begin(), x.end(), w) != x.end()) {
            removed.push_back(t);
            continue;
          }
          std::replace(x.begin(), x.end(), int(v), w);
          const double shape = tet_shape(tets.point(x[0]), tets.point(x[1]), tets.point(x[2]), tets.point(x[3]));
          worst = std::min(worst, shape);
          if (!(shape > 0) || shape < options.min_shape_ratio * old_worst || shape <= best) {
            ok = false;
            break;
          }
          // New edges from w and faces through w must not join only boundary vertices.
          if (on_boundary[size_t(w)]) {
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
          }
          if (!ok) break;
          moved.push_back(x);
        }
        if (!ok || removed.empty()) continue;
        const int cap = on_boundary[size_t(w)] ? options.max_tets_at_kept_vertex / 2 : options.max_tets_at_kept_vertex;
        if (tets.tets_of(w).size() - removed.size() + moved.size() > size_t(cap)) continue;
        best = worst;
        best_w = w;
        best_tets = std::move(moved);
        best_removed = std::move(removed);
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
