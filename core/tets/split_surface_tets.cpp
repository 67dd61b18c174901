// SPDX-License-Identifier: MIT
#include <dthex/tets/split_surface_tets.h>

#include <dthex/mesh/quality.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <map>
#include <numeric>

namespace dthex {
namespace {

// Interior edges whose two ends are boundary vertices, sorted and unique.
std::vector<std::pair<int, int>> interior_boundary_edges(const TetMesh& mesh, const std::vector<char>& on_boundary) {
  std::vector<std::pair<int, int>> boundary_edges;
  for (const auto& f : mesh.boundary_faces)
    for (int i = 0; i < 3; ++i) boundary_edges.emplace_back(std::minmax(f[size_t(i)], f[size_t((i + 1) % 3)]));
  std::sort(boundary_edges.begin(), boundary_edges.end());
  boundary_edges.erase(std::unique(boundary_edges.begin(), boundary_edges.end()), boundary_edges.end());
  std::vector<std::pair<int, int>> edges;
  for (const auto& t : mesh.tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const auto e = std::minmax(t[size_t(i)], t[size_t(j)]);
        if (on_boundary[size_t(e.first)] && on_boundary[size_t(e.second)] &&
            !std::binary_search(boundary_edges.begin(), boundary_edges.end(), std::pair<int, int>(e)))
          edges.emplace_back(e);
      }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

double signed_volume(const TetMesh& m, const std::array<int, 4>& t) {
  const Vec3& a = m.points[size_t(t[0])];
  return (m.points[size_t(t[1])] - a).dot((m.points[size_t(t[2])] - a).cross(m.points[size_t(t[3])] - a)) / 6.0;
}

// Where several interior edges between boundary vertices share tets (the tets around them
// form one cluster), one interior point can replace them all: the cluster is re-meshed as
// the cone from its volume centroid over its outer faces. Splitting each edge at its
// midpoint instead adds a point and ~2k tets per edge (k tets around it). The icosahedron
// meshed without Steiner points (15 tets, 6 such edges, all one cluster) becomes the
// paper's 20 tets around the centre instead of 45. A cone is used only when every cone tet
// is positive and no worse (shape) than the worst tet it replaces, and it adds no more tets
// than the midpoint splits would. Returns the clusters coned.
size_t cone_edge_clusters_impl(TetMesh& mesh, const std::vector<char>& on_boundary) {
  const auto edges = interior_boundary_edges(mesh, on_boundary);
  if (edges.size() < 2) return 0;
  // Union-find over tets: all tets around one such edge are in one cluster.
  std::vector<int> parent(mesh.tets.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[size_t(x)] != x) x = parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
    return x;
  };
  // Tets around each edge: the first one seen, and every other joined to it.
  std::vector<char> in_cluster(mesh.tets.size(), 0);
  std::vector<int> first_tet(edges.size(), -1), tets_around(edges.size(), 0);
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& tet = mesh.tets[t];
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const std::pair<int, int> e = std::minmax(tet[size_t(i)], tet[size_t(j)]);
        const auto it = std::lower_bound(edges.begin(), edges.end(), e);
        if (it == edges.end() || *it != e) continue;
        in_cluster[t] = 1;
        const size_t k = size_t(it - edges.begin());
        ++tets_around[k];
        if (first_tet[k] < 0) first_tet[k] = int(t);
        else parent[size_t(find(int(t)))] = find(first_tet[k]);
      }
  }
  std::map<int, std::vector<int>> clusters;
  std::map<int, int> edges_in;
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    if (in_cluster[t]) clusters[find(int(t))].push_back(int(t));
  std::map<int, size_t> split_adds;  // tets the midpoint splits would add (at least)
  for (size_t k = 0; k < edges.size(); ++k) {
    ++edges_in[find(first_tet[k])];
    split_adds[find(first_tet[k])] += size_t(tets_around[k]);
  }

  std::vector<char> removed(mesh.tets.size(), 0);
  std::vector<std::array<int, 4>> added;
  size_t coned = 0;
  for (const auto& [root, tets] : clusters) {
    if (edges_in[root] < 2) continue;  // one edge: its midpoint split is the same cone
    // Outer faces of the cluster: (tet, opposite vertex) whose face no other cluster tet has.
    std::map<std::array<int, 3>, std::pair<int, int>> faces;
    std::map<std::array<int, 3>, int> uses;
    Vec3 centroid = Vec3::Zero();
    double volume = 0, worst = 1;
    for (int t : tets) {
      const auto& tet = mesh.tets[size_t(t)];
      const double v = signed_volume(mesh, tet);
      Vec3 c = Vec3::Zero();
      for (int x : tet) c += mesh.points[size_t(x)];
      centroid += v * c / 4.0;
      volume += v;
      worst = std::min(worst, tet_shape(mesh.points[size_t(tet[0])], mesh.points[size_t(tet[1])],
                                        mesh.points[size_t(tet[2])], mesh.points[size_t(tet[3])]));
      for (int skip = 0; skip < 4; ++skip) {
        std::array<int, 3> key{};
        for (int i = 0, k = 0; i < 4; ++i)
          if (i != skip) key[size_t(k++)] = tet[size_t(i)];
        std::sort(key.begin(), key.end());
        ++uses[key];
        faces[key] = {t, skip};
      }
    }
    if (!(volume > 0)) continue;
    centroid /= volume;
    const int p = int(mesh.points.size());
    mesh.points.push_back(centroid);
    std::vector<std::array<int, 4>> cone;
    bool ok = true;
    for (const auto& [key, n] : uses) {
      if (n != 1) continue;
      const auto [t, skip] = faces[key];
      std::array<int, 4> sub = mesh.tets[size_t(t)];
      sub[size_t(skip)] = p;  // the centroid on the same side of the face as the vertex it replaces
      const auto& q = mesh.points;
      if (!(signed_volume(mesh, sub) > 0) ||
          tet_shape(q[size_t(sub[0])], q[size_t(sub[1])], q[size_t(sub[2])], q[size_t(sub[3])]) < worst) {
        ok = false;
        break;
      }
      cone.push_back(sub);
    }
    if (!ok || cone.size() > tets.size() + split_adds[root]) {  // invalid, worse, or more tets
      mesh.points.pop_back();
      continue;
    }
    for (int t : tets) removed[size_t(t)] = 1;
    added.insert(added.end(), cone.begin(), cone.end());
    ++coned;
  }
  if (!coned) return 0;
  std::vector<std::array<int, 4>> kept;
  kept.reserve(mesh.tets.size() + added.size());
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    if (!removed[t]) kept.push_back(mesh.tets[t]);
  kept.insert(kept.end(), added.begin(), added.end());
  mesh.tets = std::move(kept);
  return coned;
}

// Splits every non-boundary edge whose two ends are boundary vertices at its midpoint (a new
// interior vertex), halving each tet around it. Returns the number of edges split.
size_t split_interior_boundary_edges(TetMesh& mesh, const std::vector<char>& on_boundary) {
  const std::vector<std::pair<int, int>> candidates = interior_boundary_edges(mesh, on_boundary);
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

// Splits every interior face whose three vertices are all boundary vertices at its centroid (a
// new interior vertex), each of the two tets on it into three (a 2-to-6 split). After the edge
// splits such a face has three boundary edges: the boundary has a triangle of edges there
// that is not one of its faces. At each corner of that face, two of the face's edges lie on the
// surface, and so do the two matching edges of the hex corner on either side of the face once
// the boundary is projected; where the surface is smooth, those two edges span its tangent
// plane, and the two hexes sharing the face both have their third edge going inside: they
// cannot both be positive there, whatever the untangler does. After the split every face
// through two of those vertices has the new interior point as its third. Every tet with two
// or three boundary faces has such a face or an interior edge between boundary vertices (the
// edge opposite two faces' shared one), so after the splits only a tet that is a whole
// component has two boundary faces. Returns the faces split.
size_t split_interior_boundary_faces(TetMesh& mesh, const std::vector<char>& on_boundary) {
  std::vector<std::array<int, 3>> boundary_keys;
  boundary_keys.reserve(mesh.boundary_faces.size());
  for (const auto& f : mesh.boundary_faces) {
    std::array<int, 3> key = f;
    std::sort(key.begin(), key.end());
    boundary_keys.push_back(key);
  }
  std::sort(boundary_keys.begin(), boundary_keys.end());
  std::vector<std::array<int, 3>> candidates;
  for (const auto& t : mesh.tets) {
    if (std::count_if(t.begin(), t.end(), [&](int v) { return on_boundary[size_t(v)] != 0; }) < 3) continue;
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> key{};
      for (int i = 0, k = 0; i < 4; ++i)
        if (i != skip) key[size_t(k++)] = t[size_t(i)];
      std::sort(key.begin(), key.end());
      if (std::all_of(key.begin(), key.end(), [&](int v) { return on_boundary[size_t(v)] != 0; }) &&
          !std::binary_search(boundary_keys.begin(), boundary_keys.end(), key))
        candidates.push_back(key);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  if (candidates.empty()) return 0;

  // Tets around each vertex, kept up to date as tets are split.
  std::vector<std::vector<int>> vertex_tets(mesh.points.size());
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int v : mesh.tets[t]) vertex_tets[size_t(v)].push_back(int(t));
  size_t split = 0;
  for (const auto& face : candidates) {
    std::vector<int> around;
    for (int t : vertex_tets[size_t(face[0])]) {
      const auto& tet = mesh.tets[size_t(t)];
      if (std::find(tet.begin(), tet.end(), face[1]) != tet.end() &&
          std::find(tet.begin(), tet.end(), face[2]) != tet.end())
        around.push_back(t);
    }
    if (around.empty()) continue;
    ++split;
    const int m = int(mesh.points.size());
    mesh.points.push_back((mesh.points[size_t(face[0])] + mesh.points[size_t(face[1])] + mesh.points[size_t(face[2])]) /
                          3.0);
    vertex_tets.emplace_back();
    for (int t : around) {
      const std::array<int, 4> tet = mesh.tets[size_t(t)];
      for (int v : tet) {
        auto& list = vertex_tets[size_t(v)];
        list.erase(std::remove(list.begin(), list.end(), t), list.end());
      }
      // Replacing one corner of the face by a point inside the face keeps the orientation.
      for (size_t c = 0; c < 3; ++c) {
        std::array<int, 4> sub = tet;
        *std::find(sub.begin(), sub.end(), face[c]) = m;
        const int index = c == 0 ? t : int(mesh.tets.size());
        if (c == 0) mesh.tets[size_t(t)] = sub;
        else mesh.tets.push_back(sub);
        for (int v : sub) vertex_tets[size_t(v)].push_back(index);
      }
    }
  }
  return split;
}

}  // namespace

size_t cone_edge_clusters(TetMesh& mesh) {
  std::vector<char> on_boundary(mesh.points.size(), 0);
  for (const auto& f : mesh.boundary_faces)
    for (int v : f) on_boundary[size_t(v)] = 1;
  return cone_edge_clusters_impl(mesh, on_boundary);
}

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

  if (options.split_interior_edges) {
    if (options.cone_edge_clusters) {
      report.coned_clusters = cone_edge_clusters_impl(mesh, on_boundary);
      on_boundary.resize(mesh.points.size(), 0);  // the cone apexes are interior
    }
    report.split_edges = split_interior_boundary_edges(mesh, on_boundary);
    on_boundary.resize(mesh.points.size(), 0);  // so are the edge midpoints
  }
  if (options.split_interior_faces) {
    report.split_faces = split_interior_boundary_faces(mesh, on_boundary);
    on_boundary.resize(mesh.points.size(), 0);  // and the face centroids
  }

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
