// SPDX-License-Identifier: MIT
#include <dthex/hexes/thex.h>

#include <dthex/mesh/hex_topology.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>

namespace dthex {
namespace {

// Local edges of a tet (vertex pairs) and the lookup from a vertex pair to the edge.
constexpr int kTetEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
constexpr int kEdgeOfPair[4][4] = {{-1, 0, 1, 2}, {0, -1, 3, 4}, {1, 3, -1, 5}, {2, 4, 5, -1}};

// The corner hexes use these even permutations of (a,b,c,d): each starts at one corner
// and keeps the tet's orientation, so the hex [a, m_ab, f_abc, m_ac, m_ad, f_abd, g, f_acd]
// is positively oriented in VTK order.
constexpr int kCornerPermutations[4][4] = {{0, 1, 2, 3}, {1, 2, 0, 3}, {2, 0, 1, 3}, {3, 1, 0, 2}};

using Face = std::array<int, 3>;

Face sorted_face(int a, int b, int c) {
  Face f{a, b, c};
  std::sort(f.begin(), f.end());
  return f;
}


int first_vertex(uint64_t edge) { return int(edge >> 32); }
int first_vertex(const Face& face) { return face[0]; }

//! Assigns consecutive ids to equal keys, in key order: ids[slot] for each (key, slot)
//! entry. A counting sort on the smallest vertex id first leaves only the short runs
//! around one vertex to sort, much faster than sorting everything.
template <class Key>
std::vector<Key> number_unique(std::vector<std::pair<Key, int>>& entries, size_t n_points, std::vector<int>& ids) {
  std::vector<size_t> start(n_points + 1, 0);
  for (const auto& e : entries) ++start[size_t(first_vertex(e.first)) + 1];
  for (size_t i = 1; i <= n_points; ++i) start[i] += start[i - 1];
  std::vector<std::pair<Key, int>> sorted(entries.size());
  {
    std::vector<size_t> next(start.begin(), start.end() - 1);
    for (const auto& e : entries) sorted[next[size_t(first_vertex(e.first))]++] = e;
  }
  for (size_t v = 0; v < n_points; ++v)
    if (start[v + 1] - start[v] > 1) std::sort(sorted.begin() + long(start[v]), sorted.begin() + long(start[v + 1]));
  entries = {};
  std::vector<Key> unique_keys;
  ids.assign(sorted.size(), -1);
  for (size_t i = 0; i < sorted.size(); ++i) {
    if (i == 0 || !(sorted[i].first == sorted[i - 1].first)) unique_keys.push_back(sorted[i].first);
    ids[size_t(sorted[i].second)] = int(unique_keys.size()) - 1;
  }
  return unique_keys;
}

template <class Key>
int find_key(const std::vector<Key>& keys, const Key& key) {
  auto it = std::lower_bound(keys.begin(), keys.end(), key);
  return (it != keys.end() && *it == key) ? int(it - keys.begin()) : -1;
}

}  // namespace

HexMesh thex(const TetMesh& mesh) {
  const size_t n_points = mesh.points.size();
  const size_t n_tets = mesh.tets.size();
  for (size_t t = 0; t < n_tets; ++t) {
    const auto& tet = mesh.tets[t];
    for (int i = 0; i < 4; ++i) {
      if (tet[size_t(i)] < 0 || size_t(tet[size_t(i)]) >= n_points)
        throw InputError("thex: tet " + std::to_string(t) + " refers to point " + std::to_string(tet[size_t(i)]) +
                         ", outside the " + std::to_string(n_points) + " points");
      for (int j = 0; j < i; ++j)
        if (tet[size_t(i)] == tet[size_t(j)])
          throw InputError("thex: tet " + std::to_string(t) + " repeats point " + std::to_string(tet[size_t(i)]));
    }
  }
  if (!mesh.boundary_face_source.empty() && mesh.boundary_face_source.size() != mesh.boundary_faces.size())
    throw InputError("thex: boundary_face_source has " + std::to_string(mesh.boundary_face_source.size()) +
                     " entries for " + std::to_string(mesh.boundary_faces.size()) + " boundary faces");

  // Unique edges and faces, keyed by sorted vertex ids; slot = tet * 6 + local edge
  // (tet * 4 + local face, the face opposite local vertex f).
  std::vector<std::pair<uint64_t, int>> edge_entries(6 * n_tets);
  std::vector<std::pair<Face, int>> face_entries(4 * n_tets);
  for (size_t t = 0; t < n_tets; ++t) {
    const auto& v = mesh.tets[t];
    for (int e = 0; e < 6; ++e)
      edge_entries[6 * t + size_t(e)] = {undirected_edge_key(v[size_t(kTetEdges[e][0])], v[size_t(kTetEdges[e][1])]),
                                         int(6 * t) + e};
    for (int f = 0; f < 4; ++f)
      face_entries[4 * t + size_t(f)] = {sorted_face(v[size_t((f + 1) % 4)], v[size_t((f + 2) % 4)],
                                                     v[size_t((f + 3) % 4)]),
                                         int(4 * t) + f};
  }
  std::vector<int> tet_edge, tet_face;
  const std::vector<uint64_t> edges = number_unique(edge_entries, n_points, tet_edge);
  const std::vector<Face> faces = number_unique(face_entries, n_points, tet_face);

  const size_t edge_base = n_points, face_base = edge_base + edges.size(), cell_base = face_base + faces.size();
  HexMesh hex;
  hex.nodes.resize(cell_base + n_tets);
  std::copy(mesh.points.begin(), mesh.points.end(), hex.nodes.begin());
  for (size_t e = 0; e < edges.size(); ++e)
    hex.nodes[edge_base + e] = 0.5 * (mesh.points[size_t(edges[e] >> 32)] + mesh.points[size_t(edges[e] & 0xffffffffu)]);
  for (size_t f = 0; f < faces.size(); ++f)
    hex.nodes[face_base + f] =
        (mesh.points[size_t(faces[f][0])] + mesh.points[size_t(faces[f][1])] + mesh.points[size_t(faces[f][2])]) / 3.0;

  hex.hexes.resize(4 * n_tets);
  for (size_t t = 0; t < n_tets; ++t) {
    const auto& v = mesh.tets[t];
    const Vec3& p0 = mesh.points[size_t(v[0])];
    const double volume6 = (mesh.points[size_t(v[1])] - p0)
                               .cross(mesh.points[size_t(v[2])] - p0)
                               .dot(mesh.points[size_t(v[3])] - p0);
    hex.nodes[cell_base + t] = 0.25 * (p0 + mesh.points[size_t(v[1])] + mesh.points[size_t(v[2])] + mesh.points[size_t(v[3])]);
    const int cell = int(cell_base + t);
    auto mid = [&](int i, int j) { return int(edge_base) + tet_edge[6 * t + size_t(kEdgeOfPair[i][j])]; };
    // The face through three local vertices is the one opposite the fourth.
    auto centroid_without = [&](int opposite) { return int(face_base) + tet_face[4 * t + size_t(opposite)]; };
    for (int c = 0; c < 4; ++c) {
      int a = kCornerPermutations[c][0], b = kCornerPermutations[c][1], cc = kCornerPermutations[c][2],
          d = kCornerPermutations[c][3];
      if (volume6 < 0) std::swap(b, cc);  // mirrored tet: an odd permutation restores orientation
      hex.hexes[4 * t + size_t(c)] = {v[size_t(a)],       mid(a, b),          centroid_without(d), mid(a, cc),
                                      mid(a, d),          centroid_without(cc), cell,              centroid_without(b)};
    }
  }

  if (!mesh.tet_region.empty()) {
    if (mesh.tet_region.size() != n_tets)
      throw InputError("thex: tet_region has " + std::to_string(mesh.tet_region.size()) + " entries for " +
                       std::to_string(n_tets) + " tets");
    hex.region.resize(4 * n_tets);
    for (size_t t = 0; t < n_tets; ++t)
      for (size_t c = 0; c < 4; ++c) hex.region[4 * t + c] = mesh.tet_region[t];
  }
  if (!mesh.boundary_faces.empty()) {
    hex.boundary_facet.assign(hex.nodes.size(), -1);
    for (size_t i = 0; i < mesh.boundary_faces.size(); ++i) {
      const auto& bf = mesh.boundary_faces[i];
      const int source = mesh.boundary_face_source.empty() ? int(i) : mesh.boundary_face_source[i];
      const int face = find_key(faces, sorted_face(bf[0], bf[1], bf[2]));
      if (face < 0)
        throw InputError("thex: boundary face " + std::to_string(i) + " is not a face of any tet");
      hex.boundary_facet[face_base + size_t(face)] = source;
      for (int k = 0; k < 3; ++k) {
        const int a = bf[size_t(k)], b = bf[size_t((k + 1) % 3)];
        int& corner = hex.boundary_facet[size_t(a)];
        if (corner < 0) corner = source;
        int& midpoint = hex.boundary_facet[edge_base + size_t(find_key(edges, undirected_edge_key(a, b)))];
        if (midpoint < 0) midpoint = source;
      }
    }
  }
  return hex;
}

}  // namespace dthex
