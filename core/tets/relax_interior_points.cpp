// SPDX-License-Identifier: MIT
#include <dthex/tets/relax_interior_points.h>

#include <dthex/mesh/quality.h>
#include <dthex/numerics/grid_directions.h>

#include <Eigen/Geometry>

#include <algorithm>

namespace dthex {
namespace {

// The star of v with v at x: its worst shape (0 when a tet is flat or inverted) and the sum
// of the inverse shapes (a score that the worst tets dominate but every tet counts in).
struct StarScore {
  double worst = 0, inverse_sum = 0;
};
StarScore score_with(const TetMesh& mesh, const std::vector<int>& star, int v, const Vec3& x) {
  StarScore s;
  s.worst = 1;
  for (int t : star) {
    std::array<Vec3, 4> p;
    for (size_t i = 0; i < 4; ++i) {
      const int y = mesh.tets[size_t(t)][i];
      p[i] = y == v ? x : mesh.points[size_t(y)];
    }
    const double shape = tet_shape(p[0], p[1], p[2], p[3]);
    if (!(shape > 0)) return {};
    s.worst = std::min(s.worst, shape);
    s.inverse_sum += 1 / shape;
  }
  return s;
}

double worst_with(const TetMesh& mesh, const std::vector<int>& star, int v, const Vec3& x) {
  return score_with(mesh, star, v, x).worst;
}

// Unit normal of the face of the star's worst tet opposite v, pointing to v: the way that
// tet gets taller, which the grid directions only approximate.
Vec3 away_from_worst_face(const TetMesh& mesh, const std::vector<int>& star, int v) {
  double worst = 2;
  Vec3 direction = Vec3::Zero();
  for (int t : star) {
    const auto& tet = mesh.tets[size_t(t)];
    const double shape = tet_shape(mesh.points[size_t(tet[0])], mesh.points[size_t(tet[1])],
                                   mesh.points[size_t(tet[2])], mesh.points[size_t(tet[3])]);
    if (shape >= worst) continue;
    worst = shape;
    std::array<Vec3, 3> face;
    size_t k = 0;
    for (int y : tet)
      if (y != v) face[k++] = mesh.points[size_t(y)];
    Vec3 n = (face[1] - face[0]).cross(face[2] - face[0]);
    if (n.dot(mesh.points[size_t(v)] - face[0]) < 0) n = -n;
    direction = n.norm() > 0 ? Vec3(n.normalized()) : Vec3::Zero();
  }
  return direction;
}

// One relaxation: passes over the interior points whose worst tet is below only_below,
// each moved by a pattern search. max_min: the worst tet of the star alone is raised;
// otherwise the sum of inverse shapes falls while the worst tet does not. Marks moved points.
void relax(TetMesh& mesh, const std::vector<char>& on_boundary, const std::vector<std::vector<int>>& star,
           const RelaxInteriorPointsOptions& options, bool max_min, double only_below, std::vector<char>& moved) {
  const std::vector<Vec3>& grid = grid_directions();

  for (int pass = 0; pass < options.max_passes; ++pass) {
    // Worst star first: its moves are made before its neighbours take the room.
    std::vector<std::pair<double, int>> order;
    for (size_t v = 0; v < mesh.points.size(); ++v) {
      if (on_boundary[v] || star[v].empty()) continue;
      const double worst = worst_with(mesh, star[v], int(v), mesh.points[v]);
      if (worst > 0 && worst < only_below) order.emplace_back(worst, int(v));
    }
    std::sort(order.begin(), order.end());
    size_t moved_this_pass = 0;
    for (const auto& entry : order) {
      const auto v = entry.second;  // a plain local: lambdas below capture it (clang 14 cannot capture a binding)
      const auto& tets = star[size_t(v)];
      StarScore now = score_with(mesh, tets, v, mesh.points[size_t(v)]);  // neighbours may have moved
      const double floor = now.worst;  // no move may lower the point's worst tet
      double length = 0;
      int edges = 0;
      for (int t : tets)
        for (int y : mesh.tets[size_t(t)])
          if (y != v) {
            length += (mesh.points[size_t(y)] - mesh.points[size_t(v)]).norm();
            ++edges;
          }
      length /= std::max(edges, 1);
      double step = options.initial_step * length;
      bool any = false;
      for (int trial = 0; trial < options.max_trials && step >= options.min_step * length; ++trial) {
        const Vec3 at = mesh.points[size_t(v)];
        Vec3 best_x = at;
        StarScore best = now;
        auto better = [&](const StarScore& a, const StarScore& b) {
          if (max_min) return a.worst > b.worst * (1 + 1e-6);
          return a.worst >= floor && a.inverse_sum < b.inverse_sum * (1 - 1e-6);
        };
        auto consider = [&](const Vec3& d) {
          const Vec3 x = at + step * d;
          const StarScore s = score_with(mesh, tets, v, x);
          if (s.worst > 0 && better(s, best)) {
            best = s;
            best_x = x;
          }
        };
        consider(away_from_worst_face(mesh, tets, v));
        for (const Vec3& d : grid) consider(d);
        // A real gain only (the factors above): ties and round-off would let the point wander.
        if (best_x != at) {
          mesh.points[size_t(v)] = best_x;
          now = best;
          any = true;
        } else {
          step *= 0.5;
        }
      }
      if (any) {
        ++moved_this_pass;
        moved[size_t(v)] = 1;
      }
    }
    if (!moved_this_pass) break;
  }
}

}  // namespace

RelaxInteriorPointsReport relax_interior_points(TetMesh& mesh, const RelaxInteriorPointsOptions& options) {
  RelaxInteriorPointsReport report;
  const std::vector<double> shapes_before = tet_shapes(mesh);
  report.worst_before = shapes_before.empty() ? 0 : *std::min_element(shapes_before.begin(), shapes_before.end());
  std::vector<char> on_boundary(mesh.points.size(), 0);
  for (const auto& f : mesh.boundary_faces)
    for (int v : f) on_boundary[size_t(v)] = 1;
  std::vector<std::vector<int>> star(mesh.points.size());
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int v : mesh.tets[t]) star[size_t(v)].push_back(int(t));
  std::vector<char> moved(mesh.points.size(), 0);
  relax(mesh, on_boundary, star, options, false, options.relax_below, moved);
  if (options.max_min_below > 0) relax(mesh, on_boundary, star, options, true, options.max_min_below, moved);
  report.moved = size_t(std::count(moved.begin(), moved.end(), char(1)));
  const std::vector<double> shapes_after = tet_shapes(mesh);
  report.worst_after = shapes_after.empty() ? 0 : *std::min_element(shapes_after.begin(), shapes_after.end());
  return report;
}

}  // namespace dthex
