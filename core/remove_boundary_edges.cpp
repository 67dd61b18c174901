// SPDX-License-Identifier: MIT
#include "core/remove_boundary_edges.h"

#include "core/quality.h"

#include <algorithm>
#include <limits>
#include <optional>

namespace dthex {
namespace {

using Edge = std::pair<int, int>;

// The tets of a mesh being edited: dead tets stay in place (indices stay valid) and each
// vertex lists the tets that use it, dead ones dropped when met.
class EditableTets {
 public:
  explicit EditableTets(TetMesh& mesh) : mesh_(mesh), alive_(mesh.tets.size(), 1), vertex_tets_(mesh.points.size()) {
    for (size_t t = 0; t < mesh.tets.size(); ++t)
      for (int v : mesh.tets[t]) vertex_tets_[size_t(v)].push_back(int(t));
  }

  const Vec3& point(int v) const { return mesh_.points[size_t(v)]; }
  const std::array<int, 4>& tet(int t) const { return mesh_.tets[size_t(t)]; }

  std::vector<int> tets_with(int a, int b) {
    std::vector<int> out;
    auto& list = vertex_tets_[size_t(a)];
    list.erase(std::remove_if(list.begin(), list.end(), [&](int t) { return !alive_[size_t(t)]; }), list.end());
    for (int t : list) {
      const auto& x = tet(t);
      if (std::find(x.begin(), x.end(), b) != x.end()) out.push_back(t);
    }
    return out;
  }

  bool has_edge(int a, int b) {
    for (int t : vertex_tets_[size_t(a)]) {
      if (!alive_[size_t(t)]) continue;
      const auto& x = tet(t);
      if (std::find(x.begin(), x.end(), b) != x.end()) return true;
    }
    return false;
  }

  int add_point(const Vec3& x) {
    mesh_.points.push_back(x);
    vertex_tets_.emplace_back();
    return int(mesh_.points.size() - 1);
  }

  void replace(const std::vector<int>& old_tets, const std::vector<std::array<int, 4>>& new_tets) {
    for (int t : old_tets) alive_[size_t(t)] = 0;
    for (const auto& x : new_tets) {
      const int t = int(mesh_.tets.size());
      mesh_.tets.push_back(x);
      alive_.push_back(1);
      for (int v : x) vertex_tets_[size_t(v)].push_back(t);
    }
  }

  //! Drops the dead tets from the mesh.
  void compact() {
    size_t kept = 0;
    for (size_t t = 0; t < mesh_.tets.size(); ++t)
      if (alive_[t]) mesh_.tets[kept++] = mesh_.tets[t];
    mesh_.tets.resize(kept);
  }

 private:
  TetMesh& mesh_;
  std::vector<char> alive_;
  std::vector<std::vector<int>> vertex_tets_;
};

double shape_of(const EditableTets& m, int a, int b, int c, int d) {
  return tet_shape(m.point(a), m.point(b), m.point(c), m.point(d));
}

// The ring of vertices around edge pq, ordered so that every tet around the edge is
// (p, q, r[i], r[i+1]) in an even permutation of its stored order; nothing when the tets do
// not close one simple ring (an edge on the boundary).
std::optional<std::vector<int>> ring_around(const EditableTets& m, int p, int q, const std::vector<int>& tets) {
  std::vector<std::pair<int, int>> next;  // (a, b): a tet (p, q, a, b)
  for (int t : tets) {
    const auto& x = m.tet(t);
    int pos[4] = {-1, -1, -1, -1}, others[2] = {-1, -1}, n_other = 0;
    for (int i = 0; i < 4; ++i) {
      if (x[size_t(i)] == p) pos[0] = i;
      else if (x[size_t(i)] == q) pos[1] = i;
      else if (n_other < 2) {
        pos[2 + n_other] = i;
        others[n_other++] = x[size_t(i)];
      }
    }
    if (n_other != 2 || pos[0] < 0 || pos[1] < 0) return std::nullopt;
    int inversions = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) inversions += pos[i] > pos[j];
    if (inversions % 2) std::swap(others[0], others[1]);
    next.emplace_back(others[0], others[1]);
  }
  std::vector<int> ring;
  int at = next.front().first;
  for (size_t step = 0; step < next.size(); ++step) {
    ring.push_back(at);
    const auto it = std::find_if(next.begin(), next.end(), [&](const auto& ab) { return ab.first == at; });
    if (it == next.end()) return std::nullopt;
    at = it->second;
  }
  if (at != ring.front()) return std::nullopt;
  std::vector<int> sorted = ring;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return std::nullopt;
  return ring;
}

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

// The triangulation of the ring polygon whose tets (joined to p and to q) have the best
// worst shape, among those with no diagonal between two boundary vertices (or already an
// edge) and no triangle of three boundary vertices: the classic dynamic program over
// sub-polygons. Returns the worst shape (-1 when none is allowed) and the triangles.
struct RingTriangulation {
  double worst = -1;
  std::vector<std::array<int, 3>> triangles;  // ring positions, each in ring order
};

RingTriangulation best_ring_triangulation(EditableTets& m, int p, int q, const std::vector<int>& ring,
                                          const std::vector<char>& on_boundary) {
  const int k = int(ring.size());
  auto boundary = [&](int i) { return on_boundary[size_t(ring[size_t(i)])] != 0; };
  auto is_side = [&](int i, int j) { return j - i == 1 || (i == 0 && j == k - 1); };
  std::vector<std::vector<char>> diagonal_ok(size_t(k), std::vector<char>(size_t(k), 1));
  for (int i = 0; i < k; ++i)
    for (int j = i + 1; j < k; ++j)
      if (!is_side(i, j))
        diagonal_ok[size_t(i)][size_t(j)] =
            !(boundary(i) && boundary(j)) && !m.has_edge(ring[size_t(i)], ring[size_t(j)]);
  const double none = -1;
  std::vector<std::vector<double>> best(size_t(k), std::vector<double>(size_t(k), none));
  std::vector<std::vector<int>> split_at(size_t(k), std::vector<int>(size_t(k), -1));
  for (int i = 0; i + 1 < k; ++i) best[size_t(i)][size_t(i + 1)] = std::numeric_limits<double>::max();
  for (int span = 2; span < k; ++span)
    for (int i = 0; i + span < k; ++i) {
      const int j = i + span;
      if (!is_side(i, j) && !diagonal_ok[size_t(i)][size_t(j)]) continue;
      for (int c = i + 1; c < j; ++c) {
        const double sub = std::min(best[size_t(i)][size_t(c)], best[size_t(c)][size_t(j)]);
        if (sub <= best[size_t(i)][size_t(j)]) continue;
        if (boundary(i) && boundary(c) && boundary(j)) continue;
        const int a = ring[size_t(i)], b = ring[size_t(c)], d = ring[size_t(j)];
        const double shape = std::min({sub, shape_of(m, a, b, d, q), shape_of(m, a, d, b, p)});
        if (shape > best[size_t(i)][size_t(j)]) {
          best[size_t(i)][size_t(j)] = shape;
          split_at[size_t(i)][size_t(j)] = c;
        }
      }
    }
  RingTriangulation out;
  if (split_at[0][size_t(k - 1)] < 0) return out;
  out.worst = best[0][size_t(k - 1)];
  std::vector<std::pair<int, int>> todo = {{0, k - 1}};
  while (!todo.empty()) {
    const auto [i, j] = todo.back();
    todo.pop_back();
    if (j - i < 2) continue;
    const int c = split_at[size_t(i)][size_t(j)];
    out.triangles.push_back({i, c, j});
    todo.emplace_back(i, c);
    todo.emplace_back(c, j);
  }
  return out;
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
      if (int(around.size()) > options.max_ring) continue;
      const auto ring = ring_around(tets, p, q, around);
      if (!ring) continue;
      const RingTriangulation best = best_ring_triangulation(tets, p, q, *ring, on_boundary);
      const double needed = std::max(options.min_shape, options.min_shape_ratio * midpoint_split_worst(tets, p, q, *ring));
      if (!(best.worst >= needed && best.worst > 0)) continue;
      std::vector<std::array<int, 4>> added;
      for (const auto& [i, k, j] : best.triangles) {
        const int a = (*ring)[size_t(i)], b = (*ring)[size_t(k)], d = (*ring)[size_t(j)];
        added.push_back({a, b, d, q});
        added.push_back({a, d, b, p});
      }
      const std::vector<int> touched = vertices_of(around);
      tets.replace(around, added);
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
