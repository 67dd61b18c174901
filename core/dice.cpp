// SPDX-License-Identifier: MIT
#include "core/dice.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace dthex {
namespace {

// Parameter-cube position of each VTK hex corner.
constexpr int kCornerPosition[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                       {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
constexpr int kHexEdges[12][2] = {{0, 1}, {1, 2}, {3, 2}, {0, 3}, {4, 5}, {5, 6},
                                  {7, 6}, {4, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
// Faces as corner rings, outward oriented (VTK's hex faces).
constexpr int kHexFaces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                 {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

int local_edge(int a, int b) {
  for (int e = 0; e < 12; ++e)
    if ((kHexEdges[e][0] == a && kHexEdges[e][1] == b) || (kHexEdges[e][0] == b && kHexEdges[e][1] == a)) return e;
  return -1;
}

//! Rotates/reflects a ring of 4 so it starts at its smallest id and continues towards
//! the smaller of that id's two neighbours. Returns the ring positions in that order.
std::array<int, 4> canonical_ring_order(const std::array<int, 4>& ids) {
  int m = 0;
  for (int i = 1; i < 4; ++i)
    if (ids[size_t(i)] < ids[size_t(m)]) m = i;
  const int next = (m + 1) % 4, prev = (m + 3) % 4;
  const int step = ids[size_t(next)] <= ids[size_t(prev)] ? 1 : 3;
  return {m, (m + step) % 4, (m + 2 * step) % 4, (m + 3 * step) % 4};
}

//! Groups items by their smallest node (counting sort) and numbers equal keys within
//! each group; `ids[item]` receives the number. Linear in the items.
template <class KeyOf>
size_t number_by_smallest_node(size_t n_items, size_t n_nodes, const std::vector<int>& smallest, KeyOf key_of,
                               std::vector<int>& ids) {
  std::vector<int> start(n_nodes + 1, 0);
  for (size_t i = 0; i < n_items; ++i) ++start[size_t(smallest[i]) + 1];
  for (size_t v = 0; v < n_nodes; ++v) start[v + 1] += start[v];
  std::vector<int> order(n_items), fill(start.begin(), start.end() - 1);
  for (size_t i = 0; i < n_items; ++i) order[size_t(fill[size_t(smallest[i])]++)] = int(i);
  ids.assign(n_items, -1);
  size_t count = 0;
  std::vector<int> representatives;  // one item per distinct key of the current group
  for (size_t v = 0; v < n_nodes; ++v) {
    representatives.clear();
    for (int i = start[v]; i < start[v + 1]; ++i) {
      const size_t item = size_t(order[size_t(i)]);
      const auto key = key_of(item);
      for (int other : representatives)
        if (key_of(size_t(other)) == key) {
          ids[item] = ids[size_t(other)];
          break;
        }
      if (ids[item] < 0) {
        ids[item] = int(count++);
        representatives.push_back(int(item));
      }
    }
  }
  return count;
}

}  // namespace

HexMesh dice(const HexMesh& mesh, int n) {
  if (n < 1) throw std::invalid_argument("dice: the number of divisions must be at least 1, got " + std::to_string(n));
  const size_t n_nodes = mesh.nodes.size(), n_hexes = mesh.hexes.size();
  for (size_t h = 0; h < n_hexes; ++h)
    for (int c : mesh.hexes[h])
      if (c < 0 || size_t(c) >= n_nodes)
        throw InputError("dice: hex " + std::to_string(h) + " refers to node " + std::to_string(c) + ", outside the " +
                         std::to_string(n_nodes) + " nodes");
  const bool track_boundary = !mesh.boundary_facet.empty();
  if (track_boundary && mesh.boundary_facet.size() != n_nodes)
    throw InputError("dice: boundary_facet has " + std::to_string(mesh.boundary_facet.size()) + " entries for " +
                     std::to_string(n_nodes) + " nodes");

  // Unique edges: item = hex * 12 + local edge.
  std::vector<int> smallest(12 * n_hexes);
  for (size_t h = 0; h < n_hexes; ++h)
    for (int e = 0; e < 12; ++e)
      smallest[12 * h + size_t(e)] = std::min(mesh.hexes[h][size_t(kHexEdges[e][0])], mesh.hexes[h][size_t(kHexEdges[e][1])]);
  std::vector<int> hex_edge;
  const size_t n_edges = number_by_smallest_node(
      12 * n_hexes, n_nodes, smallest,
      [&](size_t item) {
        const auto& hx = mesh.hexes[item / 12];
        const auto& e = kHexEdges[item % 12];
        return std::max(hx[size_t(e[0])], hx[size_t(e[1])]);
      },
      hex_edge);

  // Unique faces: item = hex * 6 + local face, keyed by the sorted 4 ids.
  auto face_ids = [&](size_t item) {
    const auto& hx = mesh.hexes[item / 6];
    const auto& f = kHexFaces[item % 6];
    return std::array<int, 4>{hx[size_t(f[0])], hx[size_t(f[1])], hx[size_t(f[2])], hx[size_t(f[3])]};
  };
  auto sorted_face_ids = [&](size_t item) {
    auto ids = face_ids(item);
    std::sort(ids.begin(), ids.end());
    return ids;
  };
  smallest.assign(6 * n_hexes, 0);
  for (size_t item = 0; item < 6 * n_hexes; ++item) smallest[item] = sorted_face_ids(item)[0];
  std::vector<int> hex_face;
  const size_t n_faces = number_by_smallest_node(6 * n_hexes, n_nodes, smallest, sorted_face_ids, hex_face);
  smallest = {};

  // Per unique edge/face: the item that created it (defines node positions) and how many hexes use a face.
  std::vector<int> edge_owner(n_edges, -1), face_owner(n_faces, -1), face_uses(n_faces, 0);
  for (size_t item = 0; item < hex_edge.size(); ++item)
    if (edge_owner[size_t(hex_edge[item])] < 0) edge_owner[size_t(hex_edge[item])] = int(item);
  for (size_t item = 0; item < hex_face.size(); ++item) {
    if (face_owner[size_t(hex_face[item])] < 0) face_owner[size_t(hex_face[item])] = int(item);
    ++face_uses[size_t(hex_face[item])];
  }

  const size_t m = size_t(n - 1);
  const size_t edge_base = n_nodes, face_base = edge_base + m * n_edges, cell_base = face_base + m * m * n_faces;
  HexMesh out;
  out.nodes.resize(cell_base + m * m * m * n_hexes);
  std::copy(mesh.nodes.begin(), mesh.nodes.end(), out.nodes.begin());
  const double step = 1.0 / n;

  // Edge nodes run from the smaller to the larger end node.
  for (size_t e = 0; e < n_edges; ++e) {
    const auto& hx = mesh.hexes[size_t(edge_owner[e]) / 12];
    const auto& le = kHexEdges[size_t(edge_owner[e]) % 12];
    int a = hx[size_t(le[0])], b = hx[size_t(le[1])];
    if (a > b) std::swap(a, b);
    for (size_t s = 1; s < size_t(n); ++s)
      out.nodes[edge_base + e * m + s - 1] = (1 - s * step) * mesh.nodes[size_t(a)] + s * step * mesh.nodes[size_t(b)];
  }
  // Face node (s, t) of the canonical frame q0 q1 q2 q3: s along q0->q1, t along q0->q3.
  for (size_t f = 0; f < n_faces; ++f) {
    const auto ring = face_ids(size_t(face_owner[f]));
    const auto order = canonical_ring_order(ring);
    const Vec3& q0 = mesh.nodes[size_t(ring[size_t(order[0])])];
    const Vec3& q1 = mesh.nodes[size_t(ring[size_t(order[1])])];
    const Vec3& q2 = mesh.nodes[size_t(ring[size_t(order[2])])];
    const Vec3& q3 = mesh.nodes[size_t(ring[size_t(order[3])])];
    for (size_t s = 1; s < size_t(n); ++s)
      for (size_t t = 1; t < size_t(n); ++t) {
        const double u = s * step, v = t * step;
        out.nodes[face_base + f * m * m + (s - 1) * m + (t - 1)] =
            (1 - u) * (1 - v) * q0 + u * (1 - v) * q1 + u * v * q2 + (1 - u) * v * q3;
      }
  }

  // Per hex: the (n+1)^3 grid of node ids, then its n^3 sub-hexes.
  const size_t g = size_t(n) + 1;
  std::vector<int> grid(g * g * g);
  auto at = [&](size_t i, size_t j, size_t k) -> int& { return grid[(k * g + j) * g + i]; };
  out.hexes.resize(n_hexes * size_t(n) * size_t(n) * size_t(n));
  size_t next_hex = 0;
  for (size_t h = 0; h < n_hexes; ++h) {
    const auto& hx = mesh.hexes[h];
    auto corner = [&](int c, int axis) { return size_t(kCornerPosition[c][axis]) * size_t(n); };
    for (int c = 0; c < 8; ++c) at(corner(c, 0), corner(c, 1), corner(c, 2)) = hx[size_t(c)];
    for (int e = 0; e < 12; ++e) {
      int a = kHexEdges[e][0], b = kHexEdges[e][1];
      if (hx[size_t(a)] > hx[size_t(b)]) std::swap(a, b);
      const size_t edge = size_t(hex_edge[12 * h + size_t(e)]);
      for (size_t s = 1; s < size_t(n); ++s) {
        size_t p[3];
        for (int axis = 0; axis < 3; ++axis)
          p[axis] = size_t(int(corner(a, axis)) + int(s) * (kCornerPosition[b][axis] - kCornerPosition[a][axis]));
        at(p[0], p[1], p[2]) = int(edge_base + edge * m + s - 1);
      }
    }
    for (int f = 0; f < 6; ++f) {
      const auto ring = face_ids(6 * h + size_t(f));
      const auto order = canonical_ring_order(ring);
      const int c0 = kHexFaces[f][order[0]], c1 = kHexFaces[f][order[1]], c3 = kHexFaces[f][order[3]];
      const size_t face = size_t(hex_face[6 * h + size_t(f)]);
      for (size_t s = 1; s < size_t(n); ++s)
        for (size_t t = 1; t < size_t(n); ++t) {
          size_t p[3];
          for (int axis = 0; axis < 3; ++axis)
            p[axis] = size_t(int(corner(c0, axis)) + int(s) * (kCornerPosition[c1][axis] - kCornerPosition[c0][axis]) +
                             int(t) * (kCornerPosition[c3][axis] - kCornerPosition[c0][axis]));
          at(p[0], p[1], p[2]) = int(face_base + face * m * m + (s - 1) * m + (t - 1));
        }
    }
    std::array<Vec3, 8> x;
    for (size_t c = 0; c < 8; ++c) x[c] = mesh.nodes[size_t(hx[c])];
    size_t next_cell = cell_base + h * m * m * m;
    for (size_t k = 1; k < size_t(n); ++k)
      for (size_t j = 1; j < size_t(n); ++j)
        for (size_t i = 1; i < size_t(n); ++i) {
          const double u = i * step, v = j * step, w = k * step;
          out.nodes[next_cell] = (1 - w) * ((1 - v) * ((1 - u) * x[0] + u * x[1]) + v * ((1 - u) * x[3] + u * x[2])) +
                                 w * ((1 - v) * ((1 - u) * x[4] + u * x[5]) + v * ((1 - u) * x[7] + u * x[6]));
          at(i, j, k) = int(next_cell++);
        }
    for (size_t k = 0; k < size_t(n); ++k)
      for (size_t j = 0; j < size_t(n); ++j)
        for (size_t i = 0; i < size_t(n); ++i)
          out.hexes[next_hex++] = {at(i, j, k),         at(i + 1, j, k),         at(i + 1, j + 1, k),
                                   at(i, j + 1, k),     at(i, j, k + 1),         at(i + 1, j, k + 1),
                                   at(i + 1, j + 1, k + 1), at(i, j + 1, k + 1)};
  }

  if (track_boundary) {
    out.boundary_facet.assign(out.nodes.size(), -1);
    std::copy(mesh.boundary_facet.begin(), mesh.boundary_facet.end(), out.boundary_facet.begin());
    for (size_t item = 0; item < hex_face.size(); ++item) {
      const size_t face = size_t(hex_face[item]);
      if (face_uses[face] != 1) continue;
      const auto ring = face_ids(item);
      int newest = -1;
      for (int c : ring)
        if (mesh.boundary_facet[size_t(c)] >= 0 && c > newest) newest = c;
      if (newest < 0) continue;
      const int facet = mesh.boundary_facet[size_t(newest)];
      for (size_t i = 0; i < m * m; ++i) out.boundary_facet[face_base + face * m * m + i] = facet;
      const auto& lf = kHexFaces[item % 6];
      for (int k = 0; k < 4; ++k) {
        const size_t edge = size_t(hex_edge[12 * (item / 6) + size_t(local_edge(lf[k], lf[(k + 1) % 4]))]);
        for (size_t s = 0; s < m; ++s)
          if (out.boundary_facet[edge_base + edge * m + s] < 0) out.boundary_facet[edge_base + edge * m + s] = facet;
      }
    }
  }
  return out;
}

}  // namespace dthex
