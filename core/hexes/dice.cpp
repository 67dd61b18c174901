// SPDX-License-Identifier: MIT
#include <dthex/hexes/dice.h>

#include <dthex/mesh/hex_topology.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace dthex {
namespace {

// Parameter-cube position of each VTK hex corner.
constexpr int kCornerPosition[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                       {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};

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

bool equal(int a, int b) { return a == b; }
bool equal(const std::array<int, 3>& a, const std::array<int, 3>& b) {
  return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

//! Groups items by their smallest node (counting sort) and numbers equal keys within
//! each group; `ids[item]` receives the number. `rest[item]` is the item's key without
//! its smallest node. Linear in the items: a group holds one node's edges or faces.
template <class Rest>
size_t number_by_smallest_node(size_t n_nodes, const std::vector<int>& smallest, const std::vector<Rest>& rest,
                               std::vector<int>& ids) {
  const size_t n_items = smallest.size();
  std::vector<int> start(n_nodes + 1, 0);
  for (size_t i = 0; i < n_items; ++i) ++start[size_t(smallest[i]) + 1];
  for (size_t v = 0; v < n_nodes; ++v) start[v + 1] += start[v];
  std::vector<int> order(n_items), fill(start.begin(), start.end() - 1);
  for (size_t i = 0; i < n_items; ++i) order[size_t(fill[size_t(smallest[i])]++)] = int(i);
  fill = {};
  ids.assign(n_items, -1);
  size_t count = 0;
  std::vector<std::pair<Rest, int>> representatives;  // distinct keys of the current group and their ids
  for (size_t v = 0; v < n_nodes; ++v) {
    representatives.clear();
    for (int i = start[v]; i < start[v + 1]; ++i) {
      const size_t item = size_t(order[size_t(i)]);
      const Rest& key = rest[item];
      int id = -1;
      for (const auto& [other, other_id] : representatives)
        if (equal(other, key)) {
          id = other_id;
          break;
        }
      if (id < 0) {
        id = int(count++);
        representatives.push_back({key, id});
      }
      ids[item] = id;
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

  // Unique edges: item = hex * 12 + local edge, keyed by (smaller, larger) node.
  std::vector<int> smallest(12 * n_hexes), largest(12 * n_hexes);
  for (size_t h = 0; h < n_hexes; ++h)
    for (int e = 0; e < 12; ++e) {
      const int a = mesh.hexes[h][size_t(kHexEdges[e][0])], b = mesh.hexes[h][size_t(kHexEdges[e][1])];
      smallest[12 * h + size_t(e)] = std::min(a, b);
      largest[12 * h + size_t(e)] = std::max(a, b);
    }
  std::vector<int> hex_edge;
  const size_t n_edges = number_by_smallest_node(n_nodes, smallest, largest, hex_edge);
  largest = {};

  // Faces: item = hex * 6 + local face.
  auto face_ids = [&](size_t item) {
    const auto& hx = mesh.hexes[item / 6];
    const auto& f = kHexFaces[item % 6];
    return std::array<int, 4>{hx[size_t(f[0])], hx[size_t(f[1])], hx[size_t(f[2])], hx[size_t(f[3])]};
  };
  // Unique faces, keyed by their sorted 4 node ids (smallest, then the other three).
  smallest.assign(6 * n_hexes, 0);
  std::vector<std::array<int, 3>> others(6 * n_hexes);
  for (size_t item = 0; item < 6 * n_hexes; ++item) {
    auto ids = face_ids(item);
    std::sort(ids.begin(), ids.end());
    smallest[item] = ids[0];
    others[item] = {ids[1], ids[2], ids[3]};
  }
  std::vector<int> hex_face;
  const size_t n_faces = number_by_smallest_node(n_nodes, smallest, others, hex_face);
  smallest = {};
  others = {};

  // Unique edges and faces are numbered again in order of first use by the hexes, so
  // each is created (and its nodes placed) by the first hex that has it, nodes are
  // written in sequence, and nodes of neighbouring hexes get nearby indices.
  std::vector<int> edge_number(n_edges, -1), face_number(n_faces, -1), face_uses(n_faces, 0);
  for (int face : hex_face) ++face_uses[size_t(face)];
  // A face between two regions (HexMesh::region) is an interface: its nodes carry a boundary
  // facet as a boundary face's do, so its use count is taken as 1 (face_uses is read only there).
  if (!mesh.region.empty()) {
    if (mesh.region.size() != n_hexes)
      throw InputError("dice: region has " + std::to_string(mesh.region.size()) + " entries for " +
                       std::to_string(n_hexes) + " hexes");
    std::vector<int> first_region(n_faces, -1);
    for (size_t item = 0; item < hex_face.size(); ++item) {
      int& first = first_region[size_t(hex_face[item])];
      const int r = mesh.region[item / 6];
      if (first < 0) first = r;
      else if (first != r) face_uses[size_t(hex_face[item])] = 1;
    }
  }
  int next_edge = 0, next_face = 0;

  const size_t m = size_t(n - 1);
  const size_t edge_base = n_nodes, face_base = edge_base + m * n_edges, cell_base = face_base + m * m * n_faces;
  HexMesh out;
  out.nodes.resize(cell_base + m * m * m * n_hexes);
  std::copy(mesh.nodes.begin(), mesh.nodes.end(), out.nodes.begin());
  const double step = 1.0 / n;

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
      int& number = edge_number[size_t(hex_edge[12 * h + size_t(e)])];
      if (number < 0) {  // first use: its nodes run from the smaller to the larger end node
        number = next_edge++;
        const Vec3& pa = mesh.nodes[size_t(hx[size_t(a)])];
        const Vec3& pb = mesh.nodes[size_t(hx[size_t(b)])];
        for (size_t s = 1; s < size_t(n); ++s)
          out.nodes[edge_base + size_t(number) * m + s - 1] = (1 - s * step) * pa + s * step * pb;
      }
      const size_t edge = size_t(number);
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
      int& number = face_number[size_t(hex_face[6 * h + size_t(f)])];
      if (number < 0) {  // first use: node (s, t) of the frame q0..q3 is s along q0->q1, t along q0->q3
        number = next_face++;
        const Vec3& q0 = mesh.nodes[size_t(ring[size_t(order[0])])];
        const Vec3& q1 = mesh.nodes[size_t(ring[size_t(order[1])])];
        const Vec3& q2 = mesh.nodes[size_t(ring[size_t(order[2])])];
        const Vec3& q3 = mesh.nodes[size_t(ring[size_t(order[3])])];
        for (size_t s = 1; s < size_t(n); ++s)
          for (size_t t = 1; t < size_t(n); ++t) {
            const double u = s * step, v = t * step;
            out.nodes[face_base + size_t(number) * m * m + (s - 1) * m + (t - 1)] =
                (1 - u) * (1 - v) * q0 + u * (1 - v) * q1 + u * v * q2 + (1 - u) * v * q3;
          }
      }
      const size_t face = size_t(number);
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

  if (!mesh.region.empty()) {
    out.region.resize(out.hexes.size());
    const size_t per_hex = size_t(n) * size_t(n) * size_t(n);
    for (size_t h = 0; h < out.hexes.size(); ++h) out.region[h] = mesh.region[h / per_hex];
  }
  if (track_boundary) {
    out.boundary_facet.assign(out.nodes.size(), -1);
    std::copy(mesh.boundary_facet.begin(), mesh.boundary_facet.end(), out.boundary_facet.begin());
    for (size_t item = 0; item < hex_face.size(); ++item) {
      if (face_uses[size_t(hex_face[item])] != 1) continue;
      const size_t face = size_t(face_number[size_t(hex_face[item])]);
      const auto ring = face_ids(item);
      int newest = -1;
      for (int c : ring)
        if (mesh.boundary_facet[size_t(c)] >= 0 && c > newest) newest = c;
      if (newest < 0) continue;
      const int facet = mesh.boundary_facet[size_t(newest)];
      for (size_t i = 0; i < m * m; ++i) out.boundary_facet[face_base + face * m * m + i] = facet;
      const auto& lf = kHexFaces[item % 6];
      for (int k = 0; k < 4; ++k) {
        const size_t edge = size_t(edge_number[size_t(hex_edge[12 * (item / 6) + size_t(local_edge(lf[k], lf[(k + 1) % 4]))])]);
        for (size_t s = 0; s < m; ++s)
          if (out.boundary_facet[edge_base + edge * m + s] < 0) out.boundary_facet[edge_base + edge * m + s] = facet;
      }
    }
  }
  return out;
}

}  // namespace dthex
