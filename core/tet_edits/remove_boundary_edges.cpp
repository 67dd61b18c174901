// SPDX-License-Identifier: MIT
#include <dthex/tet_edits/remove_boundary_edges.h>

#include <dthex/mesh/quality.h>
#include <dthex/tet_edits/edge_removal.h>

#include <algorithm>

namespace dthex {
namespace {

using Edge = std::pair<int, int>;

// Worst shape among the tets a midpoint split of pq would make.
double midpoint_split_worst(const EditableTets& m, int p, int q, const std::vector<int>& ring) {
  const Vec3 mid = 0.5 * (m.point(p) + m.point(q));
  double worst = 1;
  for (size_t i = 0; i < ring.size(); ++i) {
    const Vec3& a = m.point(ring[i]);
    const Vec3& b = m.point(ring[(i + 1) % ring.size()]);
    worst = std::min({worst, tet_shape(m.point(p), mid, a, b), tet_shape(mid, m.point(q), a, b)});
  }
  return worst;
}

}  // namespace

RemoveBoundaryEdgesReport remove_boundary_edges(TetMesh& mesh, const RemoveBoundaryEdgesOptions& options) {
  RemoveBoundaryEdgesReport report;
  report.tets_before = mesh.tets.size();
  std::vector<char> on_boundary(mesh.points.size(), 0);
  std::vector<Edge> boundary_edges;
  for (const auto& f : mesh.boundary_faces)
    for (int i = 0; i < 3; ++i) {
      on_boundary[size_t(f[size_t(i)])] = 1;
      boundary_edges.emplace_back(std::minmax(f[size_t(i)], f[size_t((i + 1) % 3)]));
    }
  std::sort(boundary_edges.begin(), boundary_edges.end());
  std::vector<Edge> candidates;
  for (const auto& t : mesh.tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const Edge e = std::minmax(t[size_t(i)], t[size_t(j)]);
        if (on_boundary[size_t(e.first)] && on_boundary[size_t(e.second)] &&
            !std::binary_search(boundary_edges.begin(), boundary_edges.end(), e))
          candidates.push_back(e);
      }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  report.candidates = candidates.size();

  // The edges still to remove, and for each boundary vertex the ones it ends.
  std::vector<char> pending(candidates.size(), 1), queued(candidates.size(), 1);
  std::vector<std::vector<int>> vertex_candidates(mesh.points.size());
  for (size_t c = 0; c < candidates.size(); ++c) {
    vertex_candidates[size_t(candidates[c].first)].push_back(int(c));
    vertex_candidates[size_t(candidates[c].second)].push_back(int(c));
  }
  std::vector<int> worklist(candidates.size());
  for (size_t c = 0; c < candidates.size(); ++c) worklist[c] = int(candidates.size() - 1 - c);
  // A change to the tets around a vertex changes the rings of the pending edges it ends.
  auto requeue_around = [&](const std::vector<int>& vertices) {
    for (int v : vertices) {
      if (size_t(v) >= vertex_candidates.size()) continue;
      for (int c : vertex_candidates[size_t(v)])
        if (pending[size_t(c)] && !queued[size_t(c)]) {
          queued[size_t(c)] = 1;
          worklist.push_back(c);
        }
    }
  };
  auto vertices_of = [&](const std::vector<int>& tets) {
    std::vector<int> out;
    for (int t : tets)
      for (int v : mesh.tets[size_t(t)]) out.push_back(v);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  };

  EditableTets tets(mesh);
  for (;;) {
    while (!worklist.empty()) {
      const int c = worklist.back();
      worklist.pop_back();
      queued[size_t(c)] = 0;
      const auto [p, q] = candidates[size_t(c)];
      const std::vector<int> around = tets.tets_with(p, q);
      if (around.empty()) {
        pending[size_t(c)] = 0;
        continue;
      }
      const auto best = best_edge_removal(tets, p, q, around, options.max_ring, on_boundary);
      if (!best) continue;
      const double needed =
          std::max(options.min_shape, options.min_shape_ratio * midpoint_split_worst(tets, p, q, best->ring));
      if (!(best->worst >= needed)) continue;
      const std::vector<int> touched = vertices_of(around);
      tets.replace(around, best->new_tets);
      pending[size_t(c)] = 0;
      ++report.removed;
      requeue_around(touched);
    }
    if (!options.split_when_stuck) break;
    // No flip is left: split one pending edge at its midpoint. The new interior point joins
    // the rings of the edges around it, which may then go by flips.
    int chosen = -1;
    for (size_t c = 0; c < candidates.size() && chosen < 0; ++c)
      if (pending[c]) chosen = int(c);
    if (chosen < 0) break;
    pending[size_t(chosen)] = 0;
    const auto [p, q] = candidates[size_t(chosen)];
    const std::vector<int> around = tets.tets_with(p, q);
    if (around.empty()) continue;
    const int m = tets.add_point(0.5 * (mesh.points[size_t(p)] + mesh.points[size_t(q)]));
    std::vector<std::array<int, 4>> halves;
    for (int t : around) {
      std::array<int, 4> keeps_p = mesh.tets[size_t(t)], keeps_q = keeps_p;
      for (size_t i = 0; i < 4; ++i) {
        if (keeps_p[i] == q) keeps_p[i] = m;
        if (keeps_q[i] == p) keeps_q[i] = m;
      }
      halves.push_back(keeps_p);
      halves.push_back(keeps_q);
    }
    const std::vector<int> touched = vertices_of(around);
    tets.replace(around, halves);
    on_boundary.push_back(0);
    ++report.split;
    requeue_around(touched);
  }
  tets.compact();
  report.tets_after = mesh.tets.size();
  return report;
}

}  // namespace dthex
