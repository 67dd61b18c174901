// SPDX-License-Identifier: MIT
#include <dthex/hexes/conformity.h>

#include <dthex/hexes/boundary_overlap.h>
#include <dthex/mesh/hex_topology.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <numeric>
#include <unordered_map>

namespace dthex {
namespace {

// VTK hex faces as outward corner rings.

struct FaceUse {
  std::array<int, 4> key;  // sorted node ids
  int item;                // hex * 6 + local face
};

// Lexicographic on the key, then the item. Spelled out: std::array's operators go through
// memcmp, which dominated the whole measurement of a 272k-hex mesh.
bool face_use_less(const FaceUse& a, const FaceUse& b) {
  for (size_t k = 0; k < 4; ++k)
    if (a.key[k] != b.key[k]) return a.key[k] < b.key[k];
  return a.item < b.item;
}

bool same_face(const FaceUse& a, const FaceUse& b) {
  return a.key[0] == b.key[0] && a.key[1] == b.key[1] && a.key[2] == b.key[2] && a.key[3] == b.key[3];
}

//! Below this many hexes the face sort stays on one thread: waking threads costs more.
constexpr long kParallelHexes = 20000;

//! Sorts four ids in place (a five-comparator network: cheaper than std::sort on four).
void sort4(std::array<int, 4>& k) {
  auto order = [&](size_t i, size_t j) {
    if (k[j] < k[i]) std::swap(k[i], k[j]);
  };
  order(0, 1), order(2, 3), order(0, 2), order(1, 3), order(1, 2);
}

// Every hex face once per hex that uses it, in face_use_less order. A counting sort on the
// smallest node id first leaves only short runs (the faces around one node) to sort. The
// keys and the runs are made on all cores: the order is total (the item breaks ties), so
// the result does not depend on the thread count.
std::vector<FaceUse> sorted_face_uses(const HexMesh& mesh) {
  const long hexes = long(mesh.hexes.size());
  std::vector<FaceUse> uses(6 * size_t(hexes));
  int max_node = -1;
  bool negative = false;
#pragma omp parallel for schedule(static) reduction(max : max_node) reduction(|| : negative) if (hexes > kParallelHexes)
  for (long h = 0; h < hexes; ++h)
    for (int f = 0; f < 6; ++f) {
      auto& u = uses[6 * size_t(h) + size_t(f)];
      for (int k = 0; k < 4; ++k) u.key[size_t(k)] = mesh.hexes[size_t(h)][size_t(kHexFaces[f][k])];
      sort4(u.key);
      u.item = int(6 * h) + f;
      max_node = std::max(max_node, u.key[3]);
      negative = negative || u.key[0] < 0;
    }
  if (negative || max_node >= int(mesh.nodes.size())) {  // a broken mesh under test: plain sort, no buckets
    std::sort(uses.begin(), uses.end(), face_use_less);
    return uses;
  }
  std::vector<size_t> start(size_t(max_node) + 2, 0);
  for (const auto& u : uses) ++start[size_t(u.key[0]) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<FaceUse> sorted(uses.size());
  std::vector<size_t> next(start.begin(), start.end() - 1);
  for (const auto& u : uses) sorted[next[size_t(u.key[0])]++] = u;  // items stay ascending
  const long buckets = long(start.size()) - 1;
#pragma omp parallel for schedule(dynamic, 1024) if (hexes > kParallelHexes)
  for (long b = 0; b < buckets; ++b)
    if (start[size_t(b) + 1] - start[size_t(b)] > 1)
      std::sort(sorted.begin() + long(start[size_t(b)]), sorted.begin() + long(start[size_t(b) + 1]), face_use_less);
  return sorted;
}

//! Calls visit(first, count) for each run of equal keys.
template <class Visit>
void for_each_face(const std::vector<FaceUse>& uses, Visit visit) {
  for (size_t i = 0; i < uses.size();) {
    size_t j = i + 1;
    while (j < uses.size() && same_face(uses[j], uses[i])) ++j;
    visit(i, j - i);
    i = j;
  }
}

std::array<int, 4> face_ring(const HexMesh& mesh, int item) {
  const auto& hex = mesh.hexes[size_t(item / 6)];
  const auto& f = kHexFaces[item % 6];
  return {hex[size_t(f[0])], hex[size_t(f[1])], hex[size_t(f[2])], hex[size_t(f[3])]};
}

int find_root(std::vector<int>& parent, int x) {
  while (parent[size_t(x)] != x) x = parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
  return x;
}



// The faces used once, as outward rings in hex order, from the sorted face uses; the hex of
// each goes to `owners` when given.
std::vector<std::array<int, 4>> boundary_quads_of(const HexMesh& mesh, const std::vector<FaceUse>& uses,
                                                  std::vector<int>* owners = nullptr) {
  std::vector<int> items;
  for_each_face(uses, [&](size_t first, size_t count) {
    if (count == 1) items.push_back(uses[first].item);
  });
  std::sort(items.begin(), items.end());
  std::vector<std::array<int, 4>> quads;
  quads.reserve(items.size());
  for (int item : items) quads.push_back(face_ring(mesh, item));
  if (owners) {
    owners->clear();
    for (int item : items) owners->push_back(item / 6);
  }
  return quads;
}

//! Hexes with the same 8 nodes as an earlier one: node sets sorted, bucketed by their
//! smallest node (a counting sort, as for the faces), and compared within each short bucket.
size_t count_duplicate_hexes(const HexMesh& mesh) {
  size_t duplicates = 0;
  std::vector<size_t> start(mesh.nodes.size() + 1, 0);
  std::vector<std::array<int, 8>> node_sets = mesh.hexes;
  for (auto& h : node_sets) {
    std::sort(h.begin(), h.end());
    ++start[size_t(h[0]) + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::array<int, 8>> bucketed(node_sets.size());
  std::vector<size_t> next(start.begin(), start.end() - 1);
  for (const auto& h : node_sets) bucketed[next[size_t(h[0])]++] = h;
  for (size_t b = 0; b + 1 < start.size(); ++b) {
    const auto first = bucketed.begin() + long(start[b]), last = bucketed.begin() + long(start[b + 1]);
    if (last - first < 2) continue;
    std::sort(first, last);
    for (auto it = first + 1; it < last; ++it)
      if (*it == *(it - 1)) ++duplicates;
  }
  return duplicates;
}

//! Nodes no hex uses.
size_t count_unreferenced_nodes(const HexMesh& mesh) {
  std::vector<char> used(mesh.nodes.size(), 0);
  for (const auto& h : mesh.hexes)
    for (int v : h) used[size_t(v)] = 1;
  return size_t(std::count(used.begin(), used.end(), 0));
}

//! Nodes coinciding with an earlier one: snapped to a grid of 1e-10 of the bounding-box
//! diagonal and sorted.
size_t count_duplicate_nodes(const HexMesh& mesh) {
  if (mesh.nodes.empty()) return 0;
  Vec3 lo = mesh.nodes[0], hi = mesh.nodes[0];
  for (const auto& p : mesh.nodes) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double cell = std::max((hi - lo).norm() * 1e-10, 1e-300);
  std::vector<std::array<int64_t, 3>> snapped(mesh.nodes.size());
  for (size_t i = 0; i < mesh.nodes.size(); ++i)
    for (int k = 0; k < 3; ++k) snapped[i][size_t(k)] = int64_t(std::llround((mesh.nodes[i][k] - lo[k]) / cell));
  std::sort(snapped.begin(), snapped.end());
  size_t duplicates = 0;
  for (size_t i = 1; i < snapped.size(); ++i)
    if (snapped[i] == snapped[i - 1]) ++duplicates;
  return duplicates;
}

//! The boundary quad surface: open and misoriented edges, fans around each node (several:
//! non-manifold), and nodes hanging inside another boundary edge, into r.
void check_boundary_surface(const HexMesh& mesh, const std::vector<std::array<int, 4>>& quads, ConformityReport& r) {
  struct EdgeUse {
    uint64_t key;
    int quad, corner;  // the directed edge runs from corner to corner + 1 of quad
    bool operator<(const EdgeUse& o) const { return key < o.key; }
  };
  std::vector<EdgeUse> edges;
  edges.reserve(4 * quads.size());
  for (size_t q = 0; q < quads.size(); ++q)
    for (int c = 0; c < 4; ++c) edges.push_back({undirected_edge_key(quads[q][size_t(c)], quads[q][size_t((c + 1) % 4)]), int(q), c});
  std::sort(edges.begin(), edges.end());
  // Fans: union the corner incidences (quad * 4 + corner) that meet across a shared edge.
  std::vector<int> parent(4 * quads.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto unite = [&](int a, int b) { parent[size_t(find_root(parent, a))] = find_root(parent, b); };
  std::vector<std::pair<uint64_t, std::array<int, 2>>> boundary_edges;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i + 1;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    const int a = int(edges[i].key >> 32), b = int(edges[i].key & 0xffffffffu);
    boundary_edges.push_back({edges[i].key, {a, b}});
    if (j - i != 2) {
      ++r.open_boundary_edges;
    } else {
      const auto& e0 = edges[i];
      const auto& e1 = edges[i + 1];
      const int from0 = quads[size_t(e0.quad)][size_t(e0.corner)], from1 = quads[size_t(e1.quad)][size_t(e1.corner)];
      if (from0 == from1) ++r.misoriented_boundary_edges;
      // Corner of each quad at node a and at node b.
      for (int node : {a, b}) {
        const int c0 = quads[size_t(e0.quad)][size_t(e0.corner)] == node ? e0.corner : (e0.corner + 1) % 4;
        const int c1 = quads[size_t(e1.quad)][size_t(e1.corner)] == node ? e1.corner : (e1.corner + 1) % 4;
        unite(4 * e0.quad + c0, 4 * e1.quad + c1);
      }
    }
    i = j;
  }
  std::vector<int> first_fan(mesh.nodes.size(), -1);
  std::vector<char> counted(mesh.nodes.size(), 0);
  for (size_t q = 0; q < quads.size(); ++q)
    for (int c = 0; c < 4; ++c) {
      const size_t node = size_t(quads[q][size_t(c)]);
      const int fan = find_root(parent, int(4 * q) + c);
      if (first_fan[node] < 0) first_fan[node] = fan;
      else if (first_fan[node] != fan && !counted[node]) {
        counted[node] = 1;
        ++r.non_manifold_boundary_nodes;
      }
    }

  // Hanging nodes: boundary nodes inside a boundary edge, found through a uniform grid.
  if (!boundary_edges.empty()) {
    double total = 0;
    for (const auto& e : boundary_edges) total += (mesh.nodes[size_t(e.second[1])] - mesh.nodes[size_t(e.second[0])]).norm();
    const double cell = std::max(total / double(boundary_edges.size()), 1e-300);
    auto cell_of = [&](const Vec3& p) {
      return std::array<int64_t, 3>{int64_t(std::floor(p.x() / cell)), int64_t(std::floor(p.y() / cell)),
                                    int64_t(std::floor(p.z() / cell))};
    };
    auto hash = [](const std::array<int64_t, 3>& c) {
      return uint64_t(c[0]) * 73856093ULL ^ uint64_t(c[1]) * 19349663ULL ^ uint64_t(c[2]) * 83492791ULL;
    };
    std::unordered_map<uint64_t, std::vector<int>> grid;
    for (size_t v = 0; v < mesh.nodes.size(); ++v)
      if (first_fan[v] >= 0) grid[hash(cell_of(mesh.nodes[v]))].push_back(int(v));
    std::vector<char> hanging(mesh.nodes.size(), 0);
    for (const auto& e : boundary_edges) {
      const Vec3& a = mesh.nodes[size_t(e.second[0])];
      const Vec3& b = mesh.nodes[size_t(e.second[1])];
      const Vec3 d = b - a;
      const double len2 = d.squaredNorm();
      if (len2 <= 0) continue;
      // A node on the edge lies in a cell the edge's bounding box covers (a few cells for
      // an edge of about one cell); for a long, slanted edge whose box holds many more cells
      // than it crosses, walk it in half-cell steps and look at the 27 cells around each.
      auto test_cell = [&](int64_t x, int64_t y, int64_t z) {
        const auto it = grid.find(hash({x, y, z}));
        if (it == grid.end()) return;
        for (int v : it->second) {
          if (v == e.second[0] || v == e.second[1] || hanging[size_t(v)]) continue;
          const Vec3 p = mesh.nodes[size_t(v)] - a;
          const double t = p.dot(d) / len2;
          if (t <= 1e-9 || t >= 1 - 1e-9) continue;
          if ((p - t * d).squaredNorm() <= 1e-18 * len2) hanging[size_t(v)] = 1;
        }
      };
      const double slack = 1e-9 * std::sqrt(len2);
      const auto lo = cell_of(a.cwiseMin(b) - Vec3::Constant(slack));
      const auto hi = cell_of(a.cwiseMax(b) + Vec3::Constant(slack));
      const int steps = int(std::ceil(std::sqrt(len2) / (0.5 * cell))) + 1;
      const double box_cells = double(hi[0] - lo[0] + 1) * double(hi[1] - lo[1] + 1) * double(hi[2] - lo[2] + 1);
      if (box_cells <= 27.0 * (steps + 1)) {
        for (int64_t x = lo[0]; x <= hi[0]; ++x)
          for (int64_t y = lo[1]; y <= hi[1]; ++y)
            for (int64_t z = lo[2]; z <= hi[2]; ++z) test_cell(x, y, z);
        continue;
      }
      for (int s = 0; s <= steps; ++s) {
        const auto centre = cell_of(a + (double(s) / steps) * d);
        for (int64_t x = centre[0] - 1; x <= centre[0] + 1; ++x)
          for (int64_t y = centre[1] - 1; y <= centre[1] + 1; ++y)
            for (int64_t z = centre[2] - 1; z <= centre[2] + 1; ++z) test_cell(x, y, z);
      }
    }
    r.hanging_nodes = size_t(std::count(hanging.begin(), hanging.end(), 1));
  }

}

}  // namespace

std::vector<std::array<int, 4>> boundary_quads(const HexMesh& mesh, std::vector<int>* owners) {
  return boundary_quads_of(mesh, sorted_face_uses(mesh), owners);
}

std::vector<std::array<int, 4>> interface_quads(const HexMesh& mesh, std::vector<int>* owners,
                                                std::vector<int>* others) {
  std::vector<std::array<int, 4>> quads;
  if (owners) owners->clear();
  if (others) others->clear();
  if (mesh.region.size() != mesh.hexes.size()) return quads;
  const std::vector<FaceUse> uses = sorted_face_uses(mesh);
  std::vector<int> items;
  std::vector<std::pair<int, int>> other_of;  // (item, the hex on the other side)
  for_each_face(uses, [&](size_t first, size_t count) {
    if (count != 2) return;
    const int a = uses[first].item, b = uses[first + 1].item;
    const int ra = mesh.region[size_t(a / 6)], rb = mesh.region[size_t(b / 6)];
    if (ra != rb) items.push_back(ra < rb ? a : b);
    if (ra != rb) other_of.push_back({ra < rb ? a : b, (ra < rb ? b : a) / 6});
  });
  std::sort(items.begin(), items.end());
  std::sort(other_of.begin(), other_of.end());
  quads.reserve(items.size());
  for (int item : items) quads.push_back(face_ring(mesh, item));
  if (owners)
    for (int item : items) owners->push_back(item / 6);
  if (others)
    for (const auto& [item, hex] : other_of) others->push_back(hex);
  return quads;
}

HexMesh region_submesh(const HexMesh& mesh, int region, std::vector<int>* node_of) {
  HexMesh out;
  std::vector<int> local(mesh.nodes.size(), -1);
  for (size_t h = 0; h < mesh.hexes.size(); ++h)
    if (mesh.region.empty() || mesh.region[h] == region)
      for (int v : mesh.hexes[h]) local[size_t(v)] = 0;
  if (node_of) node_of->clear();
  for (size_t v = 0; v < mesh.nodes.size(); ++v)
    if (local[v] == 0) {
      local[v] = int(out.nodes.size());
      out.nodes.push_back(mesh.nodes[v]);
      if (!mesh.boundary_facet.empty()) out.boundary_facet.push_back(mesh.boundary_facet[v]);
      if (node_of) node_of->push_back(int(v));
    }
  for (size_t h = 0; h < mesh.hexes.size(); ++h)
    if (mesh.region.empty() || mesh.region[h] == region) {
      std::array<int, 8> hex = mesh.hexes[h];
      for (int& v : hex) v = local[size_t(v)];
      out.hexes.push_back(hex);
    }
  return out;
}

std::vector<char> boundary_nodes(const HexMesh& mesh, const std::vector<char>* known) {
  if (known && known->size() == mesh.nodes.size()) return *known;
  return boundary_nodes_of_quads(mesh, boundary_quads(mesh));
}

std::vector<char> boundary_nodes_of_quads(const HexMesh& mesh, const std::vector<std::array<int, 4>>& quads) {
  std::vector<char> on_boundary(mesh.nodes.size(), 0);
  for (size_t v = 0; v < mesh.nodes.size(); ++v) on_boundary[v] = mesh.is_boundary_node(int(v));
  for (const auto& quad : quads)
    for (int v : quad) on_boundary[size_t(v)] = 1;
  return on_boundary;
}

ConformityReport check_conformity(const HexMesh& mesh, std::vector<std::array<int, 4>>* boundary,
                                  std::vector<int>* boundary_owners) {
  ConformityReport r;
  r.hexes = mesh.hexes.size();
  r.nodes = mesh.nodes.size();
  for (const auto& hex : mesh.hexes)
    for (int v : hex)
      if (v < 0 || size_t(v) >= mesh.nodes.size())
        throw InputError("check_conformity: a hex refers to node " + std::to_string(v) + ", outside the " +
                         std::to_string(mesh.nodes.size()) + " nodes");

  const auto uses = sorted_face_uses(mesh);
  for_each_face(uses, [&](size_t, size_t count) {
    if (count == 1) ++r.boundary_faces;
    if (count > 2) ++r.overshared_faces;
  });
  std::vector<int> owners;
  const auto quads = boundary_quads_of(mesh, uses, &owners);  // the uses sorted above, not a second sort

  // The repeated hexes and nodes on one core, the boundary surface on the other: each is a
  // few sorts and scans on its own, and they write different counts.
  std::exception_ptr failure[2];
#pragma omp parallel sections num_threads(2) if (mesh.hexes.size() > size_t(kParallelHexes))
  {
#pragma omp section
    try {
      r.duplicate_hexes = count_duplicate_hexes(mesh);
      r.unreferenced_nodes = count_unreferenced_nodes(mesh);
      r.duplicate_nodes = count_duplicate_nodes(mesh);
    } catch (...) {
      failure[0] = std::current_exception();
    }
#pragma omp section
    try {
      check_boundary_surface(mesh, quads, r);
    } catch (...) {
      failure[1] = std::current_exception();
    }
  }
  for (const auto& f : failure)
    if (f) std::rethrow_exception(f);
  if (boundary) *boundary = quads;
  if (boundary_owners) *boundary_owners = owners;

  // Geometry last: boundary faces folded into the mesh's own volume.
  const BoundaryOverlapReport overlap = find_boundary_faces_inside(mesh, quads, owners);
  r.boundary_faces_inside = overlap.faces_inside;
  r.first_boundary_face_inside = overlap.first_face;
  r.first_inside_point = overlap.first_point;
  return r;
}

}  // namespace dthex
