// SPDX-License-Identifier: MIT
#include "core/split_surface_tets.h"

#include <algorithm>
#include <map>

namespace dthex {
namespace {

// Splits every non-boundary edge whose two ends are boundary vertices at its midpoint (a new
// interior vertex), halving each tet around it. Returns the number of edges split.
size_t split_interior_boundary_edges(TetMesh& mesh, const std::vector<char>& on_boundary) {
  std::vector<std::pair<int, int>> boundary_edges;
  for (const auto& f : mesh.boundary_faces)
    for (int i = 0; i < 3; ++i) boundary_edges.emplace_back(std::minmax(f[size_t(i)], f[size_t((i + 1) % 3)]));
  std::sort(boundary_edges.begin(), boundary_edges.end());
  boundary_edges.erase(std::unique(boundary_edges.begin(), boundary_edges.end()), boundary_edges.end());

  std::vector<std::pair<int, int>> candidates;
  for (const auto& t : mesh.tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const auto e = std::minmax(t[size_t(i)], t[size_t(j)]);
        if (on_boundary[size_t(e.first)] && on_boundary[size_t(e.second)] &&
            !std::binary_search(boundary_edges.begin(), boundary_edges.end(), std::pair<int, int>(e)))
          candidates.emplace_back(e);
      }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  if (candidates.empty()) return 0;

  // Tets around each vertex, kept up to date as tets are split.
  std::vector<std::vector<int>> vertex_tets(mesh.points.size());
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int v : mesh.tets[t]) vertex_tets[size_t(v)].push_back(int(t));
  size_t split = 0;
  for (const auto& [a, b] : candidates) {
    std::vector<int> around;
    for (int t : vertex_tets[size_t(a)]) {
      const auto& tet = mesh.tets[size_t(t)];
      if (std::find(tet.begin(), tet.end(), b) != tet.end()) around.push_back(t);
    }
    if (around.empty()) continue;
    ++split;
    const int m = int(mesh.points.size());
    mesh.points.push_back(0.5 * (mesh.points[size_t(a)] + mesh.points[size_t(b)]));
    vertex_tets.emplace_back();
    for (int t : around) {
      // (.., a, .., b, ..) -> a replaced by m, and b replaced by m: both keep the orientation.
      const std::array<int, 4> tet = mesh.tets[size_t(t)];
      std::array<int, 4> with_b = tet, with_a = tet;
      for (size_t i = 0; i < 4; ++i) {
        if (tet[i] == a) with_b[i] = m;
        if (tet[i] == b) with_a[i] = m;
      }
      mesh.tets[size_t(t)] = with_a;  // keeps a, loses b
      const int added = int(mesh.tets.size());
      mesh.tets.push_back(with_b);    // keeps b, loses a
      auto& b_tets = vertex_tets[size_t(b)];
      std::replace(b_tets.begin(), b_tets.end(), t, added);
      for (int v : with_b)
        if (v != b && v != m) vertex_tets[size_t(v)].push_back(added);
      vertex_tets[size_t(m)].push_back(t);
      vertex_tets[size_t(m)].push_back(added);
    }
  }
  return split;
}

}  // namespace

SplitSurfaceTetsReport split_surface_tets(TetMesh& mesh, const SplitSurfaceTetsOptions& options) {
  SplitSurfaceTetsReport report;
  // Boundary faces by their sorted vertex triple, and boundary vertices.
  std::vector<std::array<int, 3>> boundary_keys;
  boundary_keys.reserve(mesh.boundary_faces.size());
  std::vector<char> on_boundary(mesh.points.size(), 0);
  for (const auto& f : mesh.boundary_faces) {
    std::array<int, 3> key = f;
    std::sort(key.begin(), key.end());
    boundary_keys.push_back(key);
    for (int v : f) on_boundary[size_t(v)] = 1;
  }
  std::sort(boundary_keys.begin(), boundary_keys.end());
  auto is_boundary_face = [&](int a, int b, int c) {
    std::array<int, 3> key = {a, b, c};
    std::sort(key.begin(), key.end());
    return std::binary_search(boundary_keys.begin(), boundary_keys.end(), key);
  };

  if (options.split_interior_edges) report.split_edges = split_interior_boundary_edges(mesh, on_boundary);

  const size_t n_tets = mesh.tets.size();
  for (size_t t = 0; t < n_tets; ++t) {
    const std::array<int, 4> tet = mesh.tets[t];
    int boundary_faces = 0;
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> face{};
      for (int i = 0, k = 0; i < 4; ++i)
        if (i != skip) face[size_t(k++)] = tet[size_t(i)];
      if (is_boundary_face(face[0], face[1], face[2])) ++boundary_faces;
    }
    bool split = boundary_faces >= options.min_boundary_faces;
    if (!split && options.split_all_boundary_vertex_tets)
      split = std::all_of(tet.begin(), tet.end(), [&](int v) { return on_boundary[size_t(v)]; });
    if (!split) continue;
    Vec3 centroid = Vec3::Zero();
    for (int v : tet) centroid += mesh.points[size_t(v)];
    const int p = int(mesh.points.size());
    mesh.points.push_back(centroid / 4.0);
    // Replacing one vertex of a positive tet by an interior point keeps it positive.
    for (size_t i = 0; i < 4; ++i) {
      std::array<int, 4> sub = tet;
      sub[i] = p;
      if (i == 0) mesh.tets[t] = sub;
      else mesh.tets.push_back(sub);
    }
    ++report.split_tets;
  }
  return report;
}

}  // namespace dthex
