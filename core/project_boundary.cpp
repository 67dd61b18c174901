// SPDX-License-Identifier: MIT
#include "core/project_boundary.h"

#include "core/relax_boundary_nodes.h"

#include <array>
#include <cstdint>
#include <limits>
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

  // Jacobi-preconditioned conjugate gradients on the three coordinates at once (three
  // independent recurrences sharing each pass over the adjacency; the three Eigen solves
  // this replaces read the matrix three times through a slow self-adjoint product).
  // Each iteration makes three passes over the unknowns (product with p and p.q; updates,
  // preconditioned residual and its two dot products; new direction): the solve is memory
  // bound, and seven separate passes cost twice as much. The passes stay on one core: split
  // over two, every pass ends at a barrier, and on a busy machine (ctest -j2) each barrier
  // waited for a descheduled thread, which made the stage three times slower.
  const size_t m = 3 * size_t(n_unknowns);
  std::vector<double> x(m, 0.0), r = rhs, z(m), p(m), q(m);
  using Triple = std::array<double, 3>;
  Triple rhs_norm2 = {0, 0, 0}, rz = {0, 0, 0};
  for (size_t u = 0; u < size_t(n_unknowns); ++u)
    for (size_t c = 0; c < 3; ++c) {
      const size_t i = 3 * u + c;
      z[i] = p[i] = r[i] / degree[u];
      rhs_norm2[c] += r[i] * r[i];
      rz[c] += r[i] * z[i];
    }
  Triple r2 = rhs_norm2;
  auto converged = [&](size_t c) { return r2[c] <= tolerance * tolerance * rhs_norm2[c]; };
  for (int it = 0; it < max_iterations && !(converged(0) && converged(1) && converged(2)); ++it) {
    Triple pq = {0, 0, 0};
    for (size_t u = 0; u < size_t(n_unknowns); ++u) {
      double s0 = degree[u] * p[3 * u], s1 = degree[u] * p[3 * u + 1], s2 = degree[u] * p[3 * u + 2];
      for (int k = row_start[u]; k < row_start[u + 1]; ++k) {
        const size_t w = 3 * size_t(neighbours[size_t(k)]);
        s0 -= p[w], s1 -= p[w + 1], s2 -= p[w + 2];
      }
      q[3 * u] = s0, q[3 * u + 1] = s1, q[3 * u + 2] = s2;
      pq[0] += p[3 * u] * s0, pq[1] += p[3 * u + 1] * s1, pq[2] += p[3 * u + 2] * s2;
    }
    Triple alpha;
    for (size_t c = 0; c < 3; ++c) alpha[c] = converged(c) || !(pq[c] > 0) ? 0.0 : rz[c] / pq[c];
    Triple rz_new = {0, 0, 0};
    r2 = {0, 0, 0};
    for (size_t u = 0; u < size_t(n_unknowns); ++u)
      for (size_t c = 0; c < 3; ++c) {
        const size_t i = 3 * u + c;
        x[i] += alpha[c] * p[i];
        r[i] -= alpha[c] * q[i];
        z[i] = r[i] / degree[u];
        rz_new[c] += r[i] * z[i];
        r2[c] += r[i] * r[i];
      }
    Triple beta;
    for (size_t c = 0; c < 3; ++c) beta[c] = rz[c] > 0 ? rz_new[c] / rz[c] : 0.0;
    for (size_t i = 0; i < m; i += 3)
      for (size_t c = 0; c < 3; ++c) p[i + c] = z[i + c] + beta[c] * p[i + c];
    rz = rz_new;
  }
  for (size_t v = 0; v < n; ++v)
    if (unknown[v] >= 0)
      for (int c = 0; c < 3; ++c) mesh.nodes[v][c] += x[3 * size_t(unknown[v]) + size_t(c)];
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
    relax.boundary_quads = options.boundary_quads;
    static const std::vector<char> none;
    const std::vector<char>& held = options.held_nodes ? *options.held_nodes : none;
    report.relaxed_moves = relax_boundary_nodes(mesh, coarse, fine_bvh, held, displacement, relax).moves;
  }
  if (options.move_interior)
    move_interior_harmonically(mesh, displacement, options.interior_max_iterations, options.interior_tolerance);
  return report;
}

}  // namespace dthex
