// SPDX-License-Identifier: MIT
#include "core/project_boundary.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <string>

namespace dthex {
namespace {

constexpr int kHexEdges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                  {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

Vec3 unit_normal(const TriSurface& s, int t) {
  const auto& f = s.triangles[size_t(t)];
  const Vec3 n = (s.points[size_t(f[1])] - s.points[size_t(f[0])]).cross(s.points[size_t(f[2])] - s.points[size_t(f[0])]);
  const double len = n.norm();
  return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

double longest_edge(const TriSurface& s, int t) {
  const auto& f = s.triangles[size_t(t)];
  double l = 0;
  for (int i = 0; i < 3; ++i) l = std::max(l, (s.points[size_t(f[size_t(i)])] - s.points[size_t(f[size_t((i + 1) % 3)])]).norm());
  return l;
}

}  // namespace

void move_interior_harmonically(HexMesh& mesh, const std::vector<Vec3>& boundary_displacement, int max_iterations,
                                double tolerance) {
  const size_t n = mesh.nodes.size();
  std::vector<int> unknown(n, -1);
  int n_unknowns = 0;
  for (size_t v = 0; v < n; ++v)
    if (!mesh.is_boundary_node(int(v))) unknown[v] = n_unknowns++;
  if (n_unknowns == 0) return;

  // Unique undirected hex edges.
  std::vector<std::pair<int, int>> edges;
  edges.reserve(mesh.hexes.size() * 12);
  for (const auto& h : mesh.hexes)
    for (const auto& e : kHexEdges) {
      int a = h[size_t(e[0])], b = h[size_t(e[1])];
      if (a > b) std::swap(a, b);
      edges.emplace_back(a, b);
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());

  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(edges.size() * 4);
  Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(n_unknowns, 3);
  std::vector<double> degree(size_t(n_unknowns), 0.0);
  for (const auto& [a, b] : edges) {
    const int ua = unknown[size_t(a)], ub = unknown[size_t(b)];
    if (ua >= 0) degree[size_t(ua)] += 1;
    if (ub >= 0) degree[size_t(ub)] += 1;
    if (ua >= 0 && ub >= 0) {
      triplets.emplace_back(ua, ub, -1.0);
      triplets.emplace_back(ub, ua, -1.0);
    } else if (ua >= 0) {
      rhs.row(ua) += boundary_displacement[size_t(b)].transpose();
    } else if (ub >= 0) {
      rhs.row(ub) += boundary_displacement[size_t(a)].transpose();
    }
  }
  for (int u = 0; u < n_unknowns; ++u) triplets.emplace_back(u, u, std::max(degree[size_t(u)], 1.0));
  Eigen::SparseMatrix<double> laplacian(n_unknowns, n_unknowns);
  laplacian.setFromTriplets(triplets.begin(), triplets.end());

  // The matrix holds both triangles, so reading the lower one is exact. Lower | Upper would
  // make Eigen run every product on OpenMP threads, whose spin-waiting on a busy machine
  // made a 4000-node solve take seconds instead of milliseconds.
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower> solver;
  solver.setMaxIterations(max_iterations);
  solver.setTolerance(tolerance);
  solver.compute(laplacian);
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd d = solver.solve(rhs.col(c));
    for (size_t v = 0; v < n; ++v)
      if (unknown[v] >= 0) mesh.nodes[v][c] += d[unknown[v]];
  }
}

ProjectReport project_boundary(HexMesh& mesh, const TriSurface& coarse, const TriSurface& fine,
                               const TriangleBvh& fine_bvh, const ProjectOptions& options) {
  if (mesh.boundary_facet.size() != mesh.nodes.size())
    throw InputError("project_boundary: the hex mesh carries no boundary_facet per node (" +
                     std::to_string(mesh.boundary_facet.size()) + " entries for " +
                     std::to_string(mesh.nodes.size()) + " nodes)");
  for (size_t v = 0; v < mesh.nodes.size(); ++v)
    if (mesh.boundary_facet[v] >= int(coarse.triangles.size()))
      throw InputError("project_boundary: node " + std::to_string(v) + " names coarse facet " +
                       std::to_string(mesh.boundary_facet[v]) + ", the coarse surface has " +
                       std::to_string(coarse.triangles.size()) + " triangles");

  std::vector<Vec3> fine_normals(fine.triangles.size());
  for (size_t t = 0; t < fine.triangles.size(); ++t) fine_normals[t] = unit_normal(fine, int(t));
  std::vector<Vec3> coarse_normals(coarse.triangles.size());
  std::vector<double> coarse_reach(coarse.triangles.size());
  for (size_t t = 0; t < coarse.triangles.size(); ++t) {
    coarse_normals[t] = unit_normal(coarse, int(t));
    coarse_reach[t] = options.max_distance_factor * longest_edge(coarse, int(t));
  }
  const double min_cos = std::cos(options.max_normal_angle_deg * M_PI / 180.0);

  ProjectReport report;
  std::vector<Vec3> displacement(mesh.nodes.size(), Vec3::Zero());
  for (size_t v = 0; v < mesh.nodes.size(); ++v) {
    const int facet = mesh.boundary_facet[v];
    if (facet < 0) continue;
    const Vec3& q = mesh.nodes[v];
    const Vec3& n = coarse_normals[size_t(facet)];
    const double reach_sq = coarse_reach[size_t(facet)] * coarse_reach[size_t(facet)];
    TriangleBvh::ClosestPoint cp =
        fine_bvh.closest_point(q, [&](int t) { return fine_normals[size_t(t)].dot(n) >= min_cos; });
    if (cp.triangle < 0) {
      cp = fine_bvh.closest_point(q);
      ++report.unconstrained_nodes;
    } else if (cp.distance_sq > reach_sq) {
      ++report.far_nodes;
    }
    if (cp.triangle < 0) continue;  // empty fine surface
    displacement[v] = cp.point - q;
    mesh.nodes[v] = cp.point;
    ++report.projected_nodes;
    report.max_displacement = std::max(report.max_displacement, std::sqrt(cp.distance_sq));
  }
  if (options.move_interior)
    move_interior_harmonically(mesh, displacement, options.interior_max_iterations, options.interior_tolerance);
  return report;
}

}  // namespace dthex
