// SPDX-License-Identifier: MIT
#include <dthex/boundary/project_boundary.h>

#include <dthex/boundary/relax_boundary_nodes.h>
#include <dthex/mesh/hex_topology.h>
#include <dthex/numerics/conjugate_gradient.h>

#include <array>
#include <cstdint>
#include <limits>
#include <algorithm>
#include <cmath>
#include <exception>
#include <string>

namespace dthex {
namespace {


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

//! The uniform graph Laplacian of the interior nodes: diagonal = degree, -1 per interior
//! neighbour; boundary neighbours are on the right-hand side.
struct HarmonicSystem {
  int n_unknowns;
  const std::vector<double>& degree;
  const std::vector<int>& row_start;
  const std::vector<int>& neighbours;

  size_t size() const { return size_t(n_unknowns); }
  double diagonal(size_t u) const { return degree[u]; }
  template <size_t K>
  void multiply_row(size_t u, const double* p, std::array<double, K>& s) const {
    for (size_t c = 0; c < K; ++c) s[c] = degree[u] * p[K * u + c];
    for (int k = row_start[u]; k < row_start[u + 1]; ++k) {
      const size_t w = K * size_t(neighbours[size_t(k)]);
      for (size_t c = 0; c < K; ++c) s[c] -= p[w + c];
    }
  }
};

}  // namespace

void move_interior_harmonically(HexMesh& mesh, const std::vector<Vec3>& boundary_displacement, int max_iterations,
                                double tolerance) {
  const size_t n = mesh.nodes.size();
  // Interior nodes numbered along a Morton curve: neighbours in space get nearby numbers,
  // so the solver's gathers hit the cache (in the diced mesh's own order they did not,
  // and the solve was memory bound).
  std::vector<std::pair<std::uint64_t, int>> order;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::max()), hi = -lo;
  for (size_t v = 0; v < n; ++v)
    if (!mesh.is_boundary_node(int(v))) lo = lo.cwiseMin(mesh.nodes[v]), hi = hi.cwiseMax(mesh.nodes[v]);
  const double cell = std::max((hi - lo).maxCoeff(), 1e-300) / 1023.0;
  for (size_t v = 0; v < n; ++v)
    if (!mesh.is_boundary_node(int(v))) {
      std::uint64_t key = 0;
      for (int c = 0; c < 3; ++c) {
        const auto q = std::uint64_t(std::clamp((mesh.nodes[v][c] - lo[c]) / cell, 0.0, 1023.0));
        for (int bit = 0; bit < 10; ++bit) key |= ((q >> bit) & 1u) << (3 * bit + c);
      }
      order.emplace_back(key, int(v));
    }
  if (order.empty()) return;
  std::sort(order.begin(), order.end());
  std::vector<int> unknown(n, -1);
  const int n_unknowns = int(order.size());
  for (int u = 0; u < n_unknowns; ++u) unknown[size_t(order[size_t(u)].second)] = u;

  // Hex-edge neighbours of every interior node (each edge is listed by every hex around it:
  // sort and deduplicate each node's short list, far cheaper than sorting all edges).
  std::vector<int> start(size_t(n_unknowns) + 1, 0);
  for (const auto& h : mesh.hexes)
    for (const auto& e : kHexEdges) {
      const int ua = unknown[size_t(h[size_t(e[0])])], ub = unknown[size_t(h[size_t(e[1])])];
      if (ua >= 0) ++start[size_t(ua) + 1];
      if (ub >= 0) ++start[size_t(ub) + 1];
    }
  for (int u = 0; u < n_unknowns; ++u) start[size_t(u) + 1] += start[size_t(u)];
  std::vector<int> listed(size_t(start.back()));
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (const auto& h : mesh.hexes)
      for (const auto& e : kHexEdges) {
        const int a = h[size_t(e[0])], b = h[size_t(e[1])];
        if (unknown[size_t(a)] >= 0) listed[size_t(fill[size_t(unknown[size_t(a)])]++)] = b;
        if (unknown[size_t(b)] >= 0) listed[size_t(fill[size_t(unknown[size_t(b)])]++)] = a;
      }
  }
  // The uniform graph Laplacian: diagonal = degree, -1 per interior neighbour (kept in
  // `neighbours`); boundary neighbours go to the right-hand side.
  std::vector<int> row_start(size_t(n_unknowns) + 1, 0), neighbours;
  neighbours.reserve(listed.size() / 2);
  std::vector<double> degree(static_cast<size_t>(n_unknowns)), rhs(3 * static_cast<size_t>(n_unknowns), 0.0);
  for (int u = 0; u < n_unknowns; ++u) {
    const auto first = listed.begin() + start[size_t(u)], last = listed.begin() + start[size_t(u) + 1];
    std::sort(first, last);
    const auto unique_end = std::unique(first, last);
    degree[size_t(u)] = std::max(double(unique_end - first), 1.0);
    for (auto it = first; it != unique_end; ++it) {
      const int w = unknown[size_t(*it)];
      if (w >= 0) {
        neighbours.push_back(w);
      } else {
        for (int c = 0; c < 3; ++c) rhs[3 * size_t(u) + size_t(c)] += boundary_displacement[size_t(*it)][c];
      }
    }
    row_start[size_t(u) + 1] = int(neighbours.size());
  }

  // The three coordinates are three independent systems with the same matrix: x and y are
  // solved on one core and z on the other, each thread on its own with no barrier between
  // them (the earlier split of each pass over two cores waited at a barrier per pass, and on a
  // busy machine, ctest -j2, each barrier waited for a descheduled thread).
  const HarmonicSystem system{n_unknowns, degree, row_start, neighbours};
  ConjugateGradientOptions cg;
  cg.max_iterations = max_iterations;
  cg.tolerance = tolerance;
  std::vector<double> xy, z;
  std::exception_ptr failure[2];
#pragma omp parallel sections num_threads(2)
  {
#pragma omp section
    try {
      xy = solve_conjugate_gradient<2>(system, [&](size_t u, size_t c) { return rhs[3 * u + c]; }, cg);
    } catch (...) {
      failure[0] = std::current_exception();
    }
#pragma omp section
    try {
      z = solve_conjugate_gradient<1>(system, [&](size_t u, size_t) { return rhs[3 * u + 2]; }, cg);
    } catch (...) {
      failure[1] = std::current_exception();
    }
  }
  for (const auto& f : failure)
    if (f) std::rethrow_exception(f);
  for (size_t v = 0; v < n; ++v)
    if (unknown[v] >= 0) {
      const size_t u = size_t(unknown[v]);
      mesh.nodes[v] += Vec3(xy[2 * u], xy[2 * u + 1], z[u]);
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
  // Every node is projected on its own (its query reads only the input), so the nodes are
  // split over the cores.
  size_t projected = 0, unconstrained = 0, far = 0;
  double max_displacement = 0;
  const long n_nodes = long(mesh.nodes.size());
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : projected, unconstrained, far) \
    reduction(max : max_displacement)
  for (long iv = 0; iv < n_nodes; ++iv) {
    const size_t v = size_t(iv);
    const int facet = mesh.boundary_facet[v];
    if (facet < 0) continue;
    const Vec3& q = mesh.nodes[v];
    const Vec3& n = coarse_normals[size_t(facet)];
    const double reach_sq = coarse_reach[size_t(facet)] * coarse_reach[size_t(facet)];
    TriangleBvh::ClosestPoint cp =
        fine_bvh.closest_point(q, [&](int t) { return fine_normals[size_t(t)].dot(n) >= min_cos; });
    if (cp.triangle < 0) {
      cp = fine_bvh.closest_point(q);
      ++unconstrained;
    } else if (cp.distance_sq > reach_sq) {
      ++far;
    }
    if (cp.triangle < 0) continue;  // empty fine surface
    displacement[v] = cp.point - q;
    mesh.nodes[v] = cp.point;
    ++projected;
    max_displacement = std::max(max_displacement, std::sqrt(cp.distance_sq));
  }
  report.projected_nodes = projected;
  report.unconstrained_nodes = unconstrained;
  report.far_nodes = far;
  report.max_displacement = max_displacement;
  if (options.relax_rounds > 0) {
    RelaxBoundaryOptions relax;
    relax.rounds = options.relax_rounds;
    relax.constraints = options.constraints;
    static const std::vector<char> none;
    const std::vector<char>& held = options.constraints ? options.constraints->on_feature : none;
    report.relaxed_moves = relax_boundary_nodes(mesh, coarse, fine_bvh, held, displacement, relax).moves;
  }
  if (options.move_interior)
    move_interior_harmonically(mesh, displacement, options.interior_max_iterations, options.interior_tolerance);
  return report;
}

}  // namespace dthex
