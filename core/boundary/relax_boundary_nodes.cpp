// SPDX-License-Identifier: MIT
#include <dthex/boundary/relax_boundary_nodes.h>

#include <dthex/hexes/conformity.h>

#include <algorithm>
#include <cmath>

namespace dthex {
RelaxBoundaryReport relax_boundary_nodes(HexMesh& mesh, const TriSurface& coarse, const TriangleBvh& surface,
                                         const std::vector<char>& held, std::vector<Vec3>& displacement,
                                         const RelaxBoundaryOptions& options) {
  RelaxBoundaryReport report;
  const size_t n = mesh.nodes.size();
  if (mesh.boundary_facet.size() != n || options.rounds <= 0) return report;
  // Boundary-quad edges: the neighbours a node is averaged with. Nodes named on no coarse
  // facet (or on one the coarse surface lacks) are left alone.
  std::vector<std::vector<int>> neighbours(n);
  std::vector<std::array<int, 4>> found;
  if (!options.constraints) found = boundary_quads(mesh);
  for (const auto& q : options.constraints ? options.constraints->boundary_quads : found)
    for (int i = 0; i < 4; ++i) {
      const int a = q[size_t(i)], b = q[size_t((i + 1) % 4)];
      neighbours[size_t(a)].push_back(b);
      neighbours[size_t(b)].push_back(a);
    }
  std::vector<int> movable;
  for (size_t v = 0; v < n; ++v) {
    auto& list = neighbours[v];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    if (mesh.boundary_facet[v] < 0 || mesh.boundary_facet[v] >= int(coarse.triangles.size()) || list.empty()) continue;
    if (v < held.size() && held[v]) {
      ++report.held;
      continue;
    }
    movable.push_back(int(v));
  }
  const std::vector<Vec3> surface_normals = unit_triangle_normals(surface.points(), surface.triangles());
  const std::vector<Vec3> coarse_normals = unit_triangle_normals(coarse.points, coarse.triangles);
  const double min_turn_cos = std::cos(options.max_normal_turn_deg * M_PI / 180.0);

  auto facing_side = [&](size_t v) {
    const Vec3 facing = coarse_normals[size_t(mesh.boundary_facet[v])];
    return [&surface_normals, facing](int t) { return surface_normals[size_t(t)].dot(facing) >= 0; };
  };

  std::vector<Vec3> next(movable.size());
  std::vector<char> moved(movable.size());
  for (int round = 0; round < options.rounds; ++round) {
    const long count = long(movable.size());
    // Jacobi: every node reads the positions of the round before, so the order (and the
    // number of threads) does not change the result.
#pragma omp parallel for schedule(dynamic, 256)
    for (long i = 0; i < count; ++i) {
      const size_t v = size_t(movable[size_t(i)]);
      moved[size_t(i)] = 0;
      const Vec3& x = mesh.nodes[v];
      const TriangleBvh::ClosestPoint here = surface.closest_point(x, facing_side(v));
      if (here.triangle < 0) continue;
      const Vec3& normal = surface_normals[size_t(here.triangle)];
      Vec3 mean = Vec3::Zero();
      double scale = 0;
      for (int u : neighbours[v]) {
        mean += mesh.nodes[size_t(u)];
        scale += (mesh.nodes[size_t(u)] - x).norm();
      }
      mean /= double(neighbours[v].size());
      scale /= double(neighbours[v].size());
      // A node on a convex crease traces it (projection put the nodes of both neighbouring
      // facets there) and stays; on a concave one it may leave, as in the local smoother.
      if (on_surface_crease(surface, surface_normals, here.point, normal, 1e-6 * scale, min_turn_cos, true)) continue;
      Vec3 d = options.step * (mean - x);
      d -= d.dot(normal) * normal;
      const double length = d.norm();
      if (!(length > 0)) continue;
      const TriangleBvh::ClosestPoint there = surface.closest_point(x + d, facing_side(v));
      if (there.triangle < 0 || std::sqrt(there.distance_sq) > length) continue;  // another sheet
      if (surface_normals[size_t(there.triangle)].dot(normal) < min_turn_cos) continue;  // across a feature
      next[size_t(i)] = there.point;
      moved[size_t(i)] = 1;
    }
    size_t moves = 0;
    for (size_t i = 0; i < movable.size(); ++i) {
      if (!moved[i]) continue;
      const size_t v = size_t(movable[i]);
      displacement[v] += next[i] - mesh.nodes[v];
      mesh.nodes[v] = next[i];
      ++moves;
    }
    report.moves += moves;
    if (!moves) break;
  }
  return report;
}

}  // namespace dthex
