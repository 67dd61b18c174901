// SPDX-License-Identifier: MIT
#include <dthex/tet_edits/edge_removal.h>

#include <dthex/mesh/quality.h>

#include <algorithm>
#include <limits>

namespace dthex {

EditableTets::EditableTets(TetMesh& mesh) : mesh_(mesh), alive_(mesh.tets.size(), 1), vertex_tets_(mesh.points.size()) {
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int v : mesh.tets[t]) vertex_tets_[size_t(v)].push_back(int(t));
}

std::vector<int> EditableTets::tets_of(int v) {
  auto& list = vertex_tets_[size_t(v)];
  list.erase(std::remove_if(list.begin(), list.end(), [&](int t) { return !alive_[size_t(t)]; }), list.end());
  return list;
}

std::vector<int> EditableTets::tets_with(int a, int b) {
  std::vector<int> out;
  auto& list = vertex_tets_[size_t(a)];
  list.erase(std::remove_if(list.begin(), list.end(), [&](int t) { return !alive_[size_t(t)]; }), list.end());
  for (int t : list) {
    const auto& x = tet(t);
    if (std::find(x.begin(), x.end(), b) != x.end()) out.push_back(t);
  }
  return out;
}

bool EditableTets::has_edge(int a, int b) const {
  for (int t : vertex_tets_[size_t(a)]) {
    if (!alive_[size_t(t)]) continue;
    const auto& x = tet(t);
    if (std::find(x.begin(), x.end(), b) != x.end()) return true;
  }
  return false;
}

int EditableTets::add_point(const Vec3& x) {
  mesh_.points.push_back(x);
  vertex_tets_.emplace_back();
  return int(mesh_.points.size() - 1);
}

void EditableTets::replace(const std::vector<int>& old_tets, const std::vector<std::array<int, 4>>& new_tets) {
  for (int t : old_tets) alive_[size_t(t)] = 0;
  for (const auto& x : new_tets) {
    const int t = int(mesh_.tets.size());
    mesh_.tets.push_back(x);
    alive_.push_back(1);
    for (int v : x) vertex_tets_[size_t(v)].push_back(t);
  }
}

void EditableTets::compact() {
  size_t kept = 0;
  for (size_t t = 0; t < mesh_.tets.size(); ++t)
    if (alive_[t]) mesh_.tets[kept++] = mesh_.tets[t];
  mesh_.tets.resize(kept);
  alive_.assign(kept, 1);
  for (auto& list : vertex_tets_) list.clear();
  for (size_t t = 0; t < kept; ++t)
    for (int v : mesh_.tets[t]) vertex_tets_[size_t(v)].push_back(int(t));
}

namespace {
double shape_of(const EditableTets& m, int a, int b, int c, int d) {
  return tet_shape(m.point(a), m.point(b), m.point(c), m.point(d));
}

}  // namespace

double worst_shape(const EditableTets& m, const std::vector<int>& tets) {
  double worst = 1;
  for (int t : tets) {
    const auto& x = m.tet(t);
    worst = std::min(worst, shape_of(m, x[0], x[1], x[2], x[3]));
  }
  return worst;
}

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


std::vector<std::array<int, 4>> tets_of_ring_triangulation(int p, int q, const std::vector<int>& ring,
                                                             const RingTriangulation& triangulation) {
  std::vector<std::array<int, 4>> out;
  for (const auto& [i, c, j] : triangulation.triangles) {
    const int a = ring[size_t(i)], b = ring[size_t(c)], d = ring[size_t(j)];
    out.push_back({a, b, d, q});
    out.push_back({a, d, b, p});
  }
  return out;
}

std::optional<EdgeRemoval> best_edge_removal(EditableTets& m, int p, int q, const std::vector<int>& around,
                                             int max_ring, const std::vector<char>& on_boundary) {
  if (int(around.size()) > max_ring) return std::nullopt;
  auto ring = ring_around(m, p, q, around);  // none for a boundary edge
  if (!ring) return std::nullopt;
  const RingTriangulation tri = best_ring_triangulation(m, p, q, *ring, on_boundary);
  if (!(tri.worst > 0)) return std::nullopt;
  EdgeRemoval removal;
  removal.new_tets = tets_of_ring_triangulation(p, q, *ring, tri);
  removal.ring = std::move(*ring);
  removal.worst = tri.worst;
  return removal;
}

EdgeContraction contract_edge(EditableTets& m, int u, int w, const std::vector<int>& star) {
  EdgeContraction c;
  for (int t : star) {
    std::array<int, 4> x = m.tet(t);
    if (std::find(x.begin(), x.end(), w) != x.end()) {
      ++c.dropped;
      continue;
    }
    std::replace(x.begin(), x.end(), u, w);
    const double shape = shape_of(m, x[0], x[1], x[2], x[3]);
    c.worst = shape > 0 ? std::min(c.worst, shape) : 0.0;
    c.new_tets.push_back(x);
  }
  c.tets_at_kept = m.tets_of(w).size() - c.dropped + c.new_tets.size();
  return c;
}

void drop_points(TetMesh& mesh, const std::vector<char>& gone) {
  std::vector<int> new_index(mesh.points.size(), -1);
  std::vector<Vec3> points;
  for (size_t v = 0; v < mesh.points.size(); ++v)
    if (!gone[v]) {
      new_index[v] = int(points.size());
      points.push_back(mesh.points[v]);
    }
  for (auto& t : mesh.tets)
    for (int& x : t) x = new_index[size_t(x)];
  for (auto& f : mesh.boundary_faces)
    for (int& x : f) x = new_index[size_t(x)];
  mesh.points = std::move(points);
}

}  // namespace dthex
