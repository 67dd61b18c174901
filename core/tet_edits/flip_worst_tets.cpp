// SPDX-License-Identifier: MIT
#include <dthex/tet_edits/flip_worst_tets.h>

#include <dthex/mesh/quality.h>
#include <dthex/tet_edits/edge_removal.h>

#include <algorithm>

namespace dthex {
namespace {

double shape_of(const EditableTets& m, const std::array<int, 4>& t) {
  return tet_shape(m.point(t[0]), m.point(t[1]), m.point(t[2]), m.point(t[3]));
}

double mesh_worst(const TetMesh& mesh) {
  const std::vector<double> shapes = tet_shapes(mesh);
  return shapes.empty() ? 0 : *std::min_element(shapes.begin(), shapes.end());
}

// One flip found for a bad tet: the tets it replaces, the ones it makes, their worst shape.
struct Flip {
  std::vector<int> old_tets;
  std::vector<std::array<int, 4>> new_tets;
  double worst = -1;
  bool removes_edge = false;
};

// The 2-3 flip of the face of tet t opposite its local vertex skip, or nothing when that
// face is a boundary face, the new edge would join two boundary vertices, or a new tet
// would not be positive.
Flip face_flip(EditableTets& m, int t, int skip, const std::vector<char>& on_boundary) {
  const std::array<int, 4> x = m.tet(t);
  const int d = x[size_t(skip)];
  std::array<int, 3> face{};
  for (int i = 0, k = 0; i < 4; ++i)
    if (i != skip) face[size_t(k++)] = x[size_t(i)];
  const int a = face[0], b = face[1], c = face[2];
  int other = -1;
  for (int u : m.tets_with(a, b)) {
    if (u == t) continue;
    const auto& y = m.tet(u);
    if (std::find(y.begin(), y.end(), c) != y.end()) other = u;
  }
  if (other < 0) return {};  // a boundary face
  int e = -1;
  for (int v : m.tet(other))
    if (v != a && v != b && v != c) e = v;
  if (on_boundary[size_t(d)] && on_boundary[size_t(e)]) return {};
  if (m.has_edge(d, e)) return {};
  // The segment d e must pass through the face: then the three tets around it all have one
  // orientation (positive with d and e in one order), else the flip is not valid.
  Flip f;
  f.old_tets = {t, other};
  const std::array<std::pair<int, int>, 3> sides = {{{a, b}, {b, c}, {c, a}}};
  for (bool swapped : {false, true}) {
    f.new_tets.clear();
    for (const auto& [u, v] : sides)
      f.new_tets.push_back(swapped ? std::array<int, 4>{u, v, d, e} : std::array<int, 4>{u, v, e, d});
    f.worst = 1;
    for (const auto& y : f.new_tets) f.worst = std::min(f.worst, shape_of(m, y));
    if (f.worst > 0) break;
  }
  if (!(f.worst > 0)) return {};
  return f;
}

}  // namespace

FlipWorstTetsReport flip_worst_tets(TetMesh& mesh, const FlipWorstTetsOptions& options) {
  FlipWorstTetsReport report;
  report.worst_before = mesh_worst(mesh);
  std::vector<char> on_boundary(mesh.points.size(), 0);
  for (const auto& f : mesh.boundary_faces)
    for (int v : f) on_boundary[size_t(v)] = 1;
  EditableTets m(mesh);
  for (int pass = 0; pass < options.max_passes; ++pass) {
    std::vector<std::pair<double, int>> bad;
    for (size_t t = 0; t < m.tet_slots(); ++t) {
      if (!m.alive(int(t))) continue;
      const double shape = shape_of(m, m.tet(int(t)));
      if (shape < options.below) bad.emplace_back(shape, int(t));
    }
    std::sort(bad.begin(), bad.end());
    size_t flipped = 0;
    for (const auto& [shape, t] : bad) {
      if (!m.alive(t)) continue;
      Flip best;
      double best_gain = 0;
      auto consider = [&](Flip f) {
        if (f.worst < 0) return;
        const double old_worst = worst_shape(m, f.old_tets);
        // Only a real gain on the tets replaced (so the mesh's worst never falls).
        const double gain = f.worst - old_worst;
        if (f.worst > old_worst * (1 + 1e-9) && gain > best_gain) {
          best_gain = gain;
          best = std::move(f);
        }
      };
      const std::array<int, 4> x = m.tet(t);
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) {
          const int p = x[size_t(i)], q = x[size_t(j)];
          const std::vector<int> around = m.tets_with(p, q);
          auto removal = best_edge_removal(m, p, q, around, options.max_ring, on_boundary);
          if (!removal) continue;
          Flip f;
          f.old_tets = around;
          f.new_tets = std::move(removal->new_tets);
          f.worst = removal->worst;
          f.removes_edge = true;
          consider(std::move(f));
        }
      for (int skip = 0; skip < 4; ++skip) consider(face_flip(m, t, skip, on_boundary));
      if (best.worst < 0) continue;
      m.replace(best.old_tets, best.new_tets);
      ++(best.removes_edge ? report.edge_removals : report.face_flips);
      ++flipped;
    }
    if (!flipped) break;
  }
  m.compact();
  report.worst_after = mesh_worst(mesh);
  return report;
}

}  // namespace dthex
